"""The group 'p1': Land problem 1 (the beam), refined on 2 ranks and once on 1 rank, and the
penalty formulation's convergence in the bulk modulus."""

from __future__ import annotations

from pathlib import Path

from .core import Case, case_table

TITLE = "Land problem 1 (beam): deflection"
NOTE = ("Reference: 4.17 mm, converged codes 4.151 ... 4.185 mm. Incompressible, mixed "
        "Q2-P1disc (parameters/land_problem1.prm).")
KAPPA_TITLE = "Land problem 1: bulk modulus"
KAPPA_NOTE = "The penalty result as the bulk modulus grows (near-incompressibility)."


def cases(quick: bool) -> list[Case]:
    """The beam refined 0-2 times (0-1 with quick) on 2 ranks, and once on 1 rank."""
    levels = [0, 1] if quick else [0, 1, 2]
    p1 = [Case("p1", "land_problem1.prm", f"10x1x1 cells, {r} refinement(s), Q2",
               {"Global refinements": str(r)}) for r in levels]
    return p1 + [Case("p1", "land_problem1.prm", "10x1x1 cells, 1 refinement, Q2",
                      {"Global refinements": "1"}, 1)]


def kappa_cases() -> list[Case]:
    """The penalty formulation's convergence in the bulk modulus (land_problem1.prm itself is
    incompressible and mixed now; the mixed group sweeps kappa for the mixed formulation)."""
    return [Case("p1", "land_problem1.prm", f"1 refinement, Q2 penalty, kappa = {k} kPa",
                 {"Global refinements": "1", "Material/Incompressibility": "penalty",
                  "Mechanics/Volumetric integration": "reduced",
                  "Material/Volumetric/Bulk modulus": str(k)}) for k in (200, 1000, 5000)]


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's sections {title: text}."""
    return {**case_table(TITLE, cases(args.quick), ["beam_tip_z"], NOTE, args.build, workdir),
            **case_table(KAPPA_TITLE, kappa_cases(), ["beam_tip_z"], KAPPA_NOTE, args.build,
                         workdir)}
