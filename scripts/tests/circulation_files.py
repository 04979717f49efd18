"""Synthetic results files of Problem = circulation and Problem = heartbeat for the tests.

The columns are those the C++ code writes (src/simulation/circulation_run.h, the
heartbeat), the values idealised: each ventricle runs a piecewise-linear PV loop through
CORNERS (scaled for the right ventricle), a row every 10 ms, beats of 800 ms; the summary
values are made up, distinct, so that a test can find each one in the output.
"""

import numpy as np

from conftest import write_results_file

PERIOD = 800.0
ROW_INTERVAL = 10.0

#: One idealised LV beat: (time in the beat [ms], phase during the segment that ends
#: there, volume [mL], pressure [mmHg]).
CORNERS = [(0, 0, 50, 5), (300, 0, 120, 10), (350, 1, 120, 80), (450, 2, 90, 115),
           (600, 2, 50, 90), (700, 3, 50, 5), (800, 0, 55, 6)]

#: The right ventricle: the LV loop shifted by 40 mL, pressures divided by 5.
RV_VOLUME_SHIFT, RV_PRESSURE_FACTOR = 40.0, 0.2


def rows(n_beats):
    """Row times and their beat numbers (a beat's end is its last row)."""
    time = np.arange(0.0, n_beats * PERIOD + 0.5 * ROW_INTERVAL, ROW_INTERVAL)
    beat = np.maximum(np.ceil(time / PERIOD) - 1, 0)
    return time, beat


def loop(time, beat):
    """Phase code, volume [mL] and pressure [mmHg] of the LV loop at each row."""
    t = time - beat * PERIOD
    times = [c[0] for c in CORNERS]
    phase = np.array([CORNERS[k][1] for k in np.searchsorted(times, t, side="left")])
    volume = np.interp(t, times, [c[2] for c in CORNERS])
    pressure = np.interp(t, times, [c[3] for c in CORNERS])
    return phase.astype(float), volume, pressure


def _ventricle_summary(prefix, values):
    """The /summary columns of one ventricle, each beat's value ``values[key] + beat``."""
    keys = ["EDV_mL", "ESV_mL", "SV_mL", "EF", "EDP_mmHg", "peak_pressure_mmHg",
            "stroke_work_mmHg_mL", "dpdt_max", "dpdt_min", "filling_duration",
            "isovolumetric_contraction_duration", "ejection_duration",
            "isovolumetric_relaxation_duration"]
    return {f"{prefix}_{key}": values[key] for key in keys}


#: Per-beat summary values of the LV and the RV (two beats).
LV_SUMMARY = {"EDV_mL": [120.5, 121.25], "ESV_mL": [50.5, 51.25], "SV_mL": [70.0, 70.0],
              "EF": [58.09, 57.73], "EDP_mmHg": [10.25, 10.5],
              "peak_pressure_mmHg": [115.5, 116.5], "stroke_work_mmHg_mL": [5912.0, 5954.0],
              "dpdt_max": [1400.0, 1410.0], "dpdt_min": [-1700.0, -1710.0],
              "filling_duration": [400.0, 401.0],
              "isovolumetric_contraction_duration": [50.0, 49.0],
              "ejection_duration": [250.0, 251.0],
              "isovolumetric_relaxation_duration": [100.0, 99.0]}
RV_SUMMARY = {"EDV_mL": [160.5, 161.25], "ESV_mL": [90.5, 91.25], "SV_mL": [70.0, 70.0],
              "EF": [43.61, 43.41], "EDP_mmHg": [2.05, 2.1],
              "peak_pressure_mmHg": [23.1, 23.3], "stroke_work_mmHg_mL": [1182.0, 1190.0],
              "dpdt_max": [280.0, 282.0], "dpdt_min": [-340.0, -342.0],
              "filling_duration": [390.0, 391.0],
              "isovolumetric_contraction_duration": [60.0, 59.0],
              "ejection_duration": [240.0, 241.0],
              "isovolumetric_relaxation_duration": [110.0, 109.0]}


