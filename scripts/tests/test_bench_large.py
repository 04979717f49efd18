"""The section of the "large" group (scripts/systole_bench/large.py): the beam's band verdict and
the table rows of both problems."""

from systole_bench.large import LARGE_TITLE, large_text


def finished(values: dict, dofs: int) -> dict:
    return {"ok": True, "busy": False, "values": values, "wall": 900.0, "memory": 2400.0,
            "discretization": "Q2-P1disc (u-p, incompressible)", "solver": "iterative",
            "summary": {"n_dofs": dofs, "n_displacement_dofs": dofs - 1000,
                        "n_pressure_dofs": 1000, "load_steps": 10, "step_cuts": 0,
                        "newton_iterations": 12, "chord_iterations": 30,
                        "linear_iterations_per_solve": 21.5, "assembly_seconds": 60.0,
                        "linear_solver_seconds": 240.0}}


def test_beam_inside_and_outside_the_band():
    ventricle = finished({"endo_apex_z": -12.3, "epi_apex_z": -15.5}, 511387)
    inside = large_text([("Land problem 1, fine", finished({"beam_tip_z": 4.1684}, 520995)),
                         ("Land problem 3, fine", ventricle)])
    assert inside.startswith(f"## {LARGE_TITLE}\n")
    assert "Land problem 1, fine: the beam tip at 4.1684 mm, inside the band" in inside
    assert "| Land problem 1, fine | Q2-P1disc (u-p, incompressible) | iterative | 520995 " \
           "(519995 + 1000) | 4.1684 | 10 | 0 | 12 | 30 | 21.5 |" in inside
    assert "| Land problem 3, fine | Q2-P1disc (u-p, incompressible) | iterative | 511387 " \
           "(510387 + 1000) | -12.300 / -15.500 |" in inside
    outside = large_text([("Land problem 1, fine", finished({"beam_tip_z": 4.2090}, 607))])
    assert "the beam tip at 4.2090 mm, outside the band 4.151 ... 4.185 mm." in outside


def test_failed_run_is_a_row_not_a_verdict():
    failed = {"ok": False, "busy": False, "error": "Newton did not converge"}
    text = large_text([("Land problem 1, fine", failed)])
    assert "| Land problem 1, fine | failed: Newton did not converge |" in text
    assert "band" not in text.split("\n\n")[0].split("iterations / DOFs.")[1]
