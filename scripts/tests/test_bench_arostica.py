"""The Aróstica step-1 section of scripts/systole_bench/arostica.py: the distance of two runs'
tracked-point curves is taken over the times both have, the notes compare the right runs, and
a run is measured against the participants' curves."""

import numpy as np
import pytest

from systole_bench import arostica


def fake_row(label: str, dt: float, amplitude: float) -> dict:
    t = np.arange(0.0, 1000.0 + dt / 2, dt)
    row = {"ok": True, "label": label, "dt": dt, "time": t, "dofs": 801, "wall": 1.0,
           "steps": len(t) - 1, "cut": 0,
           "summary": {"newton_iterations": 10, "chord_iterations": 20},
           "volumes": (168.0, 147.0, 600.0)}
    for point, scale in (("p0", 1.0), ("p1", 0.5)):
        x = np.zeros((len(t), 3))
        x[:, 0] = -scale * amplitude * np.sin(np.pi * t / 1000.0)
        row[point] = {"curve": x, "largest": scale * amplitude, "at": 500.0,
                      "at_480": x[np.argmin(np.abs(t - 480.0))]}
    row["participants"] = {"p0": (1.0, 240.0), "p1": (2.0, 250.0)}
    return row


def test_the_curve_distance_uses_the_common_times():
    a, b = fake_row("level 0", 2.0, 10.0), fake_row("level 0", 1.0, 10.5)
    # At the common times (every 2 ms) the curves differ by 0.5 sin(pi t / T): at most 0.5.
    assert abs(arostica.curve_distance(a, b, "p0") - 0.5) < 1e-12
    assert abs(arostica.curve_distance(a, b, "p1") - 0.25) < 1e-12


def test_the_section_compares_time_steps_and_levels(monkeypatch):
    amplitudes = {("level 0", 2.0): 10.0, ("level 0", 1.0): 10.1, ("level 0", 0.5): 10.12,
                  ("level 1", 2.0): 11.0, ("level 1", 1.0): 11.2}
    monkeypatch.setattr(arostica, "run_arostica",
                        lambda label, dt, changes, build, workdir:
                        fake_row(label, dt, amplitudes.get((label, dt), 12.0)))
    text = arostica.arostica_section(None, None, quick=True)
    assert text.startswith(f"## {arostica.AROSTICA_TITLE}\n")
    assert text.count("\n| level 0 | ") == 3 and text.count("\n| level 1 | ") == 2
    assert text.count("\n| benchmark mesh P1 | 1 | ") == 1
    assert "| 1.00 (240 ms) / 2.00 (250 ms) |" in text
    assert "level 0, dt 2 -> 1 ms: p0 and p1 curves differ by at most 0.1000 and 0.0500 mm" \
        in text
    assert "level 0, dt 1 -> 0.5 ms: p0 and p1 curves differ by at most 0.0200" in text
    assert "level 0 -> level 1 at dt 1 ms: the largest displacements change by +1.100 (p0) " \
           "and +0.550 mm (p1)" in text
    assert "participants' curves" in text


def test_the_plan_runs_the_benchmark_mesh_with_its_shape():
    quick = arostica.arostica_plan(quick=True)
    full = arostica.arostica_plan(quick=False)
    tet = [changes for label, _, changes in full if label.startswith("benchmark mesh")]
    assert [c["Polynomial degree"] for c in tet] == ["1", "2"]
    for changes in tet:
        assert changes["Geometry/Gmsh/Shape"] == "arostica"
        assert changes["Geometry/Gmsh/Mesh file"].endswith("meshes/arostica_benchmark_tet.msh")
    assert not any(label == "benchmark mesh P2" for label, _, _ in quick)


@pytest.mark.parametrize("step", ["0A", "0B", "1"])
def test_the_participants_data(step):
    t, groups = arostica.participants(step)
    assert len(t) == 101 and t[0] == 0.0 and abs(t[-1] - 1000.0) <= 1.0
    assert len(groups) == 11
    for curves in groups.values():
        assert curves["p0"].shape == curves["p1"].shape == (101, 3)
        # At rest at t = 0 (three groups report their first step there: 0.01-0.03 mm).
        assert np.max(np.abs(curves["p0"][0])) < 0.03
    # Step 1's p0 moves about 35 mm towards the apex at the end of systole (the paper's
    # figure): every group between 34 and 37 mm at 480 ms.
    if step == "1":
        i = int(np.argmin(np.abs(t - 480.0)))
        sizes = [np.linalg.norm(c["p0"][i]) for c in groups.values()]
        assert 34.0 < min(sizes) and max(sizes) < 37.0


def test_a_run_on_the_participants_mean_is_at_distance_zero():
    t, groups = arostica.participants("1")
    row = {"time": t}
    for point in ("p0", "p1"):
        mean = np.mean([g[point] for g in groups.values()], axis=0)
        rest = np.array([25.0, 30.0, 0.0]) if point == "p0" else np.array([0.0, 30.0, 0.0])
        row[point] = {"curve": rest + mean}
        row[point]["mean"] = mean
    # A run's displacement is taken from its first point, the participants' mean is not
    # exactly 0 there (above): the distance is that offset, the same at every time.
    far = arostica.against_participants(row)
    for point in ("p0", "p1"):
        offset = np.linalg.norm(row[point]["mean"][0])
        assert 0 < offset < 0.03 and abs(far[point][0] - offset) < 1e-9
    # Moved by 1 mm along y after t = 0: about 1 mm from the mean.
    row["p0"]["curve"] = row["p0"]["curve"] + np.where(t[:, None] > 0, [0.0, 1.0, 0.0], 0.0)
    assert abs(arostica.against_participants(row)["p0"][0] - 1.0) < 0.03
