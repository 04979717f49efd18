"""The land group (scripts/systole_bench/land.py): its sweeps run as the studies of the land
recipes (here with a fake runner, tests/fake_land_systole.py), resume, and the Frank-Starling
and ESPVR verdicts of the section built from the studies' tables."""

import sys
from pathlib import Path

import pytest

from systole_bench import land

FAKE = Path(__file__).resolve().parent / "fake_land_systole.py"


def fake_command(tmp_path):
    return [sys.executable, str(FAKE), "{prm}", str(tmp_path / "launches.txt")]


def launches(tmp_path):
    path = tmp_path / "launches.txt"
    return path.read_text().split() if path.exists() else []


@pytest.mark.parametrize("full", (False, True), ids=("coarse", "full"))
def test_the_sweeps_run_as_studies_and_give_the_section(tmp_path, full):
    studies = tmp_path / "studies"
    rows = land.run_sweeps(tmp_path / "no-build", full, jobs=2, studies=studies,
                           command=fake_command(tmp_path))
    assert sorted(p.name for p in studies.iterdir()) == sorted(
        land.recipe(sweep, full).stem for sweep in land.SWEEPS)
    assert len(launches(tmp_path)) == 9
    assert sorted(rows["preload_with"]) == sorted(rows["preload_without"]) == [6.0, 10.0, 14.0]
    assert sorted(rows["afterload"]) == [0.7, 1.0, 1.4]
    # The filling state when the last beat starts (interpolated at 800 ms), that beat's
    # aortic closure.
    r = rows["preload_with"][6.0]
    assert r["start_lv_pressure_mmHg"] == pytest.approx(5.5)
    assert r["start_mean_active_tension"] == pytest.approx(0.3)
    assert rows["afterload"][1.4]["valve1_closes_lv_pressure_mmHg"] == pytest.approx(172.0)

    text = land.land_text(rows, full, jobs=2)
    assert "| 6 | 5.50 | 6.00 | 126.0 | 50.00 | 0.300 | 5.50 | 6.00 | 126.0 | 50.00 | 0.300 |" \
        in text
    assert "+10.00 mL with the length dependence (monotonic), +6.00 mL without it (more " \
           "with it)" in text
    assert "| x1.4 | 83.00 | 172.00 | 130.0 | 47.00 | 182.0 |" in text
    assert "P_es = 4.000 (V_es - 40.0 mL) mmHg" in text and "R^2 = 1.0000" in text
    assert "801 mechanics DOFs, 1685 EP nodes, 1 rank each, 2 runs at a time" in text
    assert "16.0 to 24.0 s (4.00 Newton iterations per step)" in text


def test_a_stopped_group_reruns_only_the_unfinished_cases(tmp_path):
    studies = tmp_path / "studies"
    land.run_sweeps(tmp_path, False, jobs=2, studies=studies, command=fake_command(tmp_path))
    assert len(launches(tmp_path)) == 9
    # Everything finished: nothing runs again.
    land.run_sweeps(tmp_path, False, jobs=2, studies=studies, command=fake_command(tmp_path))
    assert len(launches(tmp_path)) == 9
    # A case interrupted (no status) is the only one rerun.
    (studies / "land_afterload_coarse" / "cases" / "case_0002" / "status.json").unlink()
    rows = land.run_sweeps(tmp_path, False, jobs=2, studies=studies,
                           command=fake_command(tmp_path))
    assert launches(tmp_path)[9:] == ["case_0002"]
    assert all(r["status"] == "done" for sweep in rows.values() for r in sweep.values())


def row(sv: float, edv: float, status: str = "done") -> dict:
    # Every end-systolic point on the line P = 4 (V - 40 mL).
    return {"status": status, "error": "" if status == "done" else "Newton failed",
            "statistics_n_dofs": 801.0, "statistics_ep_nodes": 1685.0,
            "statistics_wall_time": 200.0, "statistics_beats": 2.0,
            "statistics_newton_iterations": 500.0, "statistics_steps": 100.0,
            "start_lv_pressure_mmHg": 6.0, "start_mean_active_tension": 0.3,
            "lv_EDP_mmHg": 6.0, "lv_EDV_mL": edv, "lv_SV_mL": sv, "lv_ESV_mL": edv - sv,
            "lv_peak_pressure_mmHg": 4.0 * (edv - sv - 40.0) + 10,
            "valve1_closes_lv_pressure_mmHg": 4.0 * (edv - sv - 40.0)}


def rows(with_sv, without_sv, failed_afterload=False) -> dict:
    result = {"afterload": {}}
    for label, svs in (("with", with_sv), ("without", without_sv)):
        result[f"preload_{label}"] = {edp: row(sv, 120.0 + edp)
                                      for edp, sv in zip((6.0, 10.0, 14.0), svs)}
    for factor, esv in ((0.7, 60.0), (1.0, 75.0), (1.4, 90.0)):
        result["afterload"][factor] = row(130.0 - esv, 130.0)
    if failed_afterload:
        result["afterload"][1.4] = row(40.0, 130.0, status="failed")
    return result


def test_the_section_says_whether_the_length_dependence_adds_stroke_volume():
    text = land.land_text(rows((50.0, 55.0, 60.0), (50.0, 53.0, 56.0)), full=False)
    assert "+10.00 mL with the length dependence (monotonic), +6.00 mL without it (more " \
           "with it)" in text
    assert "P_es = 4.000 (V_es - 40.0 mL) mmHg" in text and "R^2 = 1.0000" in text
    assert "801 mechanics DOFs, 1685 EP nodes, 2 ranks;" in text
    text = land.land_text(rows((50.0, 49.0, 55.0), (50.0, 55.0, 60.0)), full=False)
    assert "+5.00 mL with the length dependence (NOT monotonic), +10.00 mL without it (NOT " \
           "more with it)" in text


def test_a_failed_case_is_a_row_that_says_why_and_leaves_out_the_espvr():
    text = land.land_text(rows((50.0, 55.0, 60.0), (50.0, 53.0, 56.0), failed_afterload=True),
                          full=True)
    assert "| x1.4 | failed: Newton failed |" in text
    assert "ESPVR" not in text.split("| x1.4 |")[1]
