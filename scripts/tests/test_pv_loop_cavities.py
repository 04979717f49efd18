"""Tests of scripts/pv_loop.py and systole_post.cavities on the files of the 0D models:
a 3-element Windkessel (one cavity), the closed loop (two ventricles, two atria) and a
heartbeat (a 3D cavity with its aliases). Outputs go to tmp_path."""

import re
import subprocess
import sys

import h5py
import numpy as np
import pytest
from matplotlib.colors import to_rgba

from circulation_files import (CLOSED_LOOP_PRESSURES, LV_SUMMARY, RV_PRESSURE_FACTOR,
                               RV_SUMMARY, RV_VOLUME_SHIFT, WINDKESSEL_PRESSURES,
                               closed_loop_file, heartbeat_file, windkessel_file)
from conftest import SCRIPTS_DIR
from pv_loop import (NO_PHASE_COLOUR, PHASES, format_summary,  # noqa: E402
                     format_terminal_summary, make_loop_figure, make_traces_figure)
from systole_post.cavities import Cavity, find_cavities, summary_groups, ventricles
from systole_post.results import read_results

SCRIPT = SCRIPTS_DIR / "pv_loop.py"
PHASE_NAMES = [name for name, _ in PHASES.values()]


@pytest.fixture
def windkessel(tmp_path):
    return read_results(windkessel_file(tmp_path / "windkessel.h5"))


@pytest.fixture
def closed_loop(tmp_path):
    return read_results(closed_loop_file(tmp_path / "closed_loop.h5"))


@pytest.fixture
def heartbeat(tmp_path):
    return read_results(heartbeat_file(tmp_path / "heartbeat.h5"))


def legend(ax):
    return [text.get_text() for text in ax.get_legend().get_texts()]


def tables(text):
    """The per-beat tables of format_summary: title -> list of {heading: cell} per row."""
    found, title, headers = {}, None, None
    for line in text.splitlines():
        if line.endswith(":"):
            title, headers = line, None
            found[title] = []
        elif headers is None:
            headers = re.split(r"\s{2,}", line.strip())
        else:
            found[title].append(dict(zip(headers, re.split(r"\s{2,}", line.strip()))))
    return found


def test_cavities_are_found_ventricles_first():
    closed = ["time", "la_volume_mL", "lv_volume_mL", "ra_volume_mL", "rv_volume_mL",
              "systemic_arterial_pressure_mmHg", "la_pressure_mmHg", "lv_pressure_mmHg",
              "ra_pressure_mmHg", "rv_pressure_mmHg", "lv_phase", "rv_phase",
              "total_blood_volume_mL"]
    assert [c.name for c in find_cavities(closed)] == ["lv", "rv", "la", "ra"]
    assert find_cavities(closed)[2] == Cavity("la", "la_pressure_mmHg", "la_volume_mL")
    # The heartbeat's aliases and its mesh volume are no cavities of their own.
    beat = ["lv_volume_mL", "lv_pressure_mmHg", "lv_phase", "lv_mechanics_volume_mL",
            "pressure_mmHg", "volume_mL", "phase"]
    assert find_cavities(beat) == [Cavity("lv", "lv_pressure_mmHg", "lv_volume_mL",
                                          "lv_phase", "lv_mechanics_volume_mL")]
    assert find_cavities(["time", "pressure_mmHg", "volume_mL"]) == [
        Cavity("", "pressure_mmHg", "volume_mL")]
    assert find_cavities(["time", "pressure", "volume"]) == []


def test_summary_groups_split_ventricles_pressures_and_the_rest(closed_loop):
    groups = summary_groups(closed_loop.summary)
    assert list(groups.ventricles) == ["lv", "rv"] == ventricles(closed_loop.summary)
    assert [h for _, h, _ in groups.ventricles["lv"]] == [
        "EDV", "ESV", "SV", "EF", "EDP", "peak", "stroke work", "dp/dt max", "dp/dt min",
        "filling", "IVC", "ejection", "IVR"]
    assert groups.pressures == list(CLOSED_LOOP_PRESSURES)
    assert groups.others == ["start_time", "end_time", "total_blood_volume_mL",
                             "total_blood_volume_drift", "periodicity", "samples"]


def test_windkessel_has_one_loop_coloured_by_phase(windkessel):
    figure = make_loop_figure(windkessel)
    assert len(figure.axes) == 1
    ax = figure.axes[0]
    assert ax.get_title() == "LV pressure-volume loop (beats 0-1, earlier beats lighter)"
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("LV volume [mL]", "LV pressure [mmHg]")
    assert [c.get_label() for c in ax.collections] == ["beat 0", "beat 1"]
    assert legend(ax) == PHASE_NAMES
    # Rows every 10 ms: 80 segments a beat, the second starting at the end of the first.
    first, second = (c.get_segments() for c in ax.collections)
    assert len(first) == len(second) == 80
    assert np.allclose(second[0][0], first[-1][1])
    ts = windkessel.timeseries
    assert np.allclose([s[1] for s in first], np.column_stack(
        (ts["lv_volume_mL"][1:81], ts["lv_pressure_mmHg"][1:81])))
    expected = [to_rgba(PHASES[int(code)][1])[:3] for code in ts["lv_phase"][1:81]]
    assert np.allclose(ax.collections[0].get_colors()[:, :3], expected)
    assert len({tuple(c) for c in expected}) == 4


