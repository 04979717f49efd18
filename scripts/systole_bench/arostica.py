"""The group 'arostica': the Aróstica et al. 2025 benchmark, step 1."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from systole_post.results import read_results

from .core import Case, run


AROSTICA_TITLE = ("The Aróstica et al. 2025 benchmark, step 1 "
                  "(parameters/arostica_step1.prm)")


def run_arostica(level: int, dt: float, build: Path, workdir: Path) -> dict:
    """Step 1 of the benchmark at mesh level @p level and time step @p dt [ms] on 2 ranks:
    the run's row plus the displacements of the tracked points p0 and p1."""
    case = Case("arostica", "arostica_step1.prm", f"level {level}, dt {dt:g} ms",
                {"Global refinements": str(level), "Time/Time step": f"{dt:g}"})
    print(f"running the Aróstica step 1, {case.label} ...", flush=True)
    row = run(case, build, workdir)
    row["level"], row["dt"] = level, dt
    if not row["ok"]:
        return row
    name = re.sub(r"[^a-z0-9]+", "_", f"{case.problem} {case.label} {case.ranks}".lower())
    ts = read_results(workdir / "results" / name / "results.h5").timeseries
    t = np.asarray(ts["time"])
    row["time"] = t
    at = int(np.argmin(np.abs(t - 480.0)))
    for point in ("p0", "p1"):
        x = np.stack([np.asarray(ts[f"{point}_{c}"]) for c in "xyz"], axis=1)
        d = x - x[0]
        size = np.linalg.norm(d, axis=1)
        i = int(np.argmax(size))
        row[point] = {"curve": x, "largest": float(size[i]), "at": float(t[i]),
                      "at_480": d[at]}
    volume = np.asarray(ts["volume_mL"]) if "volume_mL" in ts else None
    if volume is not None:
        i = int(np.argmin(volume))
        row["volumes"] = (float(volume[0]), float(volume[i]), float(t[i]))
    return row


def curve_distance(a: dict, b: dict, point: str) -> float:
    """Largest |x_a - x_b| [mm] of a tracked point over the times both runs have."""
    ta, tb = np.round(a["time"], 9), np.round(b["time"], 9)
    common = np.intersect1d(ta, tb)
    xa = a[point]["curve"][np.searchsorted(ta, common)]
    xb = b[point]["curve"][np.searchsorted(tb, common)]
    return float(np.max(np.linalg.norm(xa - xb, axis=1)))


def arostica_section(build: Path, workdir: Path, quick: bool) -> str:
    """Step 1 at levels 0, 1 (and 2) with dt = 1 ms, and dt = 2, 0.5 ms at levels 0 and 1."""
    plan = [(0, 2.0), (0, 1.0), (0, 0.5), (1, 2.0), (1, 1.0)]
    plan += [] if quick else [(1, 0.5), (2, 1.0)]
    rows = [run_arostica(level, dt, build, workdir) for level, dt in plan]
    head = ("| level | dt [ms] | DOFs | wall [s] | steps (cuts) | Newton / chord | Krylov per "
            "solve | V at rest / smallest [mL] | p0 largest [mm] (t) | p0 at 480 ms [mm] | "
            "p1 largest [mm] (t) | p1 at 480 ms [mm] |")
    lines = [f"## {AROSTICA_TITLE}",
             "Written by `scripts/bench --only arostica` (`--quick`: without level 2 and the "
             "0.5 ms step at level 1): the benchmark's geometry, fibres, law, viscosity, "
             "density, supports and load ODEs, generalized-alpha (spectral radius 2/3), "
             "1000 ms, 2 ranks. The displacements of p0 = (25, 30, 0) mm and p1 = (0, 30, 0) "
             "mm from their rest positions.", "", head,
             "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        mark = " *" if r.get("busy") else ""
        if not r["ok"]:
            lines.append(f"| {r['level']} | {r['dt']:g} | failed: {r.get('error', '')} |")
            continue
        s = r["summary"]
        v = r.get("volumes", (math.nan, math.nan, math.nan))
        cells = [str(r["level"]), f"{r['dt']:g}", str(r["dofs"]), f"{r['wall']:.1f}{mark}",
                 f"{r['steps']} ({r['cut']})",
                 f"{int(s.get('newton_iterations', 0))} / {int(s.get('chord_iterations', 0))}",
                 f"{s.get('linear_iterations_per_solve', math.nan):.1f}",
                 f"{v[0]:.2f} / {v[1]:.2f} ({v[2]:.0f} ms)"]
        for point in ("p0", "p1"):
            q = r[point]
            cells += [f"{q['largest']:.3f} ({q['at']:.0f} ms)",
                      "(" + ", ".join(f"{c:.3f}" for c in q["at_480"]) + ")"]
        lines.append("| " + " | ".join(cells) + " |")
    if any(r.get("busy") for r in rows):
        lines += ["", "\\* The machine was busy during the run: the time is inflated."]
    ok = {(r["level"], r["dt"]): r for r in rows if r["ok"]}
    notes = []
    for level in (0, 1):
        pairs = [(2.0, 1.0), (1.0, 0.5)]
        found = [(a, b) for a, b in pairs if (level, a) in ok and (level, b) in ok]
        for a, b in found:
            notes.append(f"level {level}, dt {a:g} -> {b:g} ms: p0 and p1 curves differ by at "
                         f"most {curve_distance(ok[(level, a)], ok[(level, b)], 'p0'):.4f} "
                         f"and {curve_distance(ok[(level, a)], ok[(level, b)], 'p1'):.4f} mm")
    for a, b in ((0, 1), (1, 2)):
        if (a, 1.0) in ok and (b, 1.0) in ok:
            notes.append(f"levels {a} -> {b} at dt 1 ms: the largest displacements change by "
                         f"{ok[(b, 1.0)]['p0']['largest'] - ok[(a, 1.0)]['p0']['largest']:+.3f} "
                         f"(p0) and "
                         f"{ok[(b, 1.0)]['p1']['largest'] - ok[(a, 1.0)]['p1']['largest']:+.3f} "
                         "mm (p1)")
    if notes:
        lines += ["", "Time step and mesh: " + "; ".join(notes) + ". The participants' curves "
                  "are not on this machine: no comparison with them here."]
    return "\n".join(lines) + "\n"


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    text = arostica_section(args.build, workdir, args.quick)
    print(text, flush=True)
    return {AROSTICA_TITLE: text}
