"""Tests of systole_post.plot and scripts/plot_results.py (outputs go to tmp_path)."""

import subprocess
import sys

import numpy as np
import pytest

from circulation_files import closed_loop_file, heartbeat_file, windkessel_file
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


def test_closed_loop_panels_gather_each_quantity(tmp_path):
    results = read_results(closed_loop_file(tmp_path / "closed_loop.h5"))
    figure = make_figure(results)
    titles = [ax.get_title() for ax in figure.axes]
    # In the order of their first column; the blood volume alone (another scale).
    assert titles == ["beat [-]", "volume [mL]", "pressure [mmHg]", "flow [mL/s]", "phase [-]",
                      "total_blood_volume_mL [mL]"]
    volume, pressure, flow, phase = figure.axes[1:5]
    assert [line.get_label() for line in volume.get_lines()] == [
        "la_volume", "lv_volume", "ra_volume", "rv_volume"]
    assert len(pressure.get_lines()) == 8  # 4 vessel and 4 chamber pressures
    assert [t.get_text() for t in pressure.get_legend().get_texts()][:2] == [
        "systemic_arterial_pressure", "systemic_venous_pressure"]
    assert len(flow.get_lines()) == 8  # 4 vessel and 4 valve flows
    assert [line.get_label() for line in phase.get_lines()] == ["lv", "rv"]
    assert phase.get_lines()[0].get_drawstyle() == "steps-post"
    assert np.array_equal(volume.get_lines()[3].get_ydata(), results.timeseries["rv_volume_mL"])


def test_heartbeat_panels_skip_the_aliases_of_the_cavity(tmp_path):
    figure = make_figure(read_results(heartbeat_file(tmp_path / "heartbeat.h5")))
    panels = {ax.get_title(): [line.get_label() for line in ax.get_lines()]
              for ax in figure.axes}
    assert panels["volume [mL]"] == ["lv_volume", "lv_mechanics_volume"]
    assert panels["pressure [mmHg]"] == ["arterial_pressure", "lv_pressure", "atrial_pressure",
                                         "aortic_root_pressure"]
    assert panels["lv_phase [-]"] == ["lv_phase"]  # one column: a panel of its own
    assert "phase [-]" not in panels and "pressure_mmHg [mmHg]" not in panels
    assert "newton_iterations [-]" in panels and "step [-]" not in panels


def test_windkessel_selected_columns_stay_one_panel_each(tmp_path):
    results = read_results(windkessel_file(tmp_path / "windkessel.h5"))
    figure = make_figure(results, ["lv_pressure_mmHg", "arterial_pressure_mmHg"])
    assert [ax.get_title() for ax in figure.axes] == [
        "lv_pressure_mmHg [mmHg]", "arterial_pressure_mmHg [mmHg]"]
