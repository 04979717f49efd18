#!/usr/bin/env python3
"""Check a passive inflation of both BiV cavities (Problem = mechanics).

    check_biv_inflation.py RESULTS.h5 MESH.msh

- At load 0 each cavity volume (Problem = mechanics's cavity path) equals the independent
  computation from the .msh file (systole_post.gmsh_mesh) to 1e-9: the two cavities are
  each closed by their own lid in the common base plane.
- Both volumes grow at every load step and the Newton iteration converged (residual below
  1e-6 mN at every step).
- The thin-walled RV (4 mm) stretches more than the LV (5 mm, and more curved): its relative
  volume increase is the larger one.
"""

import sys

import numpy as np

from systole_post.gmsh_mesh import cavity_volume, read_msh
from systole_post.results import read_results


def main(argv) -> int:
    ts = read_results(argv[1]).timeseries
    mesh = read_msh(argv[2])
    failures = []
    growth = {}
    for part in ("lv_endocardium", "rv_endocardium"):
        volume = ts[f"{part}_volume_mL"] * 1000.0  # mm^3
        independent = cavity_volume(mesh, part, 25.0)
        difference = abs(volume[0] - independent) / independent
        growth[part] = volume[-1] / volume[0] - 1
        print(f"{part}: {volume[0] / 1000:.4f} -> {volume[-1] / 1000:.4f} mL "
              f"(+{growth[part] * 100:.2f} %), V(0) vs independent {difference:.1e}")
        if not difference <= 1e-9:
            failures.append(f"{part}: V(0) differs from the independent value by {difference:.3g}")
        if not np.all(np.diff(volume) > 0):
            failures.append(f"{part}: the volume does not grow at every load step")
    if not np.all(ts["residual"] < 1e-6):
        failures.append(f"residuals {ts['residual']}")
    if not growth["rv_endocardium"] > growth["lv_endocardium"] > 0:
        failures.append(f"relative growth RV {growth['rv_endocardium']:.3g} is not above "
                        f"LV {growth['lv_endocardium']:.3g} > 0")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
