"""A fast stand-in for the systole app in the land group's tests: reads the atrial pressure,
the peripheral resistance and Land's beta1 from a case of the land recipes and writes the
results file of a 2-beat heartbeat whose numbers follow simple laws.

Usage: python fake_land_systole.py CASE.prm LAUNCH_LOG

The last beat (beat 1, 800-1600 ms): EDV = 120 + p_a mL (p_a: the atrial pressure), SV = 50 +
g (p_a - 6) - 20 (R_p - 1) mL with g = 1.25 with the length dependence and 0.75 without it
(beta1 = 0), the aortic valve closing at P = 4 (ESV - 40) mmHg (an ESPVR of 4 mmHg/mL and 40 mL).
The LV pressure is p_a - 0.5 mmHg and the mean active tension 0.3 kPa when the beat starts.
Every launch appends the case folder's name to LAUNCH_LOG.
"""

import sys
from pathlib import Path

import h5py

from conftest import write_results_file
from fake_systole import read_prm


def main():
    prm, log = sys.argv[1], sys.argv[2]
    with open(log, "a") as stream:
        stream.write(Path.cwd().name + "\n")
    values = read_prm(prm)
    atrial = float(values["Circulation / Atrial pressure"])
    resistance = float(values.get("Circulation / Peripheral resistance", 1.0))
    gain = 0.75 if float(values.get("Active tension / Land / beta1", -2.4)) == 0 else 1.25
    edv = 120.0 + atrial
    sv = 50.0 + gain * (atrial - 6.0) - 20.0 * (resistance - 1.0)
    esv = edv - sv
    esp = 4.0 * (esv - 40.0)
    timeseries = {"time": [0.0, 790.0, 810.0, 1600.0], "beat": [0, 0, 1, 1],
                  "lv_pressure_mmHg": [0.0, atrial - 1.0, atrial, 5.0],
                  "mean_active_tension": [0.0, 0.4, 0.2, 0.3]}
    summary = {"beat": [0.0, 1.0], "start_time": [0.0, 800.0], "end_time": [800.0, 1600.0],
               "lv_EDP_mmHg": [atrial, atrial], "lv_EDV_mL": [edv - 10.0, edv],
               "lv_SV_mL": [sv - 5.0, sv], "lv_ESV_mL": [esv - 5.0, esv],
               "lv_peak_pressure_mmHg": [esp, esp + 10.0]}
    # The aortic valve (1) opens and closes in each beat; beat 0 closes 1 mmHg lower.
    events = {"time": [100.0, 400.0, 900.0, 1200.0], "beat": [0.0, 0.0, 1.0, 1.0],
              "valve": [1.0] * 4, "opens": [1.0, 0.0, 1.0, 0.0],
              "lv_pressure_mmHg": [60.0, esp - 1.0, 60.0, esp],
              "lv_volume_mL": [edv - 10.0, esv - 5.0, edv, esv]}
    out = Path(values["Output / Directory"]) / values["Output / Run name"]
    out.mkdir(parents=True, exist_ok=True)
    path = write_results_file(out / "results.h5", timeseries, summary=summary, events=events)
    with h5py.File(path, "a") as f:
        stats = f.create_group("statistics")
        for key, value in (("wall_time", 20.0 * (1 + atrial / 10)), ("n_dofs", 801),
                           ("ep_nodes", 1685), ("beats", 2), ("newton_iterations", 40),
                           ("steps", 10)):
            stats.create_dataset(key, data=float(value))
    return 0


if __name__ == "__main__":
    sys.exit(main())
