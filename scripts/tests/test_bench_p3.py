"""The note of the apex-refined Land problem 3 table (scripts/systole_bench/p3.py): it compares
levels of the cells on the axis (global + apex refinements), not the two largest meshes."""

from systole_bench.core import Case
from systole_bench.p3 import p3_axis_note, p3_point_note


def row(global_refinements: int, local_refinements: int, dofs: int, endo: float, epi: float):
    case = Case("p3", "land_problem3.prm", "x",
                {"Global refinements": str(global_refinements),
                 "Geometry/Local refinements": str(local_refinements)})
    return {"case": case, "ok": True, "dofs": dofs,
            "values": {"endo_apex_z": endo, "epi_apex_z": epi}}


def test_the_note_compares_the_two_finest_axis_levels():
    # The largest mesh (level 3 by global refinement) is not the finest axis level (4).
    rows = [row(1, 2, 100, -12.00, -15.50), row(2, 1, 300, -12.01, -15.51),
            row(1, 3, 200, -12.05, -15.49)]
    note = p3_axis_note(rows)
    assert "3 -> 4: endo_apex_z -0.040 mm, epi_apex_z +0.020 mm" in note
    assert "at most 0.010 mm" in note
    assert "differ by 0.040 mm, not yet below" in note


def test_the_note_says_when_the_criterion_is_met():
    rows = [row(1, 2, 100, -12.00, -15.50), row(1, 3, 200, -12.02, -15.49)]
    assert "differ by 0.020 mm, below the issue's 0.03 mm" in p3_axis_note(rows)


def test_failed_runs_and_a_single_level_give_no_note():
    failed = row(2, 2, 400, 0.0, 0.0)
    failed["ok"] = False
    assert p3_axis_note([row(1, 2, 100, -12.0, -15.5), failed]) == ""


def point_row(center: str, local_refinements: int, endo: float, epi: float):
    case = Case("p3", "land_problem3.prm", "x",
                {"Geometry/Local refinement center": center,
                 "Geometry/Local refinements": str(local_refinements)})
    return {"case": case, "ok": True, "dofs": 0,
            "values": {"endo_apex_z": endo, "epi_apex_z": epi}}


def test_the_point_note_compares_each_apex_where_it_is_refined():
    rows = [point_row("0, 0, -17", 4, -12.34, -15.56), point_row("0, 0, -17", 3, -12.33, -15.56),
            point_row("0, 0, -20", 3, -12.10, -15.50), point_row("0, 0, -20", 4, -12.10, -15.45)]
    note = p3_point_note(rows)
    assert "endo_apex_z -12.330 -> -12.340 mm (-0.010 mm, below" in note
    assert "epi_apex_z -15.500 -> -15.450 mm (+0.050 mm, not below" in note
