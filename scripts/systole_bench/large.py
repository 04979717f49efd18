"""The group 'large': Land problems 1 and 3 above 500k DOFs (2 ranks)."""

from __future__ import annotations

from pathlib import Path

from .core import Case, run
from .mixed import mixed_table


#: The "large" group: the shipped files of Land problems 1 and 3 (incompressible, Q2-P1disc)
#: on meshes above 500k DOFs, with the `auto` linear solver (matrix-free there). The beam: 30 x 3
#: x 3 coarse cells refined twice (120 x 12 x 12 cells, 521k DOFs); the ventricle: 32 x 10
#: coarse cells refined twice, without the file's local refinement at the apex (511k DOFs).
LARGE_TITLE = "Land problems 1 and 3 above 500k DOFs (2 ranks)"
LARGE_CASES = [
    ("Land problem 1, 30x3x3 cells, 2 refinements",
     Case("large", "land_problem1.prm", "30x3x3 cells, 2 refinements, Q2-P1disc",
          {"Global refinements": "2", "Geometry/Box/Cells": "30, 3, 3"})),
    ("Land problem 3, 32x10x1 cells, 2 refinements",
     Case("large", "land_problem3.prm", "32x10x1 cells, 2 refinements, Q2-P1disc",
          {"Global refinements": "2", "Geometry/Ellipsoid/Cells around circumference": "32",
           "Geometry/Ellipsoid/Cells from apex to base": "10",
           "Geometry/Local refinements": "0"})),
]
#: Land problem 1's band (Land et al. 2015, the converged codes) [mm].
P1_BAND = (4.151, 4.185)


def large_section(build: Path, workdir: Path) -> str:
    """The shipped Land problems 1 and 3 above 500k DOFs."""
    rows = []
    for label, case in LARGE_CASES:
        print(f"running {label} on {case.ranks} rank(s) ...", flush=True)
        rows.append((label, run(case, build, workdir)))
    return large_text(rows)


def large_text(rows: list[tuple[str, dict]]) -> str:
    """The large group's section from its (label, row) pairs."""
    notes = []
    for label, r in rows:
        if not r["ok"] or "beam_tip_z" not in r["values"]:
            continue
        tip, (low, high) = r["values"]["beam_tip_z"], P1_BAND
        where = "inside" if low <= tip <= high else "outside"
        notes.append(f"{label}: the beam tip at {tip:.4f} mm, {where} the band "
                     f"{low} ... {high} mm.")
    return (
        f"## {LARGE_TITLE}\n"
        "Written by `scripts/bench --only large`. The shipped `parameters/land_problem1.prm` and "
        "`parameters/land_problem3.prm` (incompressible, mixed Q2-P1disc, their load steps and "
        "Newton settings) on the finest meshes of the refinement studies: the beam of 30 x 3 x 3 "
        "coarse cells refined twice (120 x 12 x 12 cells) and the ventricle of 32 x 10 coarse "
        "cells refined twice without the file's local refinement at the apex, 2 ranks, the "
        "`auto` linear solver (above 200 000 DOFs matrix-free since 2026-12-07, iterative before). Problem 1: the deformed z of the "
        "beam tip (10, 0.5, 1); problem 3: the deformed z of the endocardial and epicardial "
        "apex, whose values depend on the level of the cells at the apex points (sections "
        "\"Land problem 3: refined at each apex\" and \"Land problem 3: the fibre field on the "
        "axis\"). Time per Newton iteration per DOF = (assembly + linear solver) / Newton "
        "iterations / DOFs." + (" " + " ".join(notes) if notes else "") + "\n\n"
        + mixed_table(rows, "problem, mesh",
                      value="beam tip z or endo / epi apex z [mm]") + "\n")


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    text = large_section(args.build, workdir)
    print(text, flush=True)
    return {LARGE_TITLE: text}
