"""The Niederer table (scripts/systole_bench/niederer.py): rows of both mass matrices side by side,
the difference from fenicsx-beat's values of the same (h, dt), and the cell-model cost from the
lumped-mass row (the one comparable with Mitchell-Schaeffer's)."""

from systole_bench.niederer import (NIEDERER_FENICSX_BEAT, NIEDERER_POINTS, niederer_levels,
                                    niederer_text)


def row(h: float, dt: float, mass: str, times: list[float], us: float) -> dict:
    return {"label": f"h = {h} mm, dt = {dt} ms, {mass} mass", "ok": True, "busy": False,
            "key": (h, dt), "mass": mass, "dofs": 4305, "steps": 1600, "cg_per_solve": 2.0,
            "us_per_step_dof": us, "wall": 10.0, "memory": 200.0,
            "summary": {f"{p}_activation_time": t for p, t in zip(NIEDERER_POINTS, times)}}


def test_rows_of_both_masses_and_the_cost_of_the_lumped_one():
    other = NIEDERER_FENICSX_BEAT[(0.5, 0.05)]
    consistent = row(0.5, 0.05, "consistent", [t + 1.0 for t in other], 3.0)
    lumped = row(0.5, 0.05, "lumped", other[:7] + [float("nan")] + other[8:], 2.0)
    ms = {"ok": True, "busy": False, "us_per_step_dof": 0.5}
    text = niederer_text([consistent, lumped], ms)
    assert "| h = 0.5 mm, dt = 0.05 ms, consistent mass | 4305 |" in text
    # Every point 1 ms later than fenicsx-beat: the largest difference is 1.00.
    assert f"| {other[7]:.2f} | 1.00 | 1600 |" in text
    # The lumped row has one point not activated; the others agree exactly.
    assert "| 0.00 (1 not activated) |" in text
    assert "ten Tusscher-Panfilov 2.00 µs per step per DOF" in text
    assert "ratio 4.0" in text


def test_the_quick_levels_run_both_masses_and_every_level_has_a_reference():
    quick, default = niederer_levels(True), niederer_levels(False)
    full = niederer_levels(False, True)
    assert {m for _, _, m in quick} == {"lumped", "consistent"}
    assert set(quick) < set(default) < set(full)
    # --full reaches the benchmark's finest resolution.
    assert (0.1, 0.005, "consistent") in full
    assert all((h, dt) in NIEDERER_FENICSX_BEAT for h, dt, _ in full)
