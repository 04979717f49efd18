#!/usr/bin/env python3
"""Check a results file of Problem = cell against the SciPy reference of its model file.

    check_cell.py RESULTS.h5 CELL_TYPE N_BEATS TOLERANCE

Every time-series value is finite (potential_mV, calcium_uM); /summary has N_BEATS rows, one
per beat; the resting potential, peak potential, APD90 and peak calcium of every beat agree
with systole_post.ten_tusscher_reference (SciPy on the Python gotranx generated from the same
.ode file, an independent code path) to TOLERANCE relative.
"""

import sys

import numpy as np

from systole_post.results import read_results
from systole_post.ten_tusscher_reference import reference_beats

MEASURES = ("resting_potential_mV", "peak_potential_mV", "APD90_ms", "peak_calcium_uM")


def main(argv) -> int:
    path, cell_type, n_beats, tolerance = argv[1], argv[2], int(argv[3]), float(argv[4])
    results = read_results(path)
    failures = []
    for name in ("potential_mV", "calcium_uM"):
        if not np.all(np.isfinite(results.timeseries[name])):
            failures.append(f"/timeseries/{name} has non-finite values")
    summary = results.summary
    if list(summary["beat"]) != list(range(n_beats)):
        failures.append(f"/summary beats {list(summary['beat'])}, expected 0..{n_beats - 1}")
    else:
        for beat, expected in enumerate(reference_beats(cell_type, n_beats)):
            for name in MEASURES:
                got, want = summary[name][beat], expected[name]
                error = abs(got - want) / abs(want)
                status = "ok" if error <= tolerance else "FAIL"
                print(f"beat {beat} {name}: {got:.5f} (SciPy {want:.5f}, "
                      f"relative {error:.1e}) {status}")
                if status != "ok":
                    failures.append(f"beat {beat} {name}: {got} vs {want}")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
