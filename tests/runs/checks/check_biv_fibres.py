#!/usr/bin/env python3
"""Check systole-fibres' output on the BiV mesh and that scripts/plot_fibres.py plots it.

    check_biv_fibres.py RESULTS.h5 ALPHA_ENDO ALPHA_EPI

- fibre, sheet, sheet_normal are unit, orthogonal and right-handed at every written vertex;
- the /summary helix-angle profile (in the frame of phi_epi and psi) follows the linear
  ALPHA_ENDO + (ALPHA_EPI - ALPHA_ENDO) phi within 8 degrees at every bin centre but the first:
  the free walls turn linearly in phi_epi. The first bin (phi_epi < 0.1) holds the septum,
  where phi_epi is near 0 on both sides and its frame is not the septal wall's; the angles on
  each surface are checked against a frame of the mesh alone in
  tests/unit/fibres/biventricular_test.cc;
- plot_fibres.py writes a PNG of it.
"""

import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

SCRIPTS = Path(__file__).resolve().parents[3] / "scripts"
from systole_post.results import read_results


def main(argv) -> int:
    path, alpha_endo, alpha_epi = argv[1], float(argv[2]), float(argv[3])
    failures = []
    with h5py.File(path, "r") as h5:
        step = h5["fields/step_000000"]
        f, s, n = (step[name][()] for name in ("fibre", "sheet", "sheet_normal"))
    for name, vectors in (("fibre", f), ("sheet", s), ("sheet_normal", n)):
        error = np.max(np.abs(np.linalg.norm(vectors, axis=1) - 1.0))
        if not error < 1e-6:
            failures.append(f"{name} is not unit (error {error:.2g})")
    orthogonality = max(np.max(np.abs((a * b).sum(axis=1))) for a, b in ((f, s), (f, n), (s, n)))
    if not orthogonality < 1e-6:
        failures.append(f"the frames are not orthogonal (error {orthogonality:.2g})")
    if not np.max(np.abs(np.cross(f, s) - n)) < 1e-6:
        failures.append("the frames are not right-handed (n != f x s)")

    summary = read_results(path).summary
    depth, mean = summary["depth"], summary["helix_mean"]
    linear = alpha_endo + (alpha_epi - alpha_endo) * depth
    for k in range(1, len(depth)):
        print(f"bin {depth[k]:.2f}: helix {mean[k]:.2f}, linear {linear[k]:.2f} degrees")
        if not abs(mean[k] - linear[k]) < 8:
            failures.append(f"bin {depth[k]:.2f}: helix {mean[k]:.2f} is not near {linear[k]:.2f}")

    with tempfile.TemporaryDirectory() as tmp:
        png = Path(tmp) / "helix.png"
        run = subprocess.run([sys.executable, str(SCRIPTS / "plot_fibres.py"), path, "-o", str(png)],
                             capture_output=True, text=True)
        if run.returncode != 0 or not png.is_file() or png.stat().st_size < 1000:
            failures.append(f"plot_fibres.py failed: {run.stderr.strip()}")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
