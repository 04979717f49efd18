"""Tests of scripts/pv_loop.py on small synthetic results files (outputs go to tmp_path).

The first tests use an old-style heartbeat file (pressure_mmHg, volume_mL, phase, the
unprefixed summary); test_pv_loop_cavities.py has the files of the 0D models.
"""

import subprocess
import sys

import numpy as np
import pytest

from conftest import SCRIPTS_DIR
from pv_loop import beat_rows, format_summary, make_loop_figure, make_traces_figure, write_pv_plots
from systole_post.results import read_results

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
SCRIPT = SCRIPTS_DIR / "pv_loop.py"

# One idealised beat: (end time in the beat [ms], phase during the step, volume [mL] and
# pressure [mmHg] at that time).
CORNERS = [(0, 0, 50, 5), (300, 0, 120, 10), (350, 1, 120, 80), (450, 2, 90, 115),
           (600, 2, 50, 90), (700, 3, 50, 5), (800, 0, 55, 6)]


def cycle_timeseries(n_beats=2, steps_per_segment=5):
    """Rows of ``n_beats`` beats, steps ending exactly at the phase changes and beat ends."""
    rows = {name: [] for name in ("time", "beat", "phase", "pressure_mmHg", "volume_mL",
                                  "flow", "aortic_pressure_mmHg")}

    def add(time, beat, phase, volume, pressure, flow):
        rows["time"].append(time)
        rows["beat"].append(beat)
        rows["phase"].append(phase)
        rows["volume_mL"].append(volume)
        rows["pressure_mmHg"].append(pressure)
        rows["flow"].append(flow)
        rows["aortic_pressure_mmHg"].append(max(pressure, 80.0) if phase == 2 else 80.0)

    add(0.0, 0, 0, CORNERS[0][2], CORNERS[0][3], 0.0)
    for beat in range(n_beats):
        for (t0, _, v0, p0), (t1, phase, v1, p1) in zip(CORNERS[:-1], CORNERS[1:]):
            flow = -(v1 - v0) / (t1 - t0) * 1000.0
            for s in np.linspace(0, 1, steps_per_segment + 1)[1:]:
                add(beat * 800.0 + t0 + s * (t1 - t0), beat, phase,
                    v0 + s * (v1 - v0), p0 + s * (p1 - p0), flow)
    return rows


SUMMARY = {"beat": [0, 1], "EDV_mL": [120.0, 120.0], "ESV_mL": [50.0, 50.0],
           "EF": [58.333333, 58.333333], "periodicity": [float("nan"), 0.0004]}


@pytest.fixture
def cycle_file(make_results):
    return make_results(cycle_timeseries(), summary=SUMMARY)


def test_beat_rows_close_the_curves_at_the_boundaries():
    rows = beat_rows(np.array([0, 0, 0, 1, 1, 2]))
    assert [list(r) for r in rows.values()] == [[0, 1, 2], [2, 3, 4], [4, 5]]


def test_loop_has_one_curve_per_beat_coloured_by_phase(cycle_file):
    figure = make_loop_figure(read_results(cycle_file))
    ax = figure.axes[0]
    assert [c.get_label() for c in ax.collections] == ["beat 0", "beat 1"]
    assert ax.get_title() == "cavity pressure-volume loop (beats 0-1, earlier beats lighter)"
    first = ax.collections[0]
    n_segments = 6 * 5
    assert len(first.get_segments()) == n_segments
    # Segment colours follow the phase of the row that ends the segment: 4 phases seen.
    colours = {tuple(np.round(c, 3)) for c in first.get_colors()}
    assert len(colours) == 4
    assert ax.get_xlabel() == "cavity volume [mL]"
    assert ax.get_ylabel() == "cavity pressure [mmHg]"
    assert len(figure.axes) == 1
    assert [t.get_text() for t in ax.get_legend().get_texts()][0] == "filling"
    # The second beat starts from the last row of the first (the curve is closed).
    assert np.allclose(ax.collections[1].get_segments()[0][0], [55.0, 6.0])


