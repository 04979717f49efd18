#!/usr/bin/env python3
"""Check the last row of a results file against independent values.

    check_values.py RESULTS.h5 COLUMN=VALUE:TOL [COLUMN>BOUND ...] [COLUMN<BOUND ...]
                    [--serial SERIAL.h5]

Every time-series value must be finite; each COLUMN's last value must lie within TOL of
VALUE (an independent reference, e.g. a published benchmark); COLUMN>BOUND and
COLUMN<BOUND check a sign or a bound. A COLUMN named summary/NAME is the last row of the
/summary column NAME (e.g. summary/linear_iterations_per_solve<40). With --serial, every column
must equal the serial run's to 1e-8 relative (to the column's scale) plus 1e-10,
row by row, except the round-off columns in NOT_COMPARED.
"""

import sys

import numpy as np

from systole_post.results import read_results


#: Columns that legitimately differ between partitions: the converged residual is at
#: round-off level, iterative solvers' iteration counts depend on the partition, and so do
#: the Newton and chord counts: the modified Newton's chord iterations continue while each
#: cuts |R| fourfold, a decision that round-off can tip when a chord's rate is near it (and
#: the direct and iterative solvers take different chord paths by design).
NOT_COMPARED = ("residual", "linear_iterations", "newton_iterations", "chord_iterations")


def main(argv) -> int:
    args = argv[1:]
    serial = None
    if "--serial" in args:
        i = args.index("--serial")
        serial = args[i + 1]
        del args[i : i + 2]
    results = read_results(args[0])
    ts = results.timeseries
    failures = []
    for name, values in ts.items():
        if not np.all(np.isfinite(values)):
            failures.append(f"column {name} has non-finite values")
    for spec in args[1:]:
        if ">" in spec or "<" in spec:  # a sign or bound check: COLUMN>VALUE, COLUMN<VALUE
            sign = ">" if ">" in spec else "<"
            name, bound = spec.split(sign)
            if name.startswith("summary/"):
                got = results.summary[name[len("summary/"):]][-1]
            else:
                got = ts[name][-1]
            print(f"{name}: {got:.6f} (expected {sign} {bound})")
            if not (got > float(bound) if sign == ">" else got < float(bound)):
                failures.append(f"{name} = {got} is not {sign} {bound}")
            continue
        name, rest = spec.split("=")
        value, tolerance = (float(x) for x in rest.split(":"))
        got = ts[name][-1]
        status = "ok" if abs(got - value) <= tolerance else "FAIL"
        print(f"{name}: {got:.6f} (expected {value} +- {tolerance}) {status}")
        if status != "ok":
            failures.append(f"{name} = {got} is not within {tolerance} of {value}")
    if serial is not None:
        reference = read_results(serial).timeseries
        for name, values in ts.items():
            ref = reference[name]
            if len(ref) != len(values):
                failures.append(f"column {name}: {len(values)} rows, serial run {len(ref)}")
                continue
            if name in NOT_COMPARED:
                continue
            # Relative 1e-8 of the column's scale, plus an absolute 1e-10 for columns
            # that are zero up to round-off (a point on the axis has x = y = 0).
            allowed = 1e-8 * np.max(np.abs(ref)) + 1e-10
            diff = np.max(np.abs(values - ref))
            if not diff <= allowed:
                failures.append(f"column {name} differs from the serial run by {diff:.3g}")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
