#!/usr/bin/env python3
"""Results of the same run on different rank counts: equal to a tolerance.

    compare_ranks.py REFERENCE.h5 OTHER.h5 [--tolerance TOL] [--floor ABS] [--fields]

Every column of /timeseries, /events and /summary (those REFERENCE has) must be in OTHER with
the same number of rows, and |a - b| <= TOL * max|a| + ABS row by row (TOL relative to the
column's largest reference value; NaN matches only NaN). Not compared: wall times (*_seconds)
and the counts and residuals that legitimately depend on the partition (NOT_COMPARED: the
converged residual is round-off, Krylov iteration counts depend on the partition, and the
modified Newton's chord decisions can be tipped by round-off).

With --fields, also the primary fields (FIELDS) of the last field step both files have
(/fields/step_NNNNNN): the output nodes (/mesh/nodes) are ordered by the partition and
duplicated on its boundaries, so the values are compared at the distinct node positions, sorted
(coordinates to 1e-9 mm); deal.II's output rounds the values to single precision, so one
float32 unit in the last place is allowed besides. A run without fields (the 0D circulation) passes this part.

The largest difference found (as a fraction of its allowance) is printed (the measured number for docs/verification.md).
"""

import argparse
import sys

import h5py
import numpy as np

GROUPS = ("timeseries", "events", "summary")
NOT_COMPARED = ("residual", "linear_iterations", "newton_iterations", "chord_iterations",
                "linear_solves", "arkode_steps_per_step")


def compared(name: str) -> bool:
    return not name.endswith("_seconds") and not any(
        name == n or name.endswith("_" + n) for n in NOT_COMPARED)


class Report:
    def __init__(self, tolerance: float, floor: float):
        self.tolerance, self.floor = tolerance, floor
        self.worst = (0.0, "")
        self.failures = []

    def check(self, what: str, a: np.ndarray, b: np.ndarray, single: bool = False) -> None:
        if a.shape != b.shape:
            self.failures.append(f"{what}: shape {a.shape}, other {b.shape}")
            return
        if a.size == 0:
            return
        if np.any(np.isnan(a) != np.isnan(b)):
            self.failures.append(f"{what}: NaN in one run only")
            return
        finite = ~np.isnan(a)
        scale = float(np.max(np.abs(a[finite]), initial=0.0))
        differences = np.abs(a[finite] - b[finite])
        allowances = np.full(differences.shape, self.tolerance * scale + self.floor)
        if single:
            # Values rounded to single precision: one float32 unit in the last place more.
            allowances += np.spacing(np.maximum(np.abs(a[finite]), np.abs(b[finite]))
                                     .astype(np.float32)).astype(np.float64)
        k = int(np.argmax(differences / allowances)) if differences.size else 0
        diff = float(differences[k]) if differences.size else 0.0
        allowed = float(allowances[k]) if differences.size else 1.0
        relative = diff / scale if scale > 0 else diff
        if diff / allowed > self.worst[0]:
            self.worst = (diff / allowed, f"{what} ({relative:.2e} relative)")
        if not diff <= allowed:
            self.failures.append(f"{what}: differs by {diff:.3e} ({relative:.3e} relative to "
                                 f"its largest value {scale:.3e}) > {self.tolerance:g}")


#: The fields compared: the primary unknowns, continuous, so one value per output node.
#: (Derived fields such as stresses are discontinuous across cells, and the output keeps one
#: of the values at a shared vertex, which one depending on the partition; they follow from
#: the compared unknowns, and their reductions are in /timeseries and /summary.) The EP's
#: activation_time field too: its nodal values (-1 where not activated; it was NaN, which spread
#: through DataOut's interpolation to every vertex of such a node's cells, docs/verification.md,
#: "Any rank count").
FIELDS = ("displacement", "transmembrane_potential", "activation_time")


def by_position(nodes: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The values at the distinct output nodes, sorted by position (coordinates to 1e-9 mm;
    each rank writes its own copy of a vertex on the partition boundary)."""
    positions, first = np.unique(np.round(nodes, 9), axis=0, return_index=True)
    return positions, values.reshape(len(nodes), -1)[first]


def compare_fields(a: h5py.File, b: h5py.File, report: Report) -> None:
    steps = sorted(set(a.get("fields", {})) & set(b.get("fields", {})))
    if not steps:
        if "fields" in a or "fields" in b:
            report.failures.append("--fields: no field step in both files")
        return
    step = steps[-1]
    nodes_a, nodes_b = a["mesh/nodes"][()], b["mesh/nodes"][()]
    for name in FIELDS:
        if name not in a["fields"][step]:
            continue
        if name not in b["fields"][step]:
            report.failures.append(f"/fields/{step}/{name}: missing in the other run")
            continue
        xa, va = by_position(nodes_a, a["fields"][step][name][()])
        xb, vb = by_position(nodes_b, b["fields"][step][name][()])
        if xa.shape != xb.shape or not np.allclose(xa, xb, rtol=0, atol=1e-8):
            report.failures.append(f"/fields/{step}/{name}: the output nodes differ")
            continue
        report.check(f"/fields/{step}/{name}", va, vb, single=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reference")
    parser.add_argument("other")
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument("--floor", type=float, default=1e-10)
    parser.add_argument("--fields", action="store_true")
    args = parser.parse_args()
    report = Report(args.tolerance, args.floor)
    with h5py.File(args.reference, "r") as a, h5py.File(args.other, "r") as b:
        for group in GROUPS:
            if group not in a:
                continue
            for name in a[group]:
                if not compared(name):
                    continue
                if name not in b.get(group, {}):
                    report.failures.append(f"/{group}/{name}: missing in {args.other}")
                    continue
                report.check(f"/{group}/{name}", a[group][name][()], b[group][name][()])
        if args.fields:
            compare_fields(a, b, report)
        rows = len(next(iter(a["timeseries"].values()))[()])
    for failure in report.failures:
        print("FAIL:", failure)
    print(f"{args.other} vs {args.reference} ({rows} rows): tolerance {args.tolerance:g} "
          f"relative + {args.floor:g}; the largest difference {report.worst[0]:.3f} of it, "
          f"in {report.worst[1] or '-'}")
    return 1 if report.failures else 0


if __name__ == "__main__":
    sys.exit(main())
