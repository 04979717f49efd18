#!/usr/bin/env python3
"""Physics check of a 'cavity volume' run: V(t) = stretch(t)^3 V(0), V(0) near the exact value.

    check_cavity_volume.py RESULTS.h5 EXACT_MM3 REL_TOL [SERIAL_RESULTS.h5]

With SERIAL_RESULTS, every time-series column must also equal the serial run's to 1e-10
(relative to the column's scale): the parallel run reproduces the serial one.
"""

import sys

import numpy as np

from systole_post.results import read_results


def main(argv) -> int:
    results = read_results(argv[1])
    exact, tolerance = float(argv[2]), float(argv[3])
    ts = results.timeseries
    volume, stretch = ts["volume"], ts["stretch"]
    failures = []
    if results.n_rows < 2:
        failures.append(f"only {results.n_rows} rows")
    error0 = abs(volume[0] - exact) / exact
    if not error0 <= tolerance:
        failures.append(f"V(0) = {volume[0]} mm^3: relative error {error0:.3g} > {tolerance}")
    scaled = volume[0] * stretch**3
    worst = np.max(np.abs(volume - scaled) / volume[0])
    if not worst <= 1e-10:
        failures.append(f"V(t) differs from stretch^3 V(0) by {worst:.3g} (relative)")
    if len(argv) > 4:
        serial = read_results(argv[4]).timeseries
        for name, values in ts.items():
            reference = serial[name]
            scale = max(np.max(np.abs(reference)), 1e-300)
            diff = np.max(np.abs(values - reference)) / scale if len(values) == len(reference) else np.inf
            if not diff <= 1e-10:
                failures.append(f"column {name} differs from the serial run by {diff:.3g}")
    for failure in failures:
        print("FAIL:", failure)
    print(f"{results.n_rows} rows, V(0) = {volume[0]:.6f} mm^3, max |V - s^3 V0|/V0 = {worst:.2e}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
