"""The Krylov growth lines of the scaling group (scripts/systole_bench/scaling.py): over all levels
of a formulation and within each coarse mesh's family of refinements, ordered by DOFs."""

from systole_bench.scaling import scaling_growth


def row(level: str, formulation: str, dofs: int, per_solve: float, ok: bool = True):
    return {"level": level, "formulation": formulation, "ok": ok,
            "summary": {"n_dofs": dofs, "linear_iterations_per_solve": per_solve}}


def test_growth_over_all_levels_and_per_family():
    rows = [row("16x5, 0", "incompressible", 2713, 20.0),
            row("32x10, 0", "incompressible", 10537, 15.0),
            row("16x5, 2", "incompressible", 128731, 30.0),
            row("32x10, 2", "incompressible", 511387, 18.0),
            row("16x5, 1", "incompressible", 17903, 25.0)]
    lines = scaling_growth(rows)
    assert lines == [
        "incompressible: 20.0 -> 18.0 Krylov iterations per solve from 2713 to 511387 DOFs "
        "(-10 %).",
        "incompressible on 16x5: 20.0 -> 30.0 Krylov iterations per solve from 2713 to "
        "128731 DOFs (+50 %).",
        "incompressible on 32x10: 15.0 -> 18.0 Krylov iterations per solve from 10537 to "
        "511387 DOFs (+20 %).",
    ]


def test_one_family_and_failed_runs():
    rows = [row("16x5, 0", "kappa/C = 1e2", 2713, 20.0),
            row("16x5, 1", "kappa/C = 1e2", 17903, 22.0),
            row("16x5, 2", "kappa/C = 1e2", 128731, 99.0, ok=False),
            row("16x5, 0", "kappa/C = 1e4", 2713, 20.0)]
    # One family: no separate family line; a failed run and a single level count for nothing.
    assert scaling_growth(rows) == [
        "kappa/C = 1e2: 20.0 -> 22.0 Krylov iterations per solve from 2713 to 17903 DOFs "
        "(+10 %)."]


def p2_row(dofs: int, endo: float, epi: float, ok: bool = True):
    from systole_bench.core import Case
    return {"case": Case("p2-mixed", "land_problem2.prm", f"{dofs} DOFs mesh", {}), "ok": ok,
            "dofs": dofs, "values": {"endo_apex_z": endo, "epi_apex_z": epi}}


def test_p2_band_note_names_the_levels_outside_and_compares_the_two_largest():
    from systole_bench.core import p2_band_note
    rows = [p2_row(17903, -26.63, -28.31), p2_row(2713, -26.607, -28.640),
            p2_row(511387, -26.62, -28.29), p2_row(9, 0.0, 0.0, ok=False)]
    note = p2_band_note(rows)
    assert "Outside the band: 2713 DOFs mesh (2713 DOFs): epi_apex_z -28.640 mm." in note
    assert "From 17903 to 511387 DOFs: endo_apex_z +0.0100 mm, epi_apex_z +0.0200 mm." in note


def test_p2_band_note_inside():
    from systole_bench.core import p2_band_note
    assert p2_band_note([p2_row(17903, -26.63, -28.31)]) == \
        " Every level lies inside the band."


def test_p2_band_note_per_element():
    from systole_bench.core import Case, p2_band_note

    def labelled(label: str, dofs: int, endo: float, epi: float):
        return {"case": Case("p2-mixed", "land_problem2.prm", label, {}), "ok": True,
                "dofs": dofs, "values": {"endo_apex_z": endo, "epi_apex_z": epi}}
    rows = [labelled("coarse, Q2-P1disc", 2713, -26.607, -28.640),
            labelled("coarse, Q2-Q1", 2603, -26.705, -28.461),
            labelled("coarse, Q2-P1disc, accelerated chords", 2713, -26.0, -28.0),
            labelled("fine, Q2-Q1", 17000, -26.65, -28.32)]
    assert p2_band_note(rows, "Q2-P1disc") == \
        " Q2-P1disc: Outside the band: coarse, Q2-P1disc (2713 DOFs): epi_apex_z -28.640 mm."
    assert p2_band_note(rows, "Q2-Q1") == (
        " Q2-Q1: Every level lies inside the band. From 2603 to 17000 DOFs: "
        "endo_apex_z +0.0550 mm, epi_apex_z +0.1410 mm.")
    assert p2_band_note(rows, "Q1-P0") == ""


def test_taylor_hood_section_reads_its_own_formulations():
    from systole_bench.scaling import SCALING_TH_TITLE, scaling_text

    def full(level: str, formulation: str, dofs: int, per_solve: float):
        r = row(level, formulation, dofs, per_solve)
        r["summary"].update({"newton_iterations": 9, "assembly_seconds": 0.1,
                             "linear_solver_seconds": 0.2, "n_displacement_dofs": dofs - 100,
                             "n_pressure_dofs": 100, "step_cuts": 0})
        r.update({"cpu": 1.0, "memory": 200.0, "load": (0.5, 0.5, 0.5)})
        return r
    rows = [full("16x5, 0", "incompressible, Q2-Q1", 2603, 27.1),
            full("32x11, 2", "incompressible, Q2-Q1", 524512, 34.9)]
    text = scaling_text(rows, th=True)
    assert text.startswith(f"## {SCALING_TH_TITLE}\n")
    assert "| 32x11, 2 | incompressible, Q2-Q1 | 524512 (524412 + 100) | 9 (0) | 34.9 |" in text
    assert ("incompressible, Q2-Q1: 27.1 -> 34.9 Krylov iterations per solve from 2603 to "
            "524512 DOFs (+29 %).") in text
    # The scaling group's own section lists none of these rows.
    assert "Q2-Q1" not in scaling_text(rows).split("\n\n")[1]
