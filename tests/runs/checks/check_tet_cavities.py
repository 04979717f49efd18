#!/usr/bin/env python3
"""Physics check of a run on a tetrahedral gmsh mesh: the initial cavity volumes against an
independent computation from the .msh file.

    check_tet_cavities.py RESULTS.h5 MESH.msh LID_X,LID_Y,LID_Z COLUMN=SURFACE ...
                          [--serial=SERIAL.h5]

Each COLUMN (a /timeseries volume column in mL, e.g. lv_endocardium_volume_mL) at step 0 equals
the volume that the mesh's physical surface SURFACE encloses with the lid plane through the
point LID (systole_post.msh41: its own reader of the file, the divergence theorem over the
surface's triangles with the origin on the lid) to 1e-9 relative: the same discrete surface,
two code paths. Every column is finite and the volumes grow under the pressure load. With
--serial, every column equals the serial run's to 1e-8 relative plus 1e-10.
"""

import sys
from pathlib import Path

import numpy as np

from systole_post.msh41 import Mesh
from systole_post.results import read_results

NOT_COMPARED = ("residual", "linear_iterations", "newton_iterations", "chord_iterations")


def main(argv) -> int:
    options = dict(a[2:].split("=", 1) for a in argv[1:] if a.startswith("--"))
    args = [a for a in argv[1:] if not a.startswith("--")]
    ts = read_results(args[0]).timeseries
    mesh = Mesh(Path(args[1]))
    lid = np.array([float(v) for v in args[2].split(",")])
    failures = []
    for name, values in ts.items():
        if not np.all(np.isfinite(values)):
            failures.append(f"column {name} has non-finite values")
    for spec in args[3:]:
        column, surface = spec.split("=")
        expected = mesh.cavity_volume(surface, lid) / 1000.0  # mm^3 -> mL
        got = ts[column][0]
        print(f"{column}: {got:.12g} mL, from the .msh file {expected:.12g} mL "
              f"(relative difference {abs(got - expected) / expected:.2e}); "
              f"after the load {ts[column][-1]:.6g} mL")
        if abs(got - expected) > 1e-9 * expected:
            failures.append(f"{column} = {got} mL, the .msh file's {surface} encloses {expected}")
        if not ts[column][-1] > got:
            failures.append(f"{column} does not grow under the load")
    if "serial" in options:
        serial = read_results(options["serial"]).timeseries
        for name, values in ts.items():
            if name in NOT_COMPARED:
                continue
            scale = max(1.0, float(np.max(np.abs(serial[name]))))
            if np.max(np.abs(values - serial[name])) > 1e-8 * scale + 1e-10:
                failures.append(f"column {name} differs from the serial run")
    for failure in failures:
        print("FAILED:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