def _pressure_summary(pressures):
    """name -> (max, min, mean) of the last beat (the first beat 1 mmHg lower)."""
    columns = {}
    for name, (high, low, mean) in pressures.items():
        for statistic, value in (("max", high), ("min", low), ("mean", mean)):
            columns[f"{name}_{statistic}_mmHg"] = [value - 1.0, value]
    return columns


def _run_summary():
    return {"total_blood_volume_mL": [1500.0, 1500.0],
            "total_blood_volume_drift": [1e-15, 2e-15],
            "periodicity": [float("nan"), 0.0125], "samples": [81.0, 81.0]}


#: Last-beat (max, min, mean) of the Windkessel's pressures in /summary.
WINDKESSEL_PRESSURES = {"arterial_pressure": (98.5, 70.25, 85.125),
                        "lv_pressure": (115.5, 5.0, 45.75),
                        "atrial_pressure": (10.0, 10.0, 10.0),
                        "aortic_root_pressure": (112.5, 70.5, 86.25)}
#: The same for the closed loop.
CLOSED_LOOP_PRESSURES = {"systemic_arterial_pressure": (124.5, 82.5, 104.5),
                         "systemic_venous_pressure": (35.9, 35.4, 35.7),
                         "pulmonary_arterial_pressure": (22.0, 19.2, 20.6),
                         "pulmonary_venous_pressure": (17.6, 14.8, 16.2),
                         "la_pressure": (18.4, 12.9, 16.0), "lv_pressure": (126.0, 9.6, 65.7),
                         "ra_pressure": (7.0, 4.1, 5.7), "rv_pressure": (26.1, 3.6, 12.9)}


def windkessel_timeseries(n_beats=2):
    """The /timeseries of the 3-element Windkessel (states lv_volume, arterial_pressure)."""
    time, beat = rows(n_beats)
    phase, volume, pressure = loop(time, beat)
    arterial = 70.0 + 0.25 * np.maximum(pressure - 70.0, 0.0)
    ejecting = phase == 2
    return {"time": time, "beat": beat, "lv_volume_mL": volume,
            "arterial_pressure_mmHg": arterial, "lv_pressure_mmHg": pressure,
            "atrial_pressure_mmHg": np.full_like(time, 10.0),
            "aortic_root_pressure_mmHg": np.where(ejecting, pressure, arterial),
            "mitral_valve_flow_mL_per_s": np.where(phase == 0, 300.0, 0.0),
            "aortic_valve_flow_mL_per_s": np.where(ejecting, 350.0, 0.0),
            "lv_phase": phase, "total_blood_volume_mL": volume + 1.5 * arterial}


def windkessel_summary():
    return {"beat": [0.0, 1.0], "start_time": [0.0, 800.0], "end_time": [800.0, 1600.0],
            **_ventricle_summary("lv", LV_SUMMARY), **_pressure_summary(WINDKESSEL_PRESSURES),
            **_run_summary()}


def events(n_beats, cavities):
    """/events: the valve closures and openings of the LV corners (valves 0 mitral, 1
    aortic), with every cavity's volume and pressure there."""
    times, valves, opens = [], [], []
    for b in range(n_beats):
        for t, valve, is_opening in ((300, 0, 0), (350, 1, 1), (600, 1, 0), (700, 0, 1)):
            times.append(b * PERIOD + t)
            valves.append(valve)
            opens.append(is_opening)
    time = np.array(times, dtype=float)
    beat = np.floor(time / PERIOD)
    _, volume, pressure = loop(time, beat)
    columns = {"time": time, "beat": beat, "valve": valves, "opens": opens}
    for c in cavities:
        columns[f"{c}_volume_mL"] = volume
        columns[f"{c}_pressure_mmHg"] = pressure
    return columns


def windkessel_file(path, n_beats=2):
    """A Problem = circulation file of the 3-element Windkessel."""
    return write_results_file(path, windkessel_timeseries(n_beats), summary=windkessel_summary(),
                              events=events(n_beats, ["lv"]), track_order=True)


