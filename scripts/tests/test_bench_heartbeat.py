"""The heartbeat table of scripts/systole_bench/heartbeat.py on the summary of the new heartbeat
(columns of the first ventricle, lv_EDV_mL, ...) and of an old-style one (EDV_mL, ...)."""

from systole_bench.heartbeat import heartbeat_column, heartbeat_section
from circulation_files import closed_loop_summary, windkessel_summary

OLD_STYLE = {"beat": [0.0], "EDV_mL": [130.0], "EF": [50.0], "aortic_diastolic_mmHg": [75.0],
             "periodicity": [float("nan")]}


def test_columns_of_the_first_ventricle_and_the_aortic_pressures():
    windkessel = windkessel_summary()
    assert heartbeat_column(windkessel, "EDV_mL") == "lv_EDV_mL"
    assert heartbeat_column(windkessel, "dpdt_max") == "lv_dpdt_max"
    assert heartbeat_column(windkessel, "aortic_systolic_mmHg") == "aortic_root_pressure_max_mmHg"
    assert heartbeat_column(windkessel, "periodicity") == "periodicity"
    assert heartbeat_column(windkessel, "activation_time_90") is None
    assert (heartbeat_column(closed_loop_summary(), "aortic_diastolic_mmHg") ==
            "systemic_arterial_pressure_min_mmHg")
    assert heartbeat_column(OLD_STYLE, "EDV_mL") == "EDV_mL"
    assert heartbeat_column(OLD_STYLE, "aortic_diastolic_mmHg") == "aortic_diastolic_mmHg"


def row(summary):
    return {"ok": True, "ranks": 1, "dofs": 100, "beats": len(summary["beat"]),
            "periodic": True, "wall": 10.0, "steps_per_beat": 80.0, "solves_per_step": 2.0,
            "newton_per_step": 1.5, "memory": 100.0, "summary": summary}


def test_the_table_checks_the_new_columns_against_the_bounds():
    lines = heartbeat_section([row(windkessel_summary())]).splitlines()
    by_name = {line.split(" | ")[0].lstrip("| "): line for line in lines if line.startswith("| ")}
    # EDV 120.5 and 121.25 mL, within 100 ... 160; the aortic root's minimum 69.5, 70.5.
    assert by_name["lv_EDV_mL"] == "| lv_EDV_mL | 120.5 | 121.2 | 100 ... 160: yes |"
    assert by_name["aortic_root_pressure_min_mmHg"].endswith("| 60 ... 90: yes |")
    assert by_name["lv_ejection_duration"].endswith("| 200 ... 350: yes |")
    assert by_name["periodicity"].endswith("| < 0.01: **no** |")  # 0.0125
    assert "EDV_mL" not in by_name


def test_the_table_still_reads_an_old_style_summary():
    lines = heartbeat_section([row(OLD_STYLE)]).splitlines()
    assert "| EDV_mL | 130 | 100 ... 160: yes |" in lines
    assert "| aortic_diastolic_mmHg | 75 | 60 ... 90: yes |" in lines
