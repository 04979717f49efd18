#!/usr/bin/env python3
"""Checks of a synthetic 'unloading' run of a ventricle.

    check_unloading.py RESULTS.h5 MESH.msh --reference MM --reload MM
                       (--wall RS_ENDO RL_ENDO RS_EPI RL_EPI | --truth TRUE.msh --scale S
                        --names base=B,endocardium=EN,epicardium=EP) [--serial SERIAL.h5]

1. The run's own measures (/summary): reference_max_error_mm <= --reference (the recovered
   vertices against the true ones) and reload_max_error_mm <= --reload.
2. Independent of the run's bookkeeping: the unloaded gmsh mesh (MESH.msh, hexahedra or
   tetrahedra) has the physical surfaces endocardium, epicardium and base, and its base nodes
   lie in one plane. With --wall (the generated ventricle), its endocardial and epicardial
   nodes lie on the analytic ellipsoids of the true reference, (x^2 + y^2)/rs^2 + z^2/rl^2 = 1
   (radii in mm), within --reference (distance to first order: |F - 1| / |grad F|). With
   --truth (a tetrahedral gmsh 4.1 file, the true reference scaled by S [mm per file unit],
   its parts named by --names), the unloaded mesh has as many nodes and tetrahedra, each
   unloaded node is within --reference of its own true node (nearest, one to one), and each
   part's nodes are the true part's nodes.
3. With --serial, the iteration table and the summary equal the serial run's (to 1e-6 of each
   column's scale: a different partition changes only round-off, which the fixed point can
   amplify a little).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from systole_post.gmsh_mesh import read_msh
from systole_post.msh41 import Mesh as Msh41
from systole_post.results import read_results


def ellipsoid_distance(p, rs, rl):
    F = (p[0] ** 2 + p[1] ** 2) / rs**2 + p[2] ** 2 / rl**2
    grad = np.array([2 * p[0] / rs**2, 2 * p[1] / rs**2, 2 * p[2] / rl**2])
    return abs(F - 1.0) / np.linalg.norm(grad)


def ellipsoid_failures(nodes, on, wall, bound):
    """The endocardial and epicardial nodes against the analytic ellipsoids of the truth."""
    failures = []
    rs_endo, rl_endo, rs_epi, rl_epi = wall
    for part, rs, rl in (("endocardium", rs_endo, rl_endo), ("epicardium", rs_epi, rl_epi)):
        # The rims (shared with the base) lie on the ellipsoid too.
        d = max(ellipsoid_distance(nodes[k], rs, rl) for k in on[part])
        print(f"{part}: {len(on[part])} nodes, largest distance to the true surface "
              f"{d:.4g} mm (must be <= {bound})")
        if not d <= bound:
            failures.append(f"{part} nodes are {d} mm off the true surface")
    return failures


def truth_failures(mesh, on, args):
    """The unloaded nodes against the true mesh's, one to one, and the parts' nodes."""
    truth = Msh41(Path(args.truth))
    true_nodes = truth.points * args.scale
    if len(mesh.nodes) != len(true_nodes) or len(mesh.tetrahedra) != len(truth.tets):
        return [f"{len(mesh.nodes)} nodes and {len(mesh.tetrahedra)} tetrahedra, the truth "
                f"{len(true_nodes)} and {len(truth.tets)}"]
    distances = np.linalg.norm(mesh.nodes[:, None, :] - true_nodes[None, :, :], axis=-1)
    match = np.argmin(distances, axis=1)
    largest = float(np.max(distances[np.arange(len(match)), match]))
    print(f"{len(match)} nodes, largest distance to their true node {largest:.4g} mm "
          f"(must be <= {args.reference})")
    failures = []
    if len(set(match.tolist())) != len(match):
        failures.append("two unloaded nodes are nearest to the same true node")
    if not largest <= args.reference:
        failures.append(f"an unloaded node is {largest} mm from its true node")
    for pair in args.names.split(","):
        part, true_part = pair.split("=")
        mine = {int(match[k]) for k in on[part]}
        theirs = set(np.unique(truth.surfaces[true_part]).tolist())
        print(f"{part}: {len(mine)} nodes, the truth's {true_part}: {len(theirs)}")
        if mine != theirs:
            failures.append(f"the nodes of {part} are not those of the truth's {true_part}")
    return failures


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("results")
    parser.add_argument("mesh")
    parser.add_argument("--wall", nargs=4, type=float)
    parser.add_argument("--truth")
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--names",
                        default="base=base,endocardium=endocardium,epicardium=epicardium")
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
    if len(mesh.hexahedra) + len(mesh.tetrahedra) == 0:
        failures.append(f"{args.mesh} has no hexahedra or tetrahedra")
    if not failures:
        on = {part: set(mesh.faces(tag).ravel().tolist()) for part, tag in names.items()}
        if args.wall:
            failures += ellipsoid_failures(nodes, on, args.wall, args.reference)
        if args.truth:
            failures += truth_failures(mesh, on, args)
        base = np.array([nodes[k] for k in sorted(on["base"])])
        # The spread along the normal of the best-fitting plane.
        spread = np.linalg.svd(base - base.mean(axis=0), compute_uv=False)[-1] / np.sqrt(len(base))
        print(f"base: {len(base)} nodes, rms distance to their plane {spread:.3g} mm")
        if not spread <= 1e-9 * max(1.0, np.max(np.abs(base))):
            failures.append(f"the base is not planar (rms distance to its plane {spread})")

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