def closed_loop_timeseries(n_beats=2):
    """The /timeseries of the closed loop (src/circulation/closed_loop.cc): four chambers,
    four vessel pressures, four vessel flows, the chamber pressures, four valve flows."""
    time, beat = rows(n_beats)
    phase, volume, pressure = loop(time, beat)
    # The RV runs the LV's phases (simpler to check than a real delay).
    atrium_volume = 70.0 + 10.0 * np.sin(2 * np.pi * time / PERIOD)
    atrium_pressure = 12.0 + 3.0 * np.cos(2 * np.pi * time / PERIOD)
    columns = {"time": time, "beat": beat, "la_volume_mL": atrium_volume,
               "lv_volume_mL": volume, "ra_volume_mL": atrium_volume - 10.0,
               "rv_volume_mL": volume + RV_VOLUME_SHIFT}
    for name, level in (("systemic_arterial", 95.0), ("systemic_venous", 35.5),
                        ("pulmonary_arterial", 20.5), ("pulmonary_venous", 16.0)):
        columns[f"{name}_pressure_mmHg"] = np.full_like(time, level)
    for name in ("systemic_arterial", "systemic_venous", "pulmonary_arterial",
                 "pulmonary_venous"):
        columns[f"{name}_flow_mL_per_s"] = np.full_like(time, 100.0)
    columns.update({"la_pressure_mmHg": atrium_pressure, "lv_pressure_mmHg": pressure,
                    "ra_pressure_mmHg": atrium_pressure - 7.0,
                    "rv_pressure_mmHg": RV_PRESSURE_FACTOR * pressure})
    for name, open_phase in (("mitral", 0), ("aortic", 2), ("tricuspid", 0), ("pulmonary", 2)):
        columns[f"{name}_valve_flow_mL_per_s"] = np.where(phase == open_phase, 300.0, 0.0)
    columns.update({"lv_phase": phase, "rv_phase": phase,
                    "total_blood_volume_mL": np.full_like(time, 1500.0)})
    return columns


def closed_loop_summary():
    return {"beat": [0.0, 1.0], "start_time": [0.0, 800.0], "end_time": [800.0, 1600.0],
            **_ventricle_summary("lv", LV_SUMMARY), **_ventricle_summary("rv", RV_SUMMARY),
            **_pressure_summary(CLOSED_LOOP_PRESSURES), **_run_summary()}


def closed_loop_file(path, n_beats=2):
    """A Problem = circulation file of the closed loop (two ventricles, two atria)."""
    return write_results_file(path, closed_loop_timeseries(n_beats),
                              summary=closed_loop_summary(),
                              events=events(n_beats, ["lv", "rv"]), track_order=True)


def heartbeat_file(path, n_beats=2):
    """A Problem = heartbeat file: the Windkessel's columns, the 3D cavity's mesh volume, the
    unprefixed aliases of that cavity, the step counters; per beat the solver counts."""
    ts = windkessel_timeseries(n_beats)
    n = len(ts["time"])
    columns = {"step": np.arange(n, dtype=float), "time": ts["time"], "beat": ts["beat"],
               "time_step": np.full(n, ROW_INTERVAL), "bdf_order": np.full(n, 2.0)}
    columns.update({k: v for k, v in ts.items() if k not in columns})
    columns.update({"lv_mechanics_volume_mL": ts["lv_volume_mL"] + 0.01,
                    "pressure_mmHg": ts["lv_pressure_mmHg"], "volume_mL": ts["lv_volume_mL"],
                    "phase": ts["lv_phase"], "mean_active_tension": np.zeros(n),
                    "newton_iterations": np.full(n, 3.0), "mechanics_solves": np.full(n, 4.0),
                    "rejected_steps": np.zeros(n)})
    summary = windkessel_summary()
    summary.update({"newton_iterations": [240.0, 236.0], "mechanics_solves": [320.0, 318.0],
                    "steps": [80.0, 80.0], "rejected_steps": [1.0, 0.0],
                    "mechanics_seconds": [12.5, 12.25]})
    return write_results_file(path, columns, summary=summary, events=events(n_beats, ["lv"]),
                              track_order=True)