def test_traces_have_pressure_volume_and_flow_panels(cycle_file):
    figure = make_traces_figure(read_results(cycle_file))
    labels = [ax.get_ylabel() for ax in figure.axes]
    assert labels == ["pressure [mmHg]", "volume [mL]", "flow [mL/s]"]
    assert [t.get_text() for t in figure.axes[0].get_legend().get_texts()] == [
        "cavity", "aortic root"]
    assert [line.get_label() for line in figure.axes[2].get_lines()] == ["outflow - inflow"]
    assert figure.axes[-1].get_xlabel() == "time [ms]"
    assert figure.axes[0].get_title().startswith("cardiac cycle (shading: filling, ")


def test_summary_table_is_aligned_with_one_row_per_beat(cycle_file):
    text = format_summary(read_results(cycle_file))
    lines = text.splitlines()
    # The cavity's table (EDV, ESV, EF), then the other columns (periodicity).
    assert len(lines) == 8
    assert lines[0] == "cavity, per beat:"
    assert len({len(line) for line in lines[1:4]}) == 1  # aligned
    assert lines[1].split() == ["beat", "[-]", "EDV", "[mL]", "ESV", "[mL]", "EF", "[%]"]
    assert lines[2].split() == ["0", "120", "50", "58.333"]
    assert lines[3].split()[0] == "1"  # the beat number, as an integer
    assert lines[4] == "per beat:"
    assert lines[5].split() == ["beat", "[-]", "periodicity", "[-]"]
    assert lines[6].split() == ["0", "-"]  # NaN periodicity shown as -
    assert lines[7].split() == ["1", "0.0004"]


def test_script_writes_pngs_and_prints_paths_and_table(cycle_file, tmp_path):
    prefix = tmp_path / "out" / "lv"
    prefix.parent.mkdir()
    done = subprocess.run([sys.executable, str(SCRIPT), str(cycle_file), "-o", str(prefix)],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[:2] == [str(tmp_path / "out" / "lv_loop.png"),
                         str(tmp_path / "out" / "lv_traces.png")]
    for name in ("lv_loop.png", "lv_traces.png"):
        data = (tmp_path / "out" / name).read_bytes()
        assert data[:8] == PNG_MAGIC
        assert len(data) > 5000
    # The terminal summary: the cavity's table, then where the other column is.
    assert lines[2] == "cavity, per beat:"
    assert lines[2:6] == format_summary(read_results(cycle_file)).splitlines()[:4]
    assert " ".join(lines[6:]).startswith("1 more per-beat column (periodicity")
    # --full: every column, as in the report.
    done = subprocess.run([sys.executable, str(SCRIPT), str(cycle_file), "-o", str(prefix),
                           "--full"], cwd=tmp_path, capture_output=True, text=True)
    assert done.stdout.splitlines()[2:] == format_summary(read_results(cycle_file)).splitlines()


def test_script_default_prefix_next_to_results(make_results, tmp_path):
    results = make_results(cycle_timeseries(n_beats=1))  # no /summary
    run_dir = tmp_path / "elsewhere"
    run_dir.mkdir()
    done = subprocess.run([sys.executable, str(SCRIPT), str(results)], cwd=run_dir,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (results.parent / "pv_loop.png").read_bytes()[:8] == PNG_MAGIC
    assert (results.parent / "pv_traces.png").read_bytes()[:8] == PNG_MAGIC
    assert "no /summary table" in done.stdout
    assert list(run_dir.iterdir()) == []


def test_minimal_columns_are_enough(make_results, tmp_path):
    rows = cycle_timeseries(n_beats=1)
    minimal = {name: rows[name] for name in ("time", "pressure_mmHg", "volume_mL")}
    written = write_pv_plots(make_results(minimal), tmp_path / "min")
    assert [p.name for p in written] == ["min_loop.png", "min_traces.png"]
    assert all(p.read_bytes()[:8] == PNG_MAGIC for p in written)


def test_script_reports_missing_columns_and_files(make_results, three_steps, tmp_path):
    done = subprocess.run([sys.executable, str(SCRIPT), str(make_results(three_steps))],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert "no cavity (columns c_pressure_mmHg and c_volume_mL" in done.stderr
    done = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path / "none.h5")],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert "no such results file" in done.stderr
