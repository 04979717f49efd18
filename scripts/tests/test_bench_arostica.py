"""The Aróstica step-1 section of scripts/systole_bench/arostica.py: the distance of two runs'
tracked-point curves is taken over the times both have, and the notes compare the right runs."""

import numpy as np

from systole_bench import arostica


def fake_row(level: int, dt: float, amplitude: float) -> dict:
    t = np.arange(0.0, 1000.0 + dt / 2, dt)
    row = {"ok": True, "level": level, "dt": dt, "time": t, "dofs": 801 * (level + 1),
           "wall": 1.0, "steps": len(t) - 1, "cut": 0,
           "summary": {"newton_iterations": 10, "chord_iterations": 20,
                       "linear_iterations_per_solve": 1.0},
           "volumes": (168.0, 147.0, 600.0)}
    for point, scale in (("p0", 1.0), ("p1", 0.5)):
        x = np.zeros((len(t), 3))
        x[:, 0] = -scale * amplitude * np.sin(np.pi * t / 1000.0)
        largest = scale * amplitude
        row[point] = {"curve": x, "largest": largest, "at": 500.0,
                      "at_480": x[np.argmin(np.abs(t - 480.0))]}
    return row


def test_the_curve_distance_uses_the_common_times():
    a, b = fake_row(0, 2.0, 10.0), fake_row(0, 1.0, 10.5)
    # At the common times (every 2 ms) the curves differ by 0.5 sin(pi t / T): at most 0.5.
    assert abs(arostica.curve_distance(a, b, "p0") - 0.5) < 1e-12
    assert abs(arostica.curve_distance(a, b, "p1") - 0.25) < 1e-12


def test_the_section_compares_time_steps_and_levels(monkeypatch):
    amplitudes = {(0, 2.0): 10.0, (0, 1.0): 10.1, (0, 0.5): 10.12, (1, 2.0): 11.0,
                  (1, 1.0): 11.2}
    monkeypatch.setattr(arostica, "run_arostica",
                        lambda level, dt, build, workdir: fake_row(level, dt,
                                                                   amplitudes[(level, dt)]))
    text = arostica.arostica_section(None, None, quick=True)
    assert text.startswith(f"## {arostica.AROSTICA_TITLE}\n")
    assert text.count("\n| 0 | ") == 3 and text.count("\n| 1 | ") == 2
    assert "level 0, dt 2 -> 1 ms: p0 and p1 curves differ by at most 0.1000 and 0.0500 mm" \
        in text
    assert "level 0, dt 1 -> 0.5 ms: p0 and p1 curves differ by at most 0.0200" in text
    assert "levels 0 -> 1 at dt 1 ms: the largest displacements change by +1.100 (p0) and " \
           "+0.550 mm (p1)" in text
