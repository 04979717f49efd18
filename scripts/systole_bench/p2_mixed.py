"""The group 'p2-mixed': Land problem 2 incompressible (mixed Q2-P1disc, and Taylor-Hood
Q2-Q1) in 10 equal load steps on both mesh families of the scaling group, up to 511k DOFs."""

from __future__ import annotations

from pathlib import Path

from .core import Case, case_table, p2_band_note, ventricle

TITLE = "Land problem 2: incompressible, up to 511k DOFs"
NOTE = ("Incompressible (mixed Q2-P1disc, the isochoric part of the Guccione law), 10 "
        "equal load steps, on the two mesh families of the scaling group (16 x 5 and "
        "32 x 10 coarse cells, refined 0-2 times), 2 ranks, the `auto` linear solver "
        "(direct up to 200 000 DOFs, above it iterative until 2026-12-07, matrix-free since) and the default Mechanics / Chord "
        "acceleration depth = auto (the direct solver's chord iterations Anderson-"
        "accelerated with depth 5 from 50 000 DOFs, plain below); 'accelerated chords': "
        "depth 5, 'plain chords': depth 0. The rows 'Q2-Q1' are the same study with the "
        "continuous pressure (Taylor-Hood, `Discretization / Pressure element = "
        "continuous`; at 467k DOFs the iterative solver without the augmented "
        "Lagrangian, which is Q2-P1disc's only). The rows 'iterative' and 'matrix-free' "
        "set the linear solver: the assembled block solver against MatrixFreeMixedSolver. "
        "Reference: "
        "endocardial apex "
        "-26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm (-28.5 ... -28.1).")
#: 10 equal load steps, incompressible.
MIXED10 = {"Material/Incompressibility": "incompressible", "Load steps": "10",
           "Mechanics/Adaptive load steps": "false"}


def chords(depth: str, label: str, levels: list) -> list[Case]:
    """The chord iterations the other way from the default ('auto': Anderson-accelerated,
    depth 5, from 50 000 DOFs with the direct solver)."""
    return [Case("p2-mixed", "land_problem2.prm",
                 f"{a}x{b}x1 cells, {r} refinement(s), Q2-P1disc, {label}",
                 {**ventricle(a, b, r), **MIXED10, "Mechanics/Chord acceleration depth": depth})
            for a, b, r in levels]


def cases(quick: bool) -> list[Case]:
    """Q2-P1disc on the scaling group's levels, the coarse test ventricle and two cells through
    the wall, Q2-Q1 from the 24-cell ventricle on, and the chord iterations either way."""
    levels = [(16, 5, 0), (16, 5, 1), (32, 10, 0), (32, 10, 1)] + (
        [] if quick else [(16, 5, 2), (32, 10, 2)])
    p2i = [Case("p2-mixed", "land_problem2.prm", f"{a}x{b}x1 cells, {r} refinement(s), Q2-P1disc",
                {**ventricle(a, b, r), **MIXED10})
           for a, b, r in levels]
    # The coarse test ventricle (8 x 3, 24 cells) and the coarsest mesh with two cells through
    # the wall: how far the wall resolution moves the epicardial apex.
    p2i += [Case("p2-mixed", "land_problem2.prm", "8x3x1 cells, 0 refinement(s), Q2-P1disc",
                 {**ventricle(8, 3, 0), **MIXED10}),
            Case("p2-mixed", "land_problem2.prm", "16x5x2 cells, 0 refinement(s), Q2-P1disc",
                 {**ventricle(16, 5, 0), **MIXED10, "Geometry/Ellipsoid/Cells through wall": "2"})]
    # The same study with the continuous pressure (Taylor-Hood Q2-Q1), from the 24-cell
    # ventricle on (on the finest level the iterative solver, without the augmented
    # Lagrangian: that is Q2-P1disc's only).
    th_levels = [(8, 3, 0), (16, 5, 0), (16, 5, 1), (32, 10, 0), (32, 10, 1)] + (
        [] if quick else [(16, 5, 2), (32, 10, 2)])
    p2i += [Case("p2-mixed", "land_problem2.prm", f"{a}x{b}x1 cells, {r} refinement(s), Q2-Q1",
                 {**ventricle(a, b, r), **MIXED10, "Discretization/Pressure element": "continuous"})
            for a, b, r in th_levels]
    # Matrix-based against matrix-free side by side (the assembled block solver and
    # MatrixFreeMixedSolver, both with inexact Newton), from 16k DOFs to 511k.
    solver_levels = [(16, 5, 1), (32, 10, 1)] + ([] if quick else [(16, 5, 2), (32, 10, 2)])
    p2i += [Case("p2-mixed", "land_problem2.prm",
                 f"{a}x{b}x1 cells, {r} refinement(s), Q2-P1disc, {solver}",
                 {**ventricle(a, b, r), **MIXED10, "Mechanics/Linear solver": solver})
            for a, b, r in solver_levels for solver in ("iterative", "matrix-free")]
    # Accelerated below the default's threshold, plain above, on the 16 x 5 levels the direct
    # solver takes.
    p2i += chords("5", "accelerated chords", [(16, 5, 0), (16, 5, 1)])
    return p2i + chords("0", "plain chords", [] if quick else [(16, 5, 2)])


def band_notes(rows: list[dict]) -> str:
    """The band notes of each element's study."""
    return p2_band_note(rows, "Q2-P1disc") + p2_band_note(rows, "Q2-Q1")


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    return case_table(TITLE, cases(args.quick), ["endo_apex_z", "epi_apex_z"], NOTE, args.build,
                      workdir, extra=band_notes, chords=True)
