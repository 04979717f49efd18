"""Tests of systole_post.plot and scripts/plot_results.py (outputs go to tmp_path)."""

import subprocess
import sys

import pytest

from conftest import SCRIPTS_DIR
from systole_post.plot import make_figure, plot_timeseries
from systole_post.results import read_results

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_plot_writes_png(make_results, three_steps, tmp_path):
    out = plot_timeseries(read_results(make_results(three_steps)), tmp_path / "plot.png")
    assert out == tmp_path / "plot.png"
    data = out.read_bytes()
    assert data[:8] == PNG_MAGIC
    assert len(data) > 1000


def test_default_subplots_skip_time_and_step_and_show_units(make_results, three_steps):
    figure = make_figure(read_results(make_results(three_steps)))
    titles = [ax.get_title() for ax in figure.axes]  # HDF5 link order: alphabetical here
    assert titles == ["phase [-]", "pressure [kPa]", "volume [mm^3]"]
    assert figure.axes[-1].get_xlabel() == "time [ms]"


def test_selected_columns_only(make_results, three_steps):
    figure = make_figure(read_results(make_results(three_steps)), ["pressure"])
    assert [ax.get_title() for ax in figure.axes] == ["pressure [kPa]"]
    line = figure.axes[0].get_lines()[0]
    assert list(line.get_xdata()) == three_steps["time"]
    assert list(line.get_ydata()) == three_steps["pressure"]


def test_unknown_column_raises(make_results, three_steps, tmp_path):
    with pytest.raises(ValueError, match="no time-series column"):
        plot_timeseries(make_results(three_steps), tmp_path / "p.png", ["flux"])
    assert not (tmp_path / "p.png").exists()


def test_script_default_output_next_to_results(make_results, three_steps, tmp_path):
    results = make_results(three_steps)
    run_dir = tmp_path / "elsewhere"
    run_dir.mkdir()
    # Run from another directory without PYTHONPATH: the script must find systole_post itself.
    done = subprocess.run([sys.executable, str(SCRIPTS_DIR / "plot_results.py"), str(results)],
                          cwd=run_dir, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    expected = results.parent / "timeseries.png"
    assert done.stdout.strip() == str(expected)
    assert expected.read_bytes()[:8] == PNG_MAGIC
    assert list(run_dir.iterdir()) == []


def test_script_output_option_and_columns(make_results, three_steps, tmp_path):
    results = make_results(three_steps)
    out = tmp_path / "volume.png"
    done = subprocess.run([sys.executable, str(SCRIPTS_DIR / "plot_results.py"), str(results),
                           "-o", str(out), "--columns", "volume"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == str(out)
    assert out.read_bytes()[:8] == PNG_MAGIC
    assert not (tmp_path / "timeseries.png").exists()


def test_script_reports_missing_file(tmp_path):
    done = subprocess.run([sys.executable, str(SCRIPTS_DIR / "plot_results.py"),
                           str(tmp_path / "none.h5")], capture_output=True, text=True)
    assert done.returncode == 1
    assert "no such results file" in done.stderr
