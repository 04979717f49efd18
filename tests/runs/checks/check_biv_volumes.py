#!/usr/bin/env python3
"""Physics check of a 'cavity volume' run on the BiV mesh: both cavity volumes against an
independent computation from the .msh file, and V(t) = stretch(t)^3 V(0).

    check_biv_volumes.py RESULTS.h5 MESH.msh [--serial=SERIAL.h5] [--coarser=COARSE.h5]
                         [--max-below=FRACTION] [--min-ratio=R]

- V_LV(0), V_RV(0) (Systole: deal.II's gmsh import, Mechanics::CavityVolume with the field
  ((x - x0) . e) e that has no flux through the base plane) equal those of
  systole_post.gmsh_mesh.cavity_volume (its own .msh reader, the field x / 3 over the
  endocardium plus the explicit polygon of its basal ring) to 1e-9 (relative): the same
  discrete surface, two code paths. The issue asks for 1e-3.
- Both lie within 1 % (or --max-below) of the exact volumes of the smooth shape
  (systole_post.biv_shape), below it (the flat facets cut the convex cavity walls; the
  structured meshes of scripts/make_biv_hex_mesh.py are far coarser on the RV free wall).
- With --serial every column equals the serial run's to 1e-10 (relative).
- With --coarser (the same run on a coarser mesh): the distance to the exact volume shrinks by
  at least 1.8 (or --min-ratio) for both cavities (meshes/biv_coarse.msh to biv_fine.msh: element size 6 to
  4 mm, 2.3 and 2.4 measured, close to the (6/4)^2 = 2.25 of second order; biv_hex_coarse.msh
  to biv_hex_fine.msh: 12 instead of 10 cells along the junction, (12/10)^2 = 1.44 for second
  order, 1.54 (LV) and 1.48 (RV) measured).
"""

import sys

import numpy as np

from systole_post.biv_shape import lv_cavity_volume, rv_cavity_volume
from systole_post.gmsh_mesh import cavity_volume, read_msh
from systole_post.results import read_results

BASE_Z = 25.0


def main(argv) -> int:
    options = dict(a[2:].split("=", 1) for a in argv[1:] if a.startswith("--"))
    argv = [a for a in argv if not a.startswith("--")]
    ts = read_results(argv[1]).timeseries
    coarse = read_results(options["coarser"]).timeseries if "coarser" in options else None
    mesh = read_msh(argv[2])
    max_below = float(options.get("max-below", 0.01))
    min_ratio = float(options.get("min-ratio", 1.8))
    exact = {"lv_endocardium": lv_cavity_volume(), "rv_endocardium": rv_cavity_volume()}
    failures = []
    for part in ("lv_endocardium", "rv_endocardium"):
        volume = ts[f"{part}_volume"]
        independent = cavity_volume(mesh, part, BASE_Z)
        difference = abs(volume[0] - independent) / independent
        below = (exact[part] - volume[0]) / exact[part]
        print(f"{part}: Systole {volume[0]:.6f} mm^3, independent {independent:.6f} mm^3 "
              f"(relative difference {difference:.2e}), exact {exact[part]:.3f} mm^3 "
              f"({below * 100:.3f} % below)")
        if not difference <= 1e-9:
            failures.append(f"{part}: V(0) differs from the independent value by {difference:.3g}")
        if not 0 <= below <= max_below:
            failures.append(f"{part}: V(0) is {below * 100:.3g} % below the exact volume")
        if coarse is not None:
            below_coarse = (exact[part] - coarse[f"{part}_volume"][0]) / exact[part]
            print(f"{part}: {below_coarse:.3e} below on the coarser mesh, {below:.3e} here "
                  f"(ratio {below_coarse / below:.2f})")
            if not below_coarse >= min_ratio * below:
                failures.append(f"{part}: the error shrinks only by {below_coarse / below:.3g}")
        worst = np.max(np.abs(volume - volume[0] * ts["stretch"] ** 3) / volume[0])
        if not worst <= 1e-10:
            failures.append(f"{part}: V(t) differs from stretch^3 V(0) by {worst:.3g}")
    if "serial" in options:
        serial = read_results(options["serial"]).timeseries
        for name, values in ts.items():
            reference = serial[name]
            scale = max(np.max(np.abs(reference)), 1e-300)
            diff = (np.max(np.abs(values - reference)) / scale
                    if len(values) == len(reference) else np.inf)
            if not diff <= 1e-10:
                failures.append(f"column {name} differs from the serial run by {diff:.3g}")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
