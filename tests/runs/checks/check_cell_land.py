#!/usr/bin/env python3
"""Check a results file of Problem = cell with Land tension (parameters/cell_ttp_land.prm).

    check_cell_land.py RESULTS.h5 N_BEATS TOLERANCE

Physiological ranges per beat (/summary: resting potential -90..-80 mV, peak +20..+50 mV,
APD90 250..350 ms, peak calcium 0.3..3 µM, peak tension 10..100 kPa at 1 Hz); /timeseries
active_tension is finite and non-negative; and the tension agrees with an independent
integration (systole_post.land_reference: SciPy solve_ivp of the same Land ODEs driven by the
run's own calcium trace, at fixed stretch 1) to TOLERANCE relative to the peak tension.
"""

import sys

import numpy as np

from systole_post.land_reference import isometric_twitch
from systole_post.results import read_results

RANGES = {
    "resting_potential_mV": (-90.0, -80.0),
    "peak_potential_mV": (20.0, 50.0),
    "APD90_ms": (250.0, 350.0),
    "peak_calcium_uM": (0.3, 3.0),
    "peak_tension_kPa": (10.0, 100.0),
}


def main(argv) -> int:
    path, n_beats, tolerance = argv[1], int(argv[2]), float(argv[3])
    results = read_results(path)
    failures = []
    ts, summary = results.timeseries, results.summary
    tension = np.asarray(ts["active_tension"])
    if not np.all(np.isfinite(tension)) or tension.min() < -1e-9:
        failures.append("/timeseries/active_tension is not finite and non-negative")
    if list(summary["beat"]) != list(range(n_beats)):
        failures.append(f"/summary beats {list(summary['beat'])}, expected 0..{n_beats - 1}")
    for beat in range(len(summary["beat"])):
        for name, (low, high) in RANGES.items():
            value = summary[name][beat]
            status = "ok" if low <= value <= high else "FAIL"
            print(f"beat {beat} {name}: {value:.4f} (range {low}..{high}) {status}")
            if status != "ok":
                failures.append(f"beat {beat} {name} = {value} outside {low}..{high}")
    reference = isometric_twitch(ts["time"], ts["calcium_uM"], 1.0)
    error = np.max(np.abs(tension - reference)) / np.max(reference)
    peak_error = abs(tension.max() - reference.max()) / reference.max()
    print(f"active_tension vs SciPy solve_ivp: max difference {error:.3e} of the peak "
          f"{reference.max():.3f} kPa, peak difference {peak_error:.3e} (tolerance {tolerance})")
    if not error <= tolerance:
        failures.append(f"active_tension differs from the SciPy reference by {error:.3e}")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