def test_windkessel_traces_show_its_pressures_volume_and_valve_flows(windkessel):
    figure = make_traces_figure(windkessel)
    assert [ax.get_ylabel() for ax in figure.axes] == [
        "pressure [mmHg]", "volume [mL]", "flow [mL/s]"]
    assert legend(figure.axes[0]) == ["LV", "aortic root", "arteries (Windkessel)",
                                      "atrium (Windkessel)"]
    assert [line.get_label() for line in figure.axes[1].get_lines()] == ["LV"]
    assert legend(figure.axes[2]) == ["mitral", "aortic"]
    lv = figure.axes[0].get_lines()[0]
    assert np.array_equal(lv.get_ydata(), windkessel.timeseries["lv_pressure_mmHg"])
    assert figure.axes[0].get_title().startswith("cardiac cycle (shading: LV filling, ")


def test_windkessel_summary_has_the_lv_table_and_the_pressures(windkessel):
    text = format_summary(windkessel)
    found = tables(text)
    assert list(found) == ["LV, per beat:", "pressures [mmHg] in beat 1:", "per beat:"]
    lv = found["LV, per beat:"]
    assert [row["beat [-]"] for row in lv] == ["0", "1"]
    assert lv[1]["EDV [mL]"] == "121.25" and lv[1]["ESV [mL]"] == "51.25"
    assert lv[0]["EF [%]"] == "58.09" and lv[0]["EDP [mmHg]"] == "10.25"
    assert lv[0]["stroke work [mmHg mL]"] == "5912"
    assert lv[0]["dp/dt max [mmHg/s]"] == "1400" and lv[1]["dp/dt min [mmHg/s]"] == "-1710"
    assert [lv[0][h] for h in ("filling [ms]", "IVC [ms]", "ejection [ms]", "IVR [ms]")] == [
        "400", "50", "250", "100"]
    pressures = {row["pressure"]: row for row in found["pressures [mmHg] in beat 1:"]}
    assert list(pressures) == list(WINDKESSEL_PRESSURES)
    assert [pressures["aortic_root_pressure"][s] for s in ("max", "min", "mean")] == [
        "112.5", "70.5", "86.25"]  # the last beat's, not the first's (1 mmHg lower)
    rest = found["per beat:"]
    assert [row["periodicity [-]"] for row in rest] == ["-", "0.0125"]
    assert rest[1]["start_time [ms]"] == "800"
    # Every LV column is in the LV table, under a short name (lv_pressure is a pressure).
    assert re.findall(r"\blv_\w+", text) == ["lv_pressure"]


def test_closed_loop_has_a_loop_per_cavity(closed_loop):
    figure = make_loop_figure(closed_loop)
    titles = [ax.get_title().split(" ")[0] for ax in figure.axes]
    assert titles == ["LV", "RV", "LA", "RA"]
    lv, rv, la, ra = figure.axes
    assert legend(lv) == legend(rv) == PHASE_NAMES
    assert la.get_legend() is None and ra.get_legend() is None
    assert all(len(ax.collections) == 2 for ax in figure.axes)  # two beats each
    # The ventricles by phase (4 colours), the atria in one colour.
    assert len({tuple(c) for c in rv.collections[1].get_colors()}) == 4
    for beat in la.collections:  # the faded first beat differs in alpha only
        assert {tuple(np.round(c[:3], 6)) for c in beat.get_colors()} == {
            tuple(np.round(to_rgba(NO_PHASE_COLOUR)[:3], 6))}
    # The RV loop is the LV loop shifted by 40 mL and scaled by 0.2 in pressure.
    v_lv, p_lv = np.array(lv.collections[1].get_segments())[:, 1].T
    v_rv, p_rv = np.array(rv.collections[1].get_segments())[:, 1].T
    assert np.allclose(v_rv, v_lv + RV_VOLUME_SHIFT)
    assert np.allclose(p_rv, RV_PRESSURE_FACTOR * p_lv)
    assert rv.get_xlabel() == "RV volume [mL]" and ra.get_ylabel() == "RA pressure [mmHg]"


