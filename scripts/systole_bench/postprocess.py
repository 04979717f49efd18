"""The group 'postprocess': the postprocessors on analytic deformations and the AHA
partition (hidden unit tests).
"""

from __future__ import annotations

import subprocess
from pathlib import Path


POSTPROCESS_TITLE = "Postprocessors: analytic deformations and the AHA partition"


def postprocess_section(build: Path) -> str:
    """The analytic checks of the postprocessors (tests/unit/postprocess): run them and
    report what each one checks and whether it passed."""
    checks = [
        ("Homogeneous stretch along the fibres*",
         "u = (lambda - 1)(f0 . X) f0, lambda = 1.15, a uniform fibre frame, on the default "
         "ventricle (16 x 5 cells, Q2, MappingQ2, no Dirichlet part): at every quadrature point "
         "lambda_f = J = lambda and e . E e = (lambda^2 - 1)/2 (f0 . e)^2 for e = e_c, e_l, e_r "
         "of the wall coordinates' frame, to 1e-10; the nodal fibre_stretch and J (lumped L2 "
         "projection) equal lambda to 1e-10"),
        ("Simple shear*",
         "u = gamma (e_z . X) e_x, gamma = 0.2: E = (gamma (a x b + b x a) + gamma^2 b x b)/2 "
         "in every frame direction, J = 1, lambda_f = sqrt(1 + 2 f0 . E f0), to 1e-10"),
        ("A uniform dilation*",
         "u = (lambda - 1)(X - c) about an off-axis point, lambda = 1.1: long_axis_shortening "
         "= 1 - lambda, wall_thickening = lambda - 1, torsion = 0, to 1e-10"),
        ("A prescribed twist*",
         "rotation by phi about the long axis up to the top of the apical ring, 0 from the "
         "bottom of the basal ring, linear between (phi = -12, 7.5, 25 degrees): torsion = "
         "phi and long_axis_shortening = 0 to 1e-10"),
        ("The 17 AHA segments of the default ventricle*",
         "every segment holds points of at least one cell; the segment volumes add up to the "
         "wall volume (GridTools::volume with the same mapping) to 1e-10 relative"),
        ("A stretch along the fibre gives*",
         "pointwise: random frames, F = I + (lambda - 1) f0 x f0, S = s0 f0 x f0: the fibre "
         "and first principal Cauchy stress equal lambda s0 to 1e-12"),
    ]
    lines = [f"## {POSTPROCESS_TITLE}",
             "The postprocessors of `Postprocess / List of postprocessors` against deformations "
             "with closed-form values (`tests/unit/postprocess`, run now):", "",
             "| check | what | passed |", "|---|---|---|"]
    for name, what in checks:
        out = subprocess.run([str(build / "tests" / "systole-unit"), name],
                             capture_output=True, text=True)
        lines.append(f"| {name.rstrip('*')} | {what} | "
                     f"{'yes' if out.returncode == 0 else '**no**'} |")
    return "\n".join(lines) + "\n"


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    text = postprocess_section(args.build)
    print(text, flush=True)
    return {POSTPROCESS_TITLE: text}
