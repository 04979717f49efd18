"""The group 'p3': Land problem 3 (inflation and active contraction), refined globally, at the
apex, and at each apex point; penalty and incompressible.
"""

from __future__ import annotations

from pathlib import Path

from .core import Case, case_table, ventricle


def p3_note(rows: list[dict]) -> str:
    """What the P3 refinement table shows: convergence and the apex on the axis."""
    done = sorted((r for r in rows if r["ok"]), key=lambda r: r["dofs"])
    if len(done) < 2:
        return ""
    fine, coarse = done[-1], done[-2]
    change = ", ".join(
        f"{k} {fine['values'][k] - coarse['values'][k]:+.3f} mm"
        for k in ("endo_apex_z", "epi_apex_z", "midwall_apex_z", "midwall_equator_y"))
    off_axis = max(abs(r["values"][f"{p}_apex_{c}"]) for r in done
                   for p in ("endo", "epi", "midwall") for c in "xy")
    return (f"\n\nFrom the second finest ({coarse['dofs']} DOFs) to the finest mesh "
            f"({fine['dofs']} DOFs): {change}. The apexes stay on the axis "
            f"(|x|, |y| <= {off_axis:.1e} mm at every level).")


def axis_level(case: Case) -> int:
    """Refinement level of the cells on the axis of a P3 case (global + apex refinements)."""
    return int(case.changes["Global refinements"]) + int(case.changes["Geometry/Local refinements"])


def p3_axis_note(rows: list[dict]) -> str:
    """What the apex-refined P3 table shows: the apex values level by level of the cells on
    the axis (meshes of equal axis level: their spread), and the change between the two
    finest levels against the issue's 0.03 mm."""
    done = [r for r in rows if r["ok"]]
    levels = sorted({axis_level(r["case"]) for r in done})
    if len(levels) < 2:
        return ""
    keys = ("endo_apex_z", "epi_apex_z")
    finest = {lv: max((r for r in done if axis_level(r["case"]) == lv), key=lambda r: r["dofs"])
              for lv in levels}
    spread = max((max(r["values"][k] for r in group) - min(r["values"][k] for r in group))
                 for lv in levels for k in keys
                 for group in [[r for r in done if axis_level(r["case"]) == lv]])
    steps = "; ".join(
        f"{a} -> {b}: " + ", ".join(f"{k} {finest[b]['values'][k] - finest[a]['values'][k]:+.3f} mm"
                                    for k in keys)
        for a, b in zip(levels, levels[1:]))
    a, b = levels[-2], levels[-1]
    worst = max(abs(finest[b]["values"][k] - finest[a]["values"][k]) for k in keys)
    verdict = "below" if worst < 0.03 else "not yet below"
    return (f"\n\nChange of the apexes from one level of the cells on the axis to the next "
            f"(the finest mesh of each level): {steps}. Meshes of equal axis level differ by at "
            f"most {spread:.3f} mm. The two finest levels ({a}, {b}) differ by {worst:.3f} mm, "
            f"{verdict} the issue's 0.03 mm.")


def p3_point_note(rows: list[dict]) -> str:
    """What the P3 table refined at each apex point shows: the change of that apex from the
    second finest to the finest level at the point, against the issue's 0.03 mm."""
    parts = []
    for point, key in (("0, 0, -17", "endo_apex_z"), ("0, 0, -20", "epi_apex_z")):
        done = sorted((r for r in rows if r["ok"]
                       and r["case"].changes["Geometry/Local refinement center"] == point),
                      key=lambda r: int(r["case"].changes["Geometry/Local refinements"]))
        if len(done) < 2:
            continue
        change = done[-1]["values"][key] - done[-2]["values"][key]
        parts.append(f"{key} {done[-2]['values'][key]:.3f} -> {done[-1]['values'][key]:.3f} mm "
                     f"({change:+.3f} mm, {'below' if abs(change) < 0.03 else 'not below'} the "
                     "issue's 0.03 mm)")
    if not parts:
        return ""
    return ("\n\nRefined at the point itself, from the second finest to the finest level "
            "there: " + "; ".join(parts) + ".")


#: Penalty, as land_problem3.prm was (it is incompressible and refined at the apex now).
PENALTY = {"Material/Incompressibility": "penalty", "Material/Volumetric/Bulk modulus": "1000"}
COLUMNS = ["endo_apex_z", "epi_apex_z", "midwall_apex_z", "midwall_equator_y"]
TITLE = "Land problem 3 (inflation and active contraction)"
NOTE = ("Analytic helix fibres +90/-90 degrees, T_a = 60 kPa, 15 kPa, bulk modulus 1000 kPa. "
        "The mesh is refined both ways: more coarse cells (around the axis x from apex to "
        "base; `Geometry / Ellipsoid`) and global refinement. Points: the endocardial "
        "(0, 0, -17) and epicardial (0, 0, -20) apex, and the midwall line at v = 0 "
        "(t = 0.5) at its apex (0, 0, -18.5) and at the equator (-8.5, 0, 0). Sign check: "
        "the midwall line at v = 0 twists toward +y (midwall_equator_y > 0). The reference "
        "values are checked independently of this table.")
