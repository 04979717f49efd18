"""The group 'arostica': the Aróstica et al. 2025 benchmark, step 1."""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np

from systole_post.results import read_results

from .core import ROOT, Case, run


AROSTICA_TITLE = ("The Aróstica et al. 2025 benchmark, step 1 "
                  "(parameters/arostica_step1.prm)")
DATA = Path(__file__).resolve().parent / "data"
BENCHMARK_MESH = {"Geometry/Type": "gmsh", "Geometry/Global refinements": "0",
                  "Geometry/Gmsh/Mesh file": str(ROOT / "meshes" / "arostica_benchmark_tet.msh"),
                  "Geometry/Gmsh/Shape": "arostica", "Discretization/Mapping degree": "1"}


def participants(step: str = "1") -> tuple[np.ndarray, dict[str, dict[str, np.ndarray]]]:
    """The benchmark participants' curves (data/README.md): the times [ms] and
    {group: {"p0": (n, 3), "p1": (n, 3)}}, displacements [mm]."""
    with open(DATA / f"arostica_step{step}_participants.csv", newline="") as f:
        rows = list(csv.reader(f))
    values = np.array(rows[1:], dtype=float)
    groups: dict[str, dict[str, np.ndarray]] = {}
    for j, name in enumerate(rows[0][1:], start=1):
        group, point, component = name.rsplit("_", 2)
        curves = groups.setdefault(group, {})
        curves.setdefault(point, np.zeros((len(values), 3)))[:, "xyz".index(component)] = \
            values[:, j]
    return values[:, 0], groups


def against_participants(row: dict, step: str = "1") -> dict[str, tuple[float, float]]:
    """{point: (largest distance [mm] of the run's displacement from the participants' mean
    over the participants' times, the time [ms])}, the run interpolated linearly in time."""
    t, groups = participants(step)
    out = {}
    for point in ("p0", "p1"):
        mean = np.mean([g[point] for g in groups.values()], axis=0)
        curve = row[point]["curve"] - row[point]["curve"][0]
        mine = np.stack([np.interp(t, row["time"], curve[:, k]) for k in range(3)], axis=1)
        distance = np.linalg.norm(mine - mean, axis=1)
        i = int(np.argmax(distance))
        out[point] = (float(distance[i]), float(t[i]))
    return out


def participants_note(step: str = "1") -> str:
    """One sentence: the participants' own spread about their mean and the mean's peak."""
    t, groups = participants(step)
    parts = []
    for point in ("p0", "p1"):
        mean = np.mean([g[point] for g in groups.values()], axis=0)
        spread = max(float(np.max(np.linalg.norm(g[point] - mean, axis=1)))
                     for g in groups.values())
        size = np.linalg.norm(mean, axis=1)
        i = int(np.argmax(size))
        parts.append(f"{point}: every curve within {spread:.2f} mm of the mean, whose largest "
                     f"displacement is {size[i]:.2f} mm at {t[i]:.0f} ms")
    return (f"The {len(groups)} participants' curves (scripts/systole_bench/data/, every "
            "10 ms): " + "; ".join(parts) + ".")


def run_arostica(label: str, dt: float, changes: dict, build: Path, workdir: Path) -> dict:
    """Step 1 of the benchmark with the time step @p dt [ms] and the entries @p changes of
    parameters/arostica_step1.prm on 2 ranks: the run's row plus the displacements of the
    tracked points p0 and p1."""
    case = Case("arostica", "arostica_step1.prm", f"{label}, dt {dt:g} ms",
                {**changes, "Time/Time step": f"{dt:g}"})
    print(f"running the Aróstica step 1, {case.label} ...", flush=True)
    row = run(case, build, workdir)
    row["label"], row["dt"] = label, dt
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
    row["participants"] = against_participants(row)
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


def arostica_plan(quick: bool) -> list[tuple[str, float, dict]]:
    """The runs: the generated hexahedral mesh at levels 0, 1 (and 2) with dt = 2, 1 (and
    0.5) ms, level 1 with straight-edged cells, and the participants' own tetrahedral mesh
    (meshes/arostica_benchmark_tet.msh) with P1 and P2 elements (P2 with dt = 2 ms: 89 679
    DOFs; dt 2 -> 1 ms moves the curves of the generated mesh by at most 0.01 mm)."""
    level = [f"level {n}" for n in range(3)]
    plan = [(level[0], 2.0, {}), (level[0], 1.0, {}), (level[0], 0.5, {}),
            (level[1], 2.0, {}), (level[1], 1.0, {})]
    plan = [(label, dt, {"Global refinements": label[-1], **changes})
            for label, dt, changes in plan]
    plan.append(("level 1, straight edges", 1.0,
                 {"Global refinements": "1", "Discretization/Mapping degree": "1"}))
    tet = [("benchmark mesh P1", 1.0, {**BENCHMARK_MESH, "Polynomial degree": "1"})]
    if quick:
        return plan + tet
    return plan + [(level[1], 0.5, {"Global refinements": "1"}),
                   (level[2], 1.0, {"Global refinements": "2"})] + tet + [
        ("benchmark mesh P2", 2.0, {**BENCHMARK_MESH, "Polynomial degree": "2"})]


