"""The land group (scripts/systole_bench/land.py): its cases (the afterload x1 run is the preload
run at 10 mmHg), the numbers it reads from a run (the filling state when the reported beat
starts), and the Frank-Starling and ESPVR verdicts of its section."""

import subprocess

import h5py
import numpy as np
import pytest

from systole_bench import land
from conftest import write_results_file


def test_the_cases_of_both_ventricles():
    for full in (False, True):
        cases = land.land_cases(full)
        assert sorted(cases) == sorted(
            [f"land_preload_{label}_{edp}" for label in ("with", "without")
             for edp in (6, 10, 14)] + ["land_afterload_0.7", "land_afterload_1.4"])
        for name, changes in cases.items():
            assert ("Active tension/Land/beta0" in changes) == ("without" in name)
            # The coarse ventricle is run with the full one's tension and mitral valve.
            assert ("Circulation/Mitral valve resistance" in changes) == (not full)
        assert cases["land_afterload_1.4"]["Circulation/Atrial pressure"] == "10"
    assert land.land_afterload_name(1.0) == "land_preload_with_10"
    assert land.land_afterload_name(0.7) == "land_afterload_0.7"


def test_a_run_gives_the_filling_state_when_its_last_beat_starts(tmp_path):
    # Two beats of 800 ms; the LV pressure rises linearly from 2 to 6 mmHg over the last
    # 100 ms of beat 0 and the mean tension falls from 1.0 to 0.5 kPa (steps at 750 and
    # 810 ms: the values at 800 ms are interpolated).
    timeseries = {"time": [0.0, 700.0, 750.0, 810.0, 900.0, 1600.0],
                  "beat": [0, 0, 0, 1, 1, 1],
                  "lv_volume_mL": [100.0, 110.0, 115.0, 121.0, 100.0, 118.0],
                  "lv_pressure_mmHg": [0.0, 2.0, 4.0, 6.4, 90.0, 5.0],
                  "mean_active_tension": [50.0, 1.0, 0.75, 0.45, 60.0, 0.5]}
    summary = {"beat": [0.0, 1.0], "start_time": [0.0, 800.0], "end_time": [800.0, 1600.0],
               "lv_EDV_mL": [110.0, 121.0], "lv_SV_mL": [40.0, 50.0]}
    # Beat 1: the aortic valve (1) opens at 70 mmHg and closes at 95 mmHg.
    events = {"time": [850.0, 1100.0], "beat": [1.0, 1.0], "valve": [1.0, 1.0],
              "opens": [1.0, 0.0], "lv_pressure_mmHg": [70.0, 95.0]}
    folder = tmp_path / "results" / "run"
    folder.mkdir(parents=True)
    path = write_results_file(folder / "results.h5", timeseries, summary=summary,
                              events=events)
    with h5py.File(path, "a") as f:
        stats = f.create_group("statistics")
        for key, value in (("wall_time", 20.0), ("n_dofs", 801), ("beats", 2), ("periodic", 0),
                           ("newton_iterations", 40), ("steps", 10), ("ep_nodes", 1685)):
            stats.create_dataset(key, data=value)
    ok = subprocess.CompletedProcess([], 0, "", "")
    row = land.land_row("run", tmp_path, ok, False, 2)
    assert row["summary"]["lv_SV_mL"] == 50.0
    assert row["start_pressure"] == pytest.approx(6.0)
    assert row["start_tension"] == pytest.approx(0.5)
    assert (row["opening_pressure"], row["esp"]) == (70.0, 95.0)
    # The first beat: it starts at 0 ms.
    first = land.land_row("run", tmp_path, ok, False, 2, beat=0)
    assert first["summary"]["lv_SV_mL"] == 40.0
    assert first["start_pressure"] == 0.0 and first["esp"] != first["esp"]  # no closure: NaN


def fake_row(sv: float, edv: float) -> dict:
    # Every end-systolic point on the line P = 4 (V - 40 mL).
    esp = 4.0 * (edv - sv - 40.0)
    return {"ok": True, "busy": False, "ranks": 2, "dofs": 801, "ep_nodes": 1685,
            "wall": 200.0, "beats": 2, "newton": 500, "steps": 100, "esp": esp,
            "start_pressure": 6.0, "start_tension": 0.3,
            "summary": {"lv_EDP_mmHg": 6.0, "lv_EDV_mL": edv, "lv_SV_mL": sv,
                        "lv_ESV_mL": edv - sv, "lv_peak_pressure_mmHg": esp + 10}}


def rows(with_sv, without_sv) -> dict:
    result = {}
    for label, svs in (("with", with_sv), ("without", without_sv)):
        for edp, sv in zip((6, 10, 14), svs):
            result[f"land_preload_{label}_{edp}"] = fake_row(sv, 120.0 + edp)
    # x1 is the preload run at 10 mmHg with the length dependence.
    for factor, esv in ((0.7, 60.0), (1.4, 90.0)):
        result[f"land_afterload_{factor:g}"] = fake_row(130.0 - esv, 130.0)
    return result


def test_the_section_says_whether_the_length_dependence_adds_stroke_volume():
    text = land.land_text(rows((50.0, 55.0, 60.0), (50.0, 53.0, 56.0)), full=False)
    assert "+10.00 mL with the length dependence (monotonic), +6.00 mL without it (more " \
           "with it)" in text
    assert "P_es = 4.000 (V_es - 40.0 mL) mmHg" in text and "R^2 = 1.0000" in text
    text = land.land_text(rows((50.0, 49.0, 55.0), (50.0, 55.0, 60.0)), full=False)
    assert "+5.00 mL with the length dependence (NOT monotonic), +10.00 mL without it (NOT " \
           "more with it)" in text