def test_closed_loop_traces_split_the_left_and_the_right_heart(closed_loop):
    figure = make_traces_figure(closed_loop)
    assert [ax.get_ylabel() for ax in figure.axes] == [
        "left heart pressure [mmHg]", "right heart pressure [mmHg]", "volume [mL]",
        "flow [mL/s]"]
    left, right, volume, flow = figure.axes
    assert legend(left) == ["LV", "LA", "systemic arteries", "pulmonary veins"]
    assert legend(right) == ["RV", "RA", "pulmonary arteries", "systemic veins"]
    assert legend(volume) == ["LV", "RV", "LA", "RA"]
    assert legend(flow) == ["mitral", "aortic", "tricuspid", "pulmonary"]
    # A cavity has one colour in every panel.
    colour = {ax: {line.get_label(): line.get_color() for line in ax.get_lines()}
              for ax in figure.axes}
    assert colour[left]["LV"] == colour[volume]["LV"]
    assert colour[right]["RV"] == colour[volume]["RV"]
    assert len(set(colour[volume].values())) == 4
    rv = right.get_lines()[0]
    assert np.array_equal(rv.get_ydata(), closed_loop.timeseries["rv_pressure_mmHg"])


def test_closed_loop_summary_has_a_table_per_ventricle(closed_loop):
    found = tables(format_summary(closed_loop))
    assert list(found) == ["LV, per beat:", "RV, per beat:", "pressures [mmHg] in beat 1:",
                           "per beat:"]
    for title, values in (("LV, per beat:", LV_SUMMARY), ("RV, per beat:", RV_SUMMARY)):
        rows = found[title]
        assert [float(rows[b]["EDV [mL]"]) for b in (0, 1)] == values["EDV_mL"]
        assert [float(rows[b]["peak [mmHg]"]) for b in (0, 1)] == values["peak_pressure_mmHg"]
        assert [float(rows[b]["IVC [ms]"]) for b in (0, 1)] == values[
            "isovolumetric_contraction_duration"]
    pressures = {row["pressure"]: row for row in found["pressures [mmHg] in beat 1:"]}
    assert list(pressures) == list(CLOSED_LOOP_PRESSURES)
    assert [float(pressures["pulmonary_arterial_pressure"][s]) for s in ("max", "min", "mean")
            ] == list(CLOSED_LOOP_PRESSURES["pulmonary_arterial_pressure"])


def test_heartbeat_uses_the_prefixed_cavity_and_shows_the_mesh_volume(heartbeat):
    loops = make_loop_figure(heartbeat)
    assert [ax.get_title().split(" ")[0] for ax in loops.axes] == ["LV"]  # no alias loop
    traces = make_traces_figure(heartbeat)
    pressure, volume, _ = traces.axes
    assert legend(pressure)[0] == "LV" and "cavity" not in legend(pressure)
    lines = volume.get_lines()
    assert [line.get_label() for line in lines] == ["LV", "LV (3D mesh)"]
    assert lines[0].get_color() == lines[1].get_color()
    assert (lines[0].get_linestyle(), lines[1].get_linestyle()) == ("-", "--")
    assert np.array_equal(lines[1].get_ydata(), heartbeat.timeseries["lv_mechanics_volume_mL"])
    found = tables(format_summary(heartbeat))
    rest = found["per beat:"]
    assert [row["newton_iterations [-]"] for row in rest] == ["240", "236"]
    assert rest[0]["mechanics_seconds [-]"] == "12.5"


def test_script_on_a_closed_loop_file(tmp_path):
    results = closed_loop_file(tmp_path / "closed_loop.h5")
    done = subprocess.run([sys.executable, str(SCRIPT), str(results), "-o",
                           str(tmp_path / "cl")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[:2] == [str(tmp_path / "cl_loop.png"), str(tmp_path / "cl_traces.png")]
    assert "LV, per beat:" in lines and "RV, per beat:" in lines
    for name in ("cl_loop.png", "cl_traces.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("fixture", ["windkessel", "closed_loop", "heartbeat"])
def test_terminal_summary_fits_100_columns_and_keeps_the_haemodynamics(fixture, request):
    results = request.getfixturevalue(fixture)
    with h5py.File(results.path, "a") as h5file:  # the AHA segments make the wide tables
        for segment in range(1, 18):
            data = h5file.create_dataset(f"summary/aha_{segment:02d}_activation_time",
                                         data=np.full(2, 10.0 * segment))
            data.attrs["unit"] = "ms"
    results = read_results(results.path)
    assert max(len(line) for line in format_summary(results).splitlines()) > 100
    text = format_terminal_summary(results, report="results/run/report.html")
    assert max(len(line) for line in text.splitlines()) <= 100
    found = tables(text.split("pressures [mmHg]")[0])
    # Every ventricle column of the wide table is in one of the split tables, per beat.
    wide = tables(format_summary(results))
    for title, rows in wide.items():
        if title == "per beat:" or not title.endswith("per beat:"):
            continue
        parts = [rs for t, rs in found.items() if t.startswith(title[:-1])]
        assert len(parts) >= 2  # split into column groups
        assert [{k: v for part in parts for k, v in part[i].items()}
                for i in range(len(rows))] == rows
    assert "17 of the AHA segments" in text and "results/run/report.html" in text
    conservation = "conservation check" in text
    assert conservation == (fixture == "closed_loop")