def arostica_row(r: dict) -> str:
    """One table row."""
    if not r["ok"]:
        return f"| {r['label']} | {r['dt']:g} | failed: {r.get('error', '')} |"
    s = r["summary"]
    v = r.get("volumes", (math.nan, math.nan, math.nan))
    cells = [r["label"], f"{r['dt']:g}", str(r["dofs"]),
             f"{r['wall']:.1f}{' *' if r.get('busy') else ''}", f"{r['steps']} ({r['cut']})",
             f"{int(s.get('newton_iterations', 0))} / {int(s.get('chord_iterations', 0))}",
             f"{v[0]:.2f} / {v[1]:.2f} ({v[2]:.0f} ms)"]
    for point in ("p0", "p1"):
        q = r[point]
        cells += [f"{q['largest']:.3f} ({q['at']:.0f} ms)",
                  "(" + ", ".join(f"{c:.3f}" for c in q["at_480"]) + ")"]
    far = r["participants"]
    cells.append(" / ".join(f"{far[p][0]:.2f} ({far[p][1]:.0f} ms)" for p in ("p0", "p1")))
    return "| " + " | ".join(cells) + " |"


def convergence_notes(rows: list[dict]) -> list[str]:
    """The time-step and mesh differences of the generated-mesh runs."""
    ok = {(r["label"], r["dt"]): r for r in rows if r["ok"]}
    notes = []
    for level in ("level 0", "level 1"):
        for a, b in ((2.0, 1.0), (1.0, 0.5)):
            if (level, a) in ok and (level, b) in ok:
                ra, rb = ok[(level, a)], ok[(level, b)]
                notes.append(f"{level}, dt {a:g} -> {b:g} ms: p0 and p1 curves differ by at "
                             f"most {curve_distance(ra, rb, 'p0'):.4f} and "
                             f"{curve_distance(ra, rb, 'p1'):.4f} mm")
    for a, b in (("level 0", "level 1"), ("level 1", "level 2")):
        if (a, 1.0) in ok and (b, 1.0) in ok:
            ra, rb = ok[(a, 1.0)], ok[(b, 1.0)]
            notes.append(f"{a} -> {b} at dt 1 ms: the largest displacements change by "
                         f"{rb['p0']['largest'] - ra['p0']['largest']:+.3f} (p0) and "
                         f"{rb['p1']['largest'] - ra['p1']['largest']:+.3f} mm (p1)")
    return notes


def arostica_section(build: Path, workdir: Path, quick: bool) -> str:
    """The runs of arostica_plan() against each other and against the participants."""
    rows = [run_arostica(label, dt, changes, build, workdir)
            for label, dt, changes in arostica_plan(quick)]
    head = ("| mesh | dt [ms] | DOFs | wall [s] | steps (cuts) | Newton / chord | V at rest / "
            "smallest [mL] | p0 largest [mm] (t) | p0 at 480 ms [mm] | p1 largest [mm] (t) | "
            "p1 at 480 ms [mm] | farthest from the participants' mean, p0 / p1 [mm] (t) |")
    lines = [f"## {AROSTICA_TITLE}",
             "Written by `scripts/bench --only arostica` (`--quick`: without level 2, the 0.5 ms "
             "step at level 1 and P2 on the benchmark's mesh): the benchmark's geometry, "
             "fibres, law, viscosity, density, supports and load ODEs, generalized-alpha "
             "(spectral radius 2/3), 1000 ms, 2 ranks. Levels: the generated hexahedral "
             "ventricle (`Geometry / Type = arostica`, Q2, cells curved with the ellipsoids; "
             "'straight edges': `Mapping degree = 1`); 'benchmark mesh': the participants' "
             "shared tetrahedral mesh (`meshes/arostica_benchmark_tet.msh`, element size 5 mm, "
             "flat facets; `Geometry / Gmsh / Shape = arostica` for the fibres). The "
             "displacements of p0 = (25, 30, 0) mm and p1 = (0, 30, 0) mm from their rest "
             "positions; the last column is the largest distance of the run's curve from the "
             "participants' mean curve over their 101 times.", "", head,
             "|" + "---|" * (head.count("|") - 1)]
    lines += [arostica_row(r) for r in rows]
    if any(r.get("busy") for r in rows):
        lines += ["", "\\* The machine was busy during the run: the time is inflated."]
    notes = convergence_notes(rows)
    if notes:
        lines += ["", "Time step and mesh: " + "; ".join(notes) + "."]
    lines += ["", participants_note()]
    return "\n".join(lines) + "\n"


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    text = arostica_section(args.build, workdir, args.quick)
    print(text, flush=True)
    return {AROSTICA_TITLE: text}
