"""The group 'p2': Land problem 2 (inflation), penalty, refined on 2 ranks and once on 1 rank."""

from __future__ import annotations

from pathlib import Path

from .core import LAND2_PENALTY, Case, case_table, ventricle

TITLE = "Land problem 2 (inflation)"
NOTE = ("The penalty formulation (parameters/land_problem2.prm until 2026-12-07; the file is now "
        "the mixed one, group p2-mixed). Reference: endocardial apex -26.6 mm (-26.9 ... -26.4), "
        "epicardial apex -28.3 mm (-28.5 ... -28.1). Bulk modulus 1000 kPa.")


def cases(quick: bool) -> list[Case]:
    """8 x 3 cells refined 0-2 times (0-1 with quick), 16 x 5 cells, and one run on 1 rank."""
    levels = [0, 1] if quick else [0, 1, 2]
    p2 = [Case("p2", "land_problem2.prm", f"8x3x1 cells, {r} refinement(s), Q2",
               {**LAND2_PENALTY, **ventricle(8, 3, r)}) for r in levels]
    p2 += [Case("p2", "land_problem2.prm", "16x5x1 cells, 0 refinement(s), Q2", LAND2_PENALTY)]
    return p2 + [Case("p2", "land_problem2.prm", "8x3x1 cells, 1 refinement, Q2",
                      {**LAND2_PENALTY, **ventricle(8, 3, 1)}, 1)]


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    return case_table(TITLE, cases(args.quick), ["endo_apex_z", "epi_apex_z"], NOTE, args.build,
                      workdir)