APEX_TITLE = "Land problem 3: refinement at the apex"
APEX_NOTE = ("The analytic helix fibre direction is undefined on the axis, so the apex "
             "displacements converge slowly under global refinement. Here the cells with a "
             "vertex within 1.5 mm of the mid-wall apex (0, 0, -18.5) are refined again "
             "(`Geometry / Local refinements`, hanging nodes), on top of the global level.")
AXIS_TITLE = "Land problem 3: incompressible, refined at the apex"
AXIS_NOTE = ("Incompressible (mixed Q2-P1disc, `Material / Incompressibility = incompressible`, "
             "as in Land et al. 2015), otherwise the cases of the penalty table above: the "
             "cells with a vertex within 1.5 mm of the mid-wall apex are refined again on top "
             "of the global level. The level of the cells at the apex points (global + "
             "local refinements) sets the apex values.")
POINT_TITLE = "Land problem 3: refined at each apex"
POINT_NOTE = ("Incompressible (mixed Q2-P1disc). 8x3x1 cells refined once, then the cells with "
              "a vertex within 0.75 mm of one apex point, (0, 0, -17) or (0, 0, -20), 3 or 4 "
              "more times (`Geometry / Local refinement center`): the cells at that point are 4 "
              "or 5 levels deep, the rest of the axis much coarser.")


def global_cases(quick: bool) -> list[Case]:
    """Refine the coarse mesh (cells around x from apex to base) and globally (penalty)."""
    levels = [(8, 3, 0), (16, 5, 0), (8, 3, 1), (16, 5, 1)] + ([] if quick else [(8, 3, 2)])
    return [Case("p3", "land_problem3.prm", f"{a}x{b}x1 cells, {r} refinement(s), Q2",
                 {**ventricle(a, b, r), **PENALTY, "Geometry/Local refinements": "0"})
            for a, b, r in levels]


def apex_cases(quick: bool) -> list[Case]:
    """Refined at the apex (the fibre direction is undefined on the axis): global level and
    local refinements within 1.5 mm of the mid-wall apex (penalty)."""
    levels = [(8, 3, 1, 1), (8, 3, 1, 2)] + ([] if quick else [
        (16, 5, 1, 2), (8, 3, 2, 1), (8, 3, 1, 3), (16, 5, 1, 3), (8, 3, 2, 2)])
    return [Case("p3", "land_problem3.prm",
                 f"{a}x{b}x1 cells, {r} refinement(s), apex refined {l} time(s), Q2",
                 {**ventricle(a, b, r), **PENALTY, "Geometry/Local refinements": str(l),
                  "Geometry/Local refinement radius": "1.5"}) for a, b, r, l in levels]


def axis_cases(quick: bool) -> list[Case]:
    """The same, incompressible (mixed Q2-P1disc, as in Land et al. 2015): the penalty
    formulation's Newton fails at 6 % of the load once the cells on the axis are 4 levels
    deep (docs/verification.md), the mixed one does not. Ordered by the level of the cells on
    the axis (global + local refinements)."""
    levels = [(8, 3, 1, 0), (8, 3, 1, 1), (8, 3, 2, 0), (8, 3, 1, 2)] + ([] if quick else [
        (8, 3, 2, 1), (8, 3, 1, 3), (8, 3, 2, 2), (8, 3, 1, 4)])
    return [Case("p3", "land_problem3.prm",
                 f"{a}x{b}x1 cells, {r} refinement(s), apex refined {l} time(s), Q2-P1disc",
                 {**ventricle(a, b, r), "Geometry/Local refinements": str(l),
                  "Geometry/Local refinement radius": "1.5",
                  "Material/Incompressibility": "incompressible"})
            for a, b, r, l in levels]


def point_cases(quick: bool) -> list[Case]:
    """Refined at each apex point in turn (0.75 mm around it), incompressible: the level of
    the cells at the point sets its value (docs/verification.md)."""
    return [Case("p3", "land_problem3.prm",
                 f"8x3x1 cells, 1 refinement, {l} more within 0.75 mm of the {name} apex, Q2-P1disc",
                 {**ventricle(8, 3, 1), "Geometry/Local refinements": str(l),
                  "Geometry/Local refinement center": center,
                  "Geometry/Local refinement radius": "0.75",
                  "Material/Incompressibility": "incompressible"})
            for name, center in (("endocardial", "0, 0, -17"), ("epicardial", "0, 0, -20"))
            for l in ((3,) if quick else (3, 4))]


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's four sections {title: text}."""
    build, quick = args.build, args.quick
    full_columns = COLUMNS[:3] + ["midwall_equator_x", "midwall_equator_y", "midwall_equator_z"]
    tables = [(TITLE, global_cases(quick), full_columns, NOTE, p3_note),
              (APEX_TITLE, apex_cases(quick), COLUMNS, APEX_NOTE, p3_note),
              (AXIS_TITLE, axis_cases(quick), COLUMNS, AXIS_NOTE, p3_axis_note),
              (POINT_TITLE, point_cases(quick), COLUMNS, POINT_NOTE, p3_point_note)]
    out = {}
    for title, cases, columns, note, extra in tables:
        out.update(case_table(title, cases, columns, note, build, workdir, extra, chords=True))
    return out
