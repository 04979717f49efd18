#!/usr/bin/env python3
"""Checks of a synthetic 'unloading' run of the generated ventricle.

    check_unloading.py RESULTS.h5 MESH.msh --wall RS_ENDO RL_ENDO RS_EPI RL_EPI
                       --reference MM --reload MM [--serial SERIAL.h5]

1. The run's own measures (/summary): reference_max_error_mm <= --reference (the recovered
   vertices against the true ones) and reload_max_error_mm <= --reload.
2. Independent of the run's bookkeeping: the unloaded gmsh mesh has the physical surfaces
   endocardium, epicardium and base, and its endocardial and epicardial nodes lie on the
   analytic ellipsoids of the true reference, (x^2 + y^2)/rs^2 + z^2/rl^2 = 1 (radii in mm),
   within --reference (distance to first order: |F - 1| / |grad F|); its base nodes lie in
   the plane of the base (the largest z).
3. With --serial, the iteration table and the summary equal the serial run's (to 1e-6 of each
   column's scale: a different partition changes only round-off, which the fixed point can
   amplify a little).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "scripts"))
from systole_post.gmsh_mesh import read_msh  # noqa: E402
from systole_post.results import read_results  # noqa: E402


def ellipsoid_distance(p, rs, rl):
    F = (p[0] ** 2 + p[1] ** 2) / rs**2 + p[2] ** 2 / rl**2
    grad = np.array([2 * p[0] / rs**2, 2 * p[1] / rs**2, 2 * p[2] / rl**2])
    return abs(F - 1.0) / np.linalg.norm(grad)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("results")
    parser.add_argument("mesh")
    parser.add_argument("--wall", nargs=4, type=float, required=True)
    parser.add_argument("--reference", type=float, required=True)
    parser.add_argument("--reload", type=float, required=True)
    parser.add_argument("--serial")
    args = parser.parse_args()
    failures = []

    results = read_results(args.results)
    summary = results.summary
    for name, bound in (("reference_max_error_mm", args.reference),
                        ("reload_max_error_mm", args.reload)):
        got = summary[name][-1]
        print(f"{name}: {got:.4g} mm (must be <= {bound})")
        if not got <= bound:
            failures.append(f"{name} = {got} > {bound}")
    print("fixed-point iterations:", summary["fixed_point_iterations"][-1],
          "forward solves:", summary["forward_solves"][-1])

    mesh = read_msh(args.mesh)
    nodes, names = mesh.nodes, mesh.names
    for part in ("endocardium", "epicardium", "base"):
        if part not in names:
            failures.append(f"{args.mesh} has no physical surface '{part}' ({sorted(names)})")
    if len(mesh.hexahedra) == 0:
        failures.append(f"{args.mesh} has no hexahedra")
    if not failures:
        on = {part: set(mesh.quads.get(tag, np.zeros((0, 4), int)).ravel().tolist())
              for part, tag in names.items()}
        rs_endo, rl_endo, rs_epi, rl_epi = args.wall
        for part, rs, rl in (("endocardium", rs_endo, rl_endo), ("epicardium", rs_epi, rl_epi)):
            # The rims (shared with the base) lie on the ellipsoid too.
            d = max(ellipsoid_distance(nodes[k], rs, rl) for k in on[part])
            print(f"{part}: {len(on[part])} nodes, largest distance to the true surface "
                  f"{d:.4g} mm (must be <= {args.reference})")
            if not d <= args.reference:
                failures.append(f"{part} nodes are {d} mm off the true surface")
        z = np.array([nodes[k][2] for k in on["base"]])
        print(f"base: {len(z)} nodes, z spread {np.ptp(z):.3g} mm")
        if not np.ptp(z) <= 1e-9 * max(1.0, np.max(np.abs(z))):
            failures.append(f"the base is not planar (z spread {np.ptp(z)})")

    if args.serial:
        serial = read_results(args.serial)
        for table, ref in ((results.timeseries, serial.timeseries), (summary, serial.summary)):
            for name, values in table.items():
                if name in ("linear_iterations",):
                    continue
                if len(values) != len(ref[name]):
                    failures.append(f"{name}: {len(values)} rows, serial {len(ref[name])}")
                    continue
                allowed = 1e-6 * np.max(np.abs(ref[name])) + 1e-9
                diff = np.max(np.abs(values - ref[name]))
                if not diff <= allowed:
                    failures.append(f"{name} differs from the serial run by {diff:.3g}")

    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
