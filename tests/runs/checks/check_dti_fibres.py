#!/usr/bin/env python3
"""Check systole-fibres with the dti generator against the rule the image was made from.

    check_dti_fibres.py RESULTS.h5 ALPHA_ENDO ALPHA_EPI LOG [--within DEGREES] [--fraction F]

The image holds the analytic helix rule of the Land et al. 2015 ventricle (endocardium
r_s = 7, r_l = 17 mm; epicardium 10, 20 mm; the radii vary linearly with the transmural
coordinate t): f = sin(alpha) e_u + cos(alpha) e_v, alpha(t) = ALPHA_ENDO + (ALPHA_EPI -
ALPHA_ENDO) t [degree], e_u (meridional) and e_v (circumferential) the unit tangents of the
point's own spheroid. Checks:

- the written fibre, sheet and sheet_normal vectors are unit, orthogonal and right-handed;
- at the written points (the vertices of every cell, off the long axis, where the rule is
  undefined), the angle between the fibre line and the rule's is below DEGREES (default 2)
  at a fraction of at least F (default 0.95) of the points; fibres have no sign, so f and
  -f count alike. t is computed here, by bisection, not taken from the code;
- the log LOG (the app's standard output) reports the rejected fraction of the mesh points.
"""

import re
import sys
from pathlib import Path

import h5py
import numpy as np

#: Endocardial and epicardial (short, long) radii of the Land ventricle [mm].
ENDO, EPI = (7.0, 17.0), (10.0, 20.0)


def transmural_coordinate(x):
    """t with rho^2 / r_s(t)^2 + z^2 / r_l(t)^2 = 1 (bisection on [-0.5, 1.5])."""
    rho2, z2 = x[:, 0] ** 2 + x[:, 1] ** 2, x[:, 2] ** 2
    lo, hi = np.full(len(x), -0.5), np.full(len(x), 1.5)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        r_s = ENDO[0] + mid * (EPI[0] - ENDO[0])
        r_l = ENDO[1] + mid * (EPI[1] - ENDO[1])
        outside = rho2 / r_s**2 + z2 / r_l**2 > 1.0  # the point lies beyond spheroid t = mid
        lo, hi = np.where(outside, mid, lo), np.where(outside, hi, mid)
    return 0.5 * (lo + hi)


def analytic_fibres(x, alpha_endo, alpha_epi, continued=False):
    """The rule's unit fibre vectors at the points x (n, 3), off the axis; angles in degree.
    Points outside the wall take the wall's angle, or with @p continued the rule continued
    linearly in t (as make_synthetic_dti.py --outside extrapolate writes the image)."""
    t = transmural_coordinate(x)
    r_s = ENDO[0] + t * (EPI[0] - ENDO[0])
    r_l = ENDO[1] + t * (EPI[1] - ENDO[1])
    cos_u = np.clip(x[:, 2] / r_l, -1.0, 1.0)
    sin_u = -np.sqrt(1.0 - cos_u**2)  # u in (-pi, 0)
    v = np.arctan2(-x[:, 1], -x[:, 0])
    e_u = np.stack([r_s * cos_u * np.cos(v), r_s * cos_u * np.sin(v), -r_l * sin_u], axis=1)
    e_v = np.stack([-r_s * sin_u * np.sin(v), r_s * sin_u * np.cos(v), np.zeros_like(v)], axis=1)
    e_u /= np.linalg.norm(e_u, axis=1)[:, None]
    e_v /= np.linalg.norm(e_v, axis=1)[:, None]
    t_rule = t if continued else np.clip(t, 0.0, 1.0)
    alpha = np.radians(alpha_endo + (alpha_epi - alpha_endo) * t_rule)[:, None]
    return np.sin(alpha) * e_u + np.cos(alpha) * e_v, t


def main(argv) -> int:
    args = argv[1:]
    options = {"--within": 2.0, "--fraction": 0.95, "--wall-margin": 1e-6}
    for name in options:
        if name in args:
            i = args.index(name)
            options[name] = float(args[i + 1])
            del args[i : i + 2]
    path, alpha_endo, alpha_epi, log = args[0], float(args[1]), float(args[2]), Path(args[3])
    failures = []

    with h5py.File(path, "r") as h5:
        nodes = h5["mesh/nodes"][()]
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

    off_axis = np.hypot(nodes[:, 0], nodes[:, 1]) > 1e-6
    # Nodes off the wall (--wall-margin > 0: the centre nodes of split hexahedra) are compared
    # with the rule continued beyond it, as the image holds it.
    expected, t = analytic_fibres(nodes[off_axis], alpha_endo, alpha_epi,
                                  continued=options["--wall-margin"] > 1e-6)
    margin = options["--wall-margin"]
    if not np.all((t > -margin) & (t < 1 + margin)):
        failures.append(f"points outside the wall: t in [{t.min():.3g}, {t.max():.3g}]")
    cosine = np.clip(np.abs((f[off_axis] * expected).sum(axis=1)), 0.0, 1.0)
    angle = np.degrees(np.arccos(cosine))
    fraction = np.mean(angle < options["--within"])
    print(f"{off_axis.sum()} points off the axis: fibre angle error mean {angle.mean():.3f}, "
          f"median {np.median(angle):.3f}, max {angle.max():.3f} degree; "
          f"{100 * fraction:.2f} % within {options['--within']} degree")
    if not fraction >= options["--fraction"]:
        failures.append(f"only {100 * fraction:.2f} % of the points within {options['--within']} "
                        f"degree ({100 * options['--fraction']:.0f} % required)")

    text = log.read_text() if log.exists() else ""
    match = re.search(r"Fibres / DTI: .*?\(([\d.eE+-]+) % rejected, limit ([\d.eE+-]+) %\)", text)
    if match:
        print(f"reported: {match.group(1)} % of the mesh points rejected (limit {match.group(2)} %)")
    else:
        failures.append(f"{log} does not report the rejected fraction ('... % rejected, limit ...')")

    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
