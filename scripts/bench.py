#!/usr/bin/env python3
"""Benchmarks of Systole: refinement studies of the Land et al. 2015 problems.

Runs each case through the systole app (1 or 2 MPI ranks), reads its results file (the
time series, the summary and /statistics: wall time, peak memory, sizes, timer sections,
Newton, Krylov and ARKode counts; no log lines), and writes docs/verification.md. The fibre
generators' costs come from systole-fibres (the rule-based solves it logs; it writes no
results file) and from the hidden unit test [dti-bench] (DTI mapping time per million
points).
Timings are what this machine measured; they are reported, never asserted.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from systole_post.cavities import ventricles  # noqa: E402
from systole_post.results import read_results  # noqa: E402


@dataclass
class Case:
    """One run: a parameter file with some entries replaced."""

    problem: str
    base: str
    label: str
    changes: dict[str, str]
    ranks: int = 2


def with_changes(text: str, changes: dict[str, str]) -> str:
    """Replace 'set NAME = ...' lines (each NAME must occur once in the base file); a key
    'Section/Subsection/NAME' is instead appended as its own subsection block (a later
    value overrides an earlier one)."""
    for key, value in changes.items():
        if "/" in key:
            *sections, entry = key.split("/")
            block = "".join(f"{'  ' * i}subsection {s}\n" for i, s in enumerate(sections))
            block += f"{'  ' * len(sections)}set {entry} = {value}\n"
            block += "".join(f"{'  ' * i}end\n" for i in reversed(range(len(sections))))
            text += "\n" + block
            continue
        pattern = re.compile(rf"^(\s*set {re.escape(key)}\s*=).*$", re.MULTILINE)
        if pattern.search(text):
            text = pattern.sub(rf"\g<1> {value}", text, count=1)
        else:
            raise KeyError(f"no entry '{key}' in the base file")
    return text


def run_watched(command: list[str], cwd: Path, ranks: int) -> tuple[subprocess.CompletedProcess,
                                                                     bool]:
    """Run command; also tell whether other work kept the machine busy meanwhile: the
    1-minute load average, sampled every 5 s while it runs, less its own ranks, exceeds
    one core on average (runs shorter than 5 s are not judged)."""
    process = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    samples = []
    while True:
        try:
            stdout, stderr = process.communicate(timeout=5)
            break
        except subprocess.TimeoutExpired:
            samples.append(os.getloadavg()[0] - ranks)
    busy = bool(samples) and sum(samples) / len(samples) > 1.0
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr), busy


BUSY_NOTE = ("\n\\* The machine was busy during the run (other work used more than one of its "
             f"{os.cpu_count()} cores on average, from the load average): the time is inflated.")


def failed_row(row: dict, out: subprocess.CompletedProcess, path: Path) -> dict:
    """A failed run's row: its error line and, from the results file (which keeps the
    converged steps of a failed run), the last converged pressure, volumes and points."""
    lines = out.stderr.strip().splitlines() or ["?"]
    row["error"] = next((line for line in lines if "error" in line), lines[0])
    if path.exists():
        ts = read_results(path).timeseries
        if "volume" in ts and len(ts["volume"]) > 0:
            row["last_converged"] = {
                "pressure": float(ts["pressure"][-1]),
                "volume": (float(ts["volume"][0]), float(ts["volume"][-1])),
                "values": {k: ts[k][-1] for k in ts if k.endswith(("_x", "_y", "_z"))}}
    return row


def run(case: Case, build: Path, workdir: Path) -> dict:
    """Run one case; return the numbers of its table row."""
    text = (ROOT / "parameters" / case.base).read_text()
    text = with_changes(text, case.changes)
    name = re.sub(r"[^a-z0-9]+", "_", f"{case.problem} {case.label} {case.ranks}".lower())
    prm = workdir / f"{name}.prm"
    prm.write_text(text + f"\nsubsection Output\n  set Run name = {name}\n"
                   "  set Field output interval = 0\nend\n")
    command = [str(build / "systole"), str(prm)]
    if case.ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
                   str(case.ranks)] + command
    out, busy = run_watched(command, workdir, case.ranks)
    row = {"case": case, "ok": out.returncode == 0, "busy": busy}
    if out.returncode != 0:
        return failed_row(row, out, workdir / "results" / name / "results.h5")
    results = read_results(workdir / "results" / name / "results.h5")
    stats = results.statistics
    row["dofs"] = int(stats["n_dofs"])
    row["wall"], row["memory"] = stats["wall_time"], stats["peak_memory_per_rank"]
    ts = results.timeseries
    row["values"] = {k: ts[k][-1] for k in ts if k.endswith(("_x", "_y", "_z"))}
    if "volume" in ts:
        row["volume"] = (float(ts["volume"][0]), float(ts["volume"][-1]))
        row["pressure"] = float(ts["pressure"][-1])
    newton = ts["newton_iterations"][1:]
    row["steps"] = len(newton)
    row["newton"] = int(np.sum(newton))
    row["newton_per_step"] = " ".join(str(int(n)) for n in newton)
    row["cut"] = int(stats["step_cuts"])
    if "chord_iterations" in ts:
        row["chord_per_step"] = " ".join(str(int(n)) for n in ts["chord_iterations"][1:])
    if "discretization" in results.statistics_text:
        row["discretization"] = results.statistics_text["discretization"]
        row["solver"] = results.statistics_text["linear_solver"]
    row["summary"] = {k: float(v[-1]) for k, v in results.summary.items()}
    return row


#: Land problem 2's band (Land et al. 2015, the spread of the published codes) [mm].
P2_BAND = {"endo_apex_z": (-26.9, -26.4), "epi_apex_z": (-28.5, -28.1)}


def p2_band_note(rows: list[dict], element: str | None = None) -> str:
    """Which finished runs lie outside Land problem 2's band, and how far the two largest
    meshes' apexes differ (element: only the rows whose label ends with it, the study of that
    element; the note then names it)."""
    done = sorted((r for r in rows if r["ok"] and
                   (element is None or r["case"].label.endswith(element))),
                  key=lambda r: r["dofs"])
    if not done:
        return ""
    if element is not None:
        return f" {element}:" + p2_band_note(done)
    outside = [f"{r['case'].label} ({r['dofs']} DOFs): {k} {r['values'][k]:.3f} mm"
               for r in done for k, (low, high) in P2_BAND.items()
               if not low <= r["values"][k] <= high]
    text = (" Every level lies inside the band." if not outside else
            " Outside the band: " + "; ".join(outside) + ".")
    if len(done) >= 2:
        a, b = done[-2], done[-1]
        moves = ", ".join(f"{k} {b['values'][k] - a['values'][k]:+.4f} mm" for k in P2_BAND)
        text += f" From {a['dofs']} to {b['dofs']} DOFs: {moves}."
    return text


def table(rows: list[dict], columns: list[str], chords: bool = False) -> str:
    """Markdown table of finished runs (chords: also the chord iterations per step)."""
    head = "| resolution | ranks | DOFs | " + " | ".join(columns) + \
        " | load steps (cuts) | Newton iterations per step | " + \
        ("chord iterations per step | " if chords else "") + \
        "wall [s] | peak memory per rank [MiB] |"
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        c = r["case"]
        if not r["ok"]:
            lines.append(f"| {c.label} | {c.ranks} | failed: {r['error']} |")
            continue
        values = " | ".join(f"{r['values'][k]:.3f}" for k in columns)
        busy = " *" if r.get("busy") else ""
        chord = f"| {r.get('chord_per_step', '-')} " if chords else ""
        lines.append(f"| {c.label} | {c.ranks} | {r['dofs']} | {values} | {r['steps']} ({r['cut']}) "
                     f"| {r['newton_per_step']} {chord}| {r['wall']:.1f}{busy} | {r['memory']:.0f} |")
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    return "\n".join(lines)


#: Ventricles of the fibre-generator costs: Geometry / Ellipsoid entries.
LAND_LV = {}
HUMAN_LV = {"Geometry/Ellipsoid/Endocardium short radius": "23",
            "Geometry/Ellipsoid/Endocardium long radius": "84",
            "Geometry/Ellipsoid/Epicardium short radius": "33",
            "Geometry/Ellipsoid/Epicardium long radius": "92",
            "Geometry/Ellipsoid/Cells around circumference": "16",
            "Geometry/Ellipsoid/Cells from apex to base": "5"}

FIBRES_PRM = """subsection Geometry
  set Type               = ellipsoid
  set Global refinements = 0
end

subsection Fibres
  set Generator = rule-based
end
"""

def run_fibres(label: str, changes: dict[str, str], build: Path, workdir: Path,
               ranks: int = 2) -> dict:
    """systole-fibres with the rule-based generator; the cost of the wall coordinates' solves
    from /statistics of its results file."""
    name = re.sub(r"[^a-z0-9]+", "_", f"fibres {label} {ranks}".lower())
    prm = workdir / f"{name}.prm"
    prm.write_text(with_changes(FIBRES_PRM, changes)
                   + f"\nsubsection Output\n  set Run name = {name}\nend\n")
    command = [str(build / "systole-fibres"), str(prm)]
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    start = time.monotonic()
    out, busy = run_watched(command, workdir, ranks)
    row = {"label": label, "ranks": ranks, "ok": out.returncode == 0,
           "wall": time.monotonic() - start, "busy": busy}
    st = {}
    if out.returncode == 0:
        st = read_results(workdir / "results" / name / "results.h5").statistics
    if out.returncode != 0 or "n_dofs" not in st:
        row["ok"] = False
        row["error"] = (out.stderr.strip().splitlines() or ["no /statistics in its results"])[0]
        return row

    def solver(which: str) -> tuple[str, float]:
        text = "MUMPS (CG failed)" if st[f"{which}_direct"] else \
            f"{int(st[f'{which}_iterations'])} CG iterations"
        return text, st[f"{which}_seconds"]

    row.update(cells=int(st["n_cells"]), degree=int(st["degree"]), dofs=int(st["n_dofs"]),
               transmural=solver("transmural"), apicobasal=solver("apicobasal"),
               setup=st["setup_seconds"], tangled=st["tangled_cells"] > 0)
    return row


def run_dti_bench(build: Path) -> dict:
    """The hidden unit test [dti-bench]: its timing lines."""
    out, busy = run_watched([str(build / "tests" / "systole-unit"), "[dti-bench]"], ROOT, 1)
    text = out.stdout
    row = {"ok": out.returncode == 0, "busy": busy}
    for where in ("wall", "box"):
        match = re.search(rf"10\^6 queries in the {where} took ([\d.]+) s wall, ([\d.]+) s CPU "
                          r"\(([\d.]+) % rejected", text)
        if not match:
            row["ok"] = False
            continue
        row[where] = tuple(float(x) for x in match.groups())
    match = re.search(r"reading (\d+) x (\d+) x (\d+) voxels and precomputing the logs took "
                      r"([\d.]+) s", text)
    if match:
        row["voxels"] = " x ".join(match.group(i) for i in (1, 2, 3))
        row["read"] = float(match.group(4))
    else:
        row["ok"] = False
    return row


def fibre_section(rows: list[dict], dti: dict) -> str:
    """The section 'Fibre generators'."""
    lines = [
        "## Fibre generators",
        "Rule-based (Bayer et al. 2012): the two solves of `Fibres::WallCoordinates` (Q2, "
        "MappingQ2, PETSc CG + BoomerAMG), from /statistics of the results file of "
        "`systole-fibres` (the helix-angle profile's own pair of solves, the same as the "
        "generator's; its total wall time holds both pairs, the frames at 5 x 5 x 5 points per "
        "cell and the output). Land ventricle: endocardium 7/17 mm, epicardium 10/20 mm "
        "(short/long radius); human-size: 23/84 and 33/92 mm.",
        "",
        "| ventricle | ranks | cells | DOFs per solve | transmural | apicobasal | set-up [s] "
        "| systole-fibres wall [s] |",
        "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['label']} | {r['ranks']} | failed: {r['error']} |")
            continue
        solve = lambda s: f"{s[1]:.2f} s ({s[0]})"  # noqa: E731
        lines.append(f"| {r['label']} | {r['ranks']} | {r['cells']} | {r['dofs']} "
                     f"| {solve(r['transmural'])} | {solve(r['apicobasal'])} | {r['setup']:.2f} "
                     f"| {r['wall']:.1f}{' *' if r['busy'] else ''} |")
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    lines.append("")
    if dti.get("ok"):
        wall, box = dti["wall"], dti["box"]
        lines.append(
            "DTI (`Fibres::DTIField`, one rank; the hidden unit test `systole-unit \"[dti-bench]\"`, "
            f"synthetic Land image of {dti['voxels']} voxels at 0.5 mm): reading the image and "
            f"precomputing log D took {dti['read']:.2f} s; 10^6 points in the wall (each a "
            "log-Euclidean interpolation of 8 voxels and one 3 x 3 eigen-decomposition) took "
            f"{wall[0]:.2f} s ({wall[1]:.2f} s CPU), 10^6 points in the box around it "
            f"({box[2]:.0f} % rejected: outside the data or isotropic, a second eigen-"
            f"decomposition for the fallback frame) {box[0]:.2f} s. The mechanics asks for "
            "27 points per Q2 cell, so 10^6 points are 37 000 cells."
            + (" (The machine was busy meanwhile: the times are inflated.)" if dti["busy"] else ""))
    else:
        lines.append("DTI mapping benchmark: failed (run `systole-unit \"[dti-bench]\"`).")
    return "\n".join(lines) + "\n"


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


#: Land problem 1 (C = 2 kPa) with the formulations and solvers of the 'mixed' group.
MIXED_FORMULATIONS = [
    ("incompressible, direct", {"Material/Incompressibility": "incompressible",
                                "Mechanics/Linear solver": "direct"}),
    ("incompressible, iterative", {"Material/Incompressibility": "incompressible",
                                   "Mechanics/Linear solver": "iterative"}),
    ("penalty, direct", {"Material/Incompressibility": "penalty",
                         "Material/Volumetric/Bulk modulus": "1000",
                         "Mechanics/Volumetric integration": "reduced",
                         "Mechanics/Linear solver": "direct"})]
MIXED_KAPPA = ["200", "20000", "2000000"]
MIXED_C = 2.0


def value_cell(values: dict) -> str:
    """The benchmark value of a run: the beam tip z (problem 1) or both apexes (problem 2)."""
    if "beam_tip_z" in values:
        return f"{values['beam_tip_z']:.4f}"
    return f"{values['endo_apex_z']:.3f} / {values['epi_apex_z']:.3f}"


def mixed_cells(r: dict) -> str:
    """The columns of a mixed-group row from the formulation on (its run banner, /summary row,
    last beam_tip_z, log)."""
    s = r["summary"]
    busy = " *" if r.get("busy") else ""
    per_dof = 1e6 * (s["assembly_seconds"] + s["linear_solver_seconds"]) / \
        max(1.0, s["newton_iterations"]) / s["n_dofs"]
    return (f"{r.get('discretization', '?')} | {r.get('solver', '?')} "
            f"| {s['n_dofs']:.0f} ({s['n_displacement_dofs']:.0f} + {s['n_pressure_dofs']:.0f}) "
            f"| {value_cell(r['values'])} | {s['load_steps']:.0f} | {s['step_cuts']:.0f} "
            f"| {s['newton_iterations']:.0f} | {s.get('chord_iterations', 0):.0f} "
            f"| {s['linear_iterations_per_solve']:.1f} "
            f"| {s['assembly_seconds']:.2f}{busy} | {s['linear_solver_seconds']:.2f}{busy} "
            f"| {per_dof:.2f}{busy} | {r['wall']:.1f}{busy} | {r['memory']:.0f} |")


MIXED_HEAD = ("formulation | solver | DOFs (u + p) | beam tip z [mm] | load steps | step cuts "
              "| Newton iterations (new tangents) | chord iterations "
              "| Krylov iterations per solve | assembly [s] "
              "| linear solver [s] | (assembly + solver) per Newton iteration per DOF [µs] "
              "| wall [s] | peak memory per rank [MiB] |")


def mixed_table(rows: list[tuple[str, dict]], first: str,
                value: str = "beam tip z [mm]") -> str:
    """Markdown table of (first column, row) pairs."""
    head = f"| {first} | " + MIXED_HEAD.replace("beam tip z [mm]", value)
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for label, r in rows:
        if not r["ok"]:
            lines.append(f"| {label} | failed: {r['error']} |")
            continue
        lines.append(f"| {label} | " + mixed_cells(r))
    if any(r.get("busy") for _, r in rows):
        lines.append(BUSY_NOTE)
    return "\n".join(lines)


def mixed_section(build: Path, workdir: Path, quick: bool) -> str:
    """Land problem 1 refined 1, 2 (and 3) times with the incompressible mixed formulation
    (direct and iterative solvers) and the penalty (direct), and a bulk-modulus sweep of the
    nearly incompressible formulation (iterative) at 1 refinement."""
    levels = [1, 2] + ([] if quick else [3])
    series = {}
    for formulation, changes in MIXED_FORMULATIONS:
        for r in levels:
            case = Case("mixed", "land_problem1.prm", f"{formulation}, {r} refinement(s)",
                        {"Global refinements": str(r), **changes})
            print(f"running Land problem 1, {case.label} on {case.ranks} rank(s) ...", flush=True)
            series.setdefault(formulation, []).append((r, run(case, build, workdir)))
    rows = [(f"{r}", row) for formulation, _ in MIXED_FORMULATIONS
            for r, row in series[formulation]]

    growth = []
    for formulation, runs in series.items():
        done = [(r, row) for r, row in runs if row["ok"]]
        if "iterative" not in formulation or len(done) < 2:
            continue
        (r0, coarse), (r1, fine) = done[0], done[-1]
        k0 = coarse["summary"]["linear_iterations_per_solve"]
        k1 = fine["summary"]["linear_iterations_per_solve"]
        n0, n1 = coarse["summary"]["n_dofs"], fine["summary"]["n_dofs"]
        plural = lambda n: f"{n} refinement{'' if n == 1 else 's'}"  # noqa: E731
        growth.append(f"With {formulation}, the Krylov iterations per solve grow from {k0:.1f} "
                      f"({plural(r0)}, {n0:.0f} DOFs) to {k1:.1f} ({plural(r1)}, {n1:.0f} "
                      f"DOFs): a ratio of {k1 / k0:.2f} for {n1 / n0:.1f} times the DOFs.")

    sweep = []
    for kappa in MIXED_KAPPA:
        case = Case("mixed", "land_problem1.prm", f"nearly incompressible, kappa = {kappa} kPa",
                    {"Global refinements": "1",
                     "Material/Incompressibility": "nearly incompressible",
                     "Material/Volumetric/Bulk modulus": kappa,
                     "Mechanics/Linear solver": "iterative"})
        print(f"running Land problem 1, {case.label} on {case.ranks} rank(s) ...", flush=True)
        power = lambda x: f"{x:.0e}".replace("e+0", "e")  # noqa: E731
        sweep.append((f"{power(float(kappa))} | {power(float(kappa) / MIXED_C)}",
                      run(case, build, workdir)))
    # The incompressible end of the sweep is the iterative run at 1 refinement above.
    sweep += [("∞ | ∞", row) for r, row in series["incompressible, iterative"] if r == 1]
    done = [row for _, row in sweep if row["ok"]]
    if len(done) >= 2:
        k0 = done[0]["summary"]["linear_iterations_per_solve"]
        k1 = done[-1]["summary"]["linear_iterations_per_solve"]
        growth.append(f"In the sweep below, from the smallest bulk modulus to the incompressible "
                      f"limit, the Krylov iterations per solve go from {k0:.1f} to {k1:.1f} "
                      f"(ratio {k1 / k0:.2f}).")

    # Land problem 2 on the shipped 16 x 5 ventricle and refined once: the shipped penalty file
    # and the incompressible mixed formulation in 10 equal load steps.
    p2_rows = []
    for label, changes in (
            ("penalty (shipped file)", {}),
            ("incompressible, 10 equal load steps",
             {"Material/Incompressibility": "incompressible", "Load steps": "10",
              "Mechanics/Adaptive load steps": "false"}),
            ("incompressible, 10 equal load steps, pure Newton",
             {"Material/Incompressibility": "incompressible", "Load steps": "10",
              "Mechanics/Adaptive load steps": "false",
              "Mechanics/Reuse factorization": "false"})):
        for r in [0] + ([] if quick else [1]):
            case = Case("mixed", "land_problem2.prm", f"{label}, {r} refinement(s)",
                        {"Global refinements": str(r), **changes})
            print(f"running Land problem 2, {case.label} on {case.ranks} rank(s) ...", flush=True)
            p2_rows.append((f"{label}, {r}", run(case, build, workdir)))

    title = "Mechanics: penalty and mixed formulations, direct and iterative solvers"
    return (
        f"## {title}\n"
        "Land problem 1 (`parameters/land_problem1.prm`: the beam, 10 x 1 x 1 coarse cells "
        "refined globally, Guccione C = 2 kPa, Q2, first load increment 1/10, then adaptive), "
        "2 ranks: the incompressible "
        "mixed formulation (the shipped file: Q2-P1disc, full Gauss rule) with the direct "
        "solver (MUMPS) and with the iterative one (FGMRES with the PETSc fieldsplit Schur "
        "block preconditioner), and the penalty formulation of the file before it (bulk "
        "modulus 1000 kPa, selective reduced integration) with the direct solver. The "
        "formulation and the solver are those the run banner names; the sizes, counts and "
        "times are the run's /summary row (assembly and linear solver: rank 0's wall time in "
        "those timer sections; Krylov iterations per solve: linear iterations over Newton "
        "and chord solves, the direct solver counts 1); time per Newton iteration per DOF = "
        "(assembly + linear solver) / Newton iterations (new tangents) / DOFs; chord "
        "iterations: updates on a factorization of an earlier iteration (Mechanics / Reuse "
        "factorization). Beam tip z: the deformed z of (10, 0.5, 1) "
        "at the last load step (reference 4.17 mm, converged codes 4.151 ... 4.185 mm).\n\n"
        + mixed_table(rows, "refinements") + "\n\n" + " ".join(growth) + "\n\n"
        "Bulk modulus sweep at 1 refinement: the nearly incompressible mixed formulation "
        "(Q2-P1disc, energy -p (J - 1) - p^2 / (2 kappa)) with the iterative solver, and the "
        "incompressible one (1/kappa = 0; the run of the table above).\n\n"
        + mixed_table(sweep, "kappa [kPa] | kappa / C") + "\n\n"
        "Land problem 2 (`parameters/land_problem2.prm`, the 16 x 5 ventricle, Q2, direct "
        "solver), refined 0 (and 1) times: the shipped penalty file and the incompressible mixed "
        "formulation (isochoric part of the Guccione law) in 10 equal load steps, with the "
        "default modified Newton and with pure Newton (Reuse factorization = false). Reference: "
        "endocardial apex -26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm (-28.5 ... "
        "-28.1).\n\n"
        + mixed_table(p2_rows, "formulation, refinements", "endo / epi apex z [mm]") + "\n")


#: The "scaling" group: Land problem 2 (C = 10 kPa) with the iterative solver on meshes from
#: 2.7k to 511k DOFs. (label, coarse cells around, from apex to base, global refinements).
SCALING_LEVELS = [("16x5, 0", 16, 5, 0), ("16x5, 1", 16, 5, 1), ("16x5, 2", 16, 5, 2),
                  ("32x10, 0", 32, 10, 0), ("32x10, 1", 32, 10, 1), ("32x10, 2", 32, 10, 2)]
#: The level the cost ratios refer to (issue 11: "from 16k to >= 500k DOFs").
SCALING_REFERENCE = "16x5, 1"
SCALING_C = 10.0
#: Formulations: (label, entries). Every one with the iterative solver (default
#: displacement preconditioner, the p-multigrid).
SCALING_FORMULATIONS = [
    ("incompressible", {"Material/Incompressibility": "incompressible"}),
    ("kappa/C = 1e2", {"Material/Incompressibility": "nearly incompressible",
                       "Material/Volumetric/Bulk modulus": "1000"}),
    ("kappa/C = 1e4", {"Material/Incompressibility": "nearly incompressible",
                       "Material/Volumetric/Bulk modulus": "100000"}),
    ("kappa/C = 1e6", {"Material/Incompressibility": "nearly incompressible",
                       "Material/Volumetric/Bulk modulus": "10000000"}),
    ("penalty, kappa/C = 1e2", {"Material/Incompressibility": "penalty"}),
]
#: Which formulations run at which level (None: all): the penalty, whose second Newton
#: iteration of a load step takes hundreds of Krylov iterations (and the second step a cut),
#: up to 16x5 refined once, the mixed ones on both mesh families up to 129k DOFs, two of them
#: at 511k (the long runs). --quick: the two coarsest levels.
SCALING_MIXED = [label for label, _ in SCALING_FORMULATIONS[:4]]
SCALING_PLAN = {"16x5, 0": None, "16x5, 1": None, "16x5, 2": SCALING_MIXED,
                "32x10, 0": SCALING_MIXED, "32x10, 1": SCALING_MIXED,
                "32x10, 2": ["incompressible", "kappa/C = 1e6"]}
#: The problem: the first two of ten equal load steps of Land problem 2 (2 kPa of 10) with
#: pure Newton (a new tangent and preconditioner at every iteration), the same at every
#: level, so that the largest run stays affordable. (The first step alone hides the hard
#: solve: the second iteration of the second step.)
SCALING_PROBLEM = {"Pressure": "2", "Load steps": "2",
                   "Mechanics/Adaptive load steps": "false",
                   "Mechanics/Reuse factorization": "false",
                   "Mechanics/Linear solver": "iterative"}


#: The "scaling-th" group: the same problem with the Taylor-Hood element (Discretization /
#: Pressure element = continuous), whose iterative solver has no augmented Lagrangian. The
#: levels of the scaling group and 32 x 11 refined twice, the first above 500k DOFs with Q2-Q1
#: (32 x 10 refined twice has 467k).
SCALING_TH = {"Discretization/Pressure element": "continuous"}
SCALING_TH_FORMULATIONS = [(f"{label}, Q2-Q1", {**entries, **SCALING_TH})
                           for label, entries in SCALING_FORMULATIONS
                           if label in ("incompressible", "kappa/C = 1e2", "kappa/C = 1e6")]
SCALING_TH_LEVELS = SCALING_LEVELS + [("32x11, 2", 32, 11, 2)]
SCALING_TH_PLAN = {"32x10, 2": ["incompressible, Q2-Q1"], "32x11, 2": ["incompressible, Q2-Q1"]}
SCALING_TITLE = "Mechanics: the iterative solver from 2.7k to 511k DOFs (Land problem 2, 2 ranks)"
SCALING_TH_TITLE = ("Mechanics: the iterative solver with the Taylor-Hood element (Land problem 2, "
                    "2 ranks)")


#: The "large" group: the shipped files of Land problems 1 and 3 (incompressible, Q2-P1disc)
#: on meshes above 500k DOFs, with the `auto` linear solver (iterative there). The beam: 30 x 3
#: x 3 coarse cells refined twice (120 x 12 x 12 cells, 521k DOFs); the ventricle: 32 x 10
#: coarse cells refined twice, without the file's local refinement at the apex (511k DOFs).
LARGE_TITLE = "Land problems 1 and 3 above 500k DOFs (2 ranks)"
LARGE_CASES = [
    ("Land problem 1, 30x3x3 cells, 2 refinements",
     Case("large", "land_problem1.prm", "30x3x3 cells, 2 refinements, Q2-P1disc",
          {"Global refinements": "2", "Geometry/Box/Cells": "30, 3, 3"})),
    ("Land problem 3, 32x10x1 cells, 2 refinements",
     Case("large", "land_problem3.prm", "32x10x1 cells, 2 refinements, Q2-P1disc",
          {"Global refinements": "2", "Geometry/Ellipsoid/Cells around circumference": "32",
           "Geometry/Ellipsoid/Cells from apex to base": "10",
           "Geometry/Local refinements": "0"})),
]
#: Land problem 1's band (Land et al. 2015, the converged codes) [mm].
P1_BAND = (4.151, 4.185)


def large_section(build: Path, workdir: Path) -> str:
    """The shipped Land problems 1 and 3 above 500k DOFs."""
    rows = []
    for label, case in LARGE_CASES:
        print(f"running {label} on {case.ranks} rank(s) ...", flush=True)
        rows.append((label, run(case, build, workdir)))
    return large_text(rows)


def large_text(rows: list[tuple[str, dict]]) -> str:
    """The large group's section from its (label, row) pairs."""
    notes = []
    for label, r in rows:
        if not r["ok"] or "beam_tip_z" not in r["values"]:
            continue
        tip, (low, high) = r["values"]["beam_tip_z"], P1_BAND
        where = "inside" if low <= tip <= high else "outside"
        notes.append(f"{label}: the beam tip at {tip:.4f} mm, {where} the band "
                     f"{low} ... {high} mm.")
    return (
        f"## {LARGE_TITLE}\n"
        "Written by `scripts/bench --only large`. The shipped `parameters/land_problem1.prm` and "
        "`parameters/land_problem3.prm` (incompressible, mixed Q2-P1disc, their load steps and "
        "Newton settings) on the finest meshes of the refinement studies: the beam of 30 x 3 x 3 "
        "coarse cells refined twice (120 x 12 x 12 cells) and the ventricle of 32 x 10 coarse "
        "cells refined twice without the file's local refinement at the apex, 2 ranks, the "
        "`auto` linear solver (iterative above 200 000 DOFs). Problem 1: the deformed z of the "
        "beam tip (10, 0.5, 1); problem 3: the deformed z of the endocardial and epicardial "
        "apex, whose values depend on the level of the cells at the apex points (sections "
        "\"Land problem 3: refined at each apex\" and \"Land problem 3: the fibre field on the "
        "axis\"). Time per Newton iteration per DOF = (assembly + linear solver) / Newton "
        "iterations / DOFs." + (" " + " ".join(notes) if notes else "") + "\n\n"
        + mixed_table(rows, "problem, mesh",
                      value="beam tip z or endo / epi apex z [mm]") + "\n")


def run_scaling(level: tuple, formulation: tuple, build: Path, workdir: Path) -> dict:
    """One run of the scaling group; also the CPU time of its processes (the children's
    rusage) and the load average at its end."""
    label, a, b, r = level
    changes = {"Global refinements": str(r),
               "Geometry/Ellipsoid/Cells around circumference": str(a),
               "Geometry/Ellipsoid/Cells from apex to base": str(b),
               **SCALING_PROBLEM, **formulation[1]}
    case = Case("scaling", "land_problem2.prm", f"{label}, {formulation[0]}", changes)
    print(f"running Land problem 2, {case.label} on {case.ranks} rank(s) ...", flush=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = run(case, build, workdir)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row["cpu"] = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    row["load"] = os.getloadavg()
    row["level"], row["formulation"] = label, formulation[0]
    return row


def scaling_cells(r: dict, reference: dict | None) -> str:
    """The columns of a scaling row from DOFs on."""
    s = r["summary"]
    busy = " *" if r.get("busy") else ""
    n = max(1.0, s["newton_iterations"])
    per_it = (s["assembly_seconds"] + s["linear_solver_seconds"]) / n
    per_dof = 1e6 * per_it / s["n_dofs"]
    ratio = "-"
    if reference is not None:
        rs = reference["summary"]
        ref = 1e6 * (rs["assembly_seconds"] + rs["linear_solver_seconds"]) / \
            max(1.0, rs["newton_iterations"]) / rs["n_dofs"]
        ratio = f"{per_dof / ref:.2f}"
    cpu_per_dof = 1e6 * r["cpu"] / n / s["n_dofs"]
    memory_per_dof = 2 * r["memory"] * 2**20 / s["n_dofs"] / 1024
    return (f"{s['n_dofs']:.0f} ({s['n_displacement_dofs']:.0f} + {s['n_pressure_dofs']:.0f}) "
            f"| {s['newton_iterations']:.0f} ({s['step_cuts']:.0f}) "
            f"| {s['linear_iterations_per_solve']:.1f} "
            f"| {s['assembly_seconds'] / n:.2f}{busy} | {s['linear_solver_seconds'] / n:.2f}{busy} "
            f"| {per_it:.2f}{busy} | {per_dof:.1f}{busy} | {ratio} | {cpu_per_dof:.1f} "
            f"| {r['memory']:.0f} | {memory_per_dof:.1f} | {r['load'][0]:.1f} |")


SCALING_HEAD = ("| level (coarse cells, refinements) | formulation | DOFs (u + p) "
                "| Newton iterations (step cuts) | Krylov iterations per solve "
                "| assembly per Newton iteration [s] | linear solver per Newton iteration [s] "
                "| (assembly + solver) per Newton iteration [s] "
                "| per Newton iteration per DOF [µs] | ratio to 16x5, 1 "
                "| CPU time of the run per Newton iteration per DOF [µs] "
                "| peak memory per rank [MiB] | 2 x peak memory per rank per DOF [KiB] "
                "| load average at the end |")


def scaling_section(build: Path, workdir: Path, quick: bool, th: bool = False) -> str:
    """Land problem 2 with the iterative solver at 2.7k ... 511k DOFs, mixed and penalty
    (th: the scaling-th group, the Taylor-Hood element at 2.6k ... 525k DOFs)."""
    levels = SCALING_TH_LEVELS if th else SCALING_LEVELS
    formulations = SCALING_TH_FORMULATIONS if th else SCALING_FORMULATIONS
    plan = SCALING_TH_PLAN if th else SCALING_PLAN
    rows = []
    for level in levels[:2] if quick else levels:
        for formulation in formulations:
            chosen = plan.get(level[0])
            if chosen is None or formulation[0] in chosen:
                rows.append(run_scaling(level, formulation, build, workdir))
    return scaling_text(rows, th)


def scaling_growth(rows: list[dict], formulations: list | None = None) -> list[str]:
    """Per formulation, the growth of the Krylov iterations per solve from the coarsest to
    the finest level run, over all levels and within each coarse mesh (a family of global
    refinements of one mesh: the label's part before the comma)."""
    growth = []
    for formulation, _ in formulations or SCALING_FORMULATIONS:
        done = [r for r in rows if r["formulation"] == formulation and r["ok"]]
        done.sort(key=lambda r: r["summary"]["n_dofs"])
        families = {}
        for r in done:
            families.setdefault(r["level"].split(",")[0], []).append(r)
        groups = [("", done)] + [(f" on {name}", members) for name, members
                                 in families.items() if len(families) > 1]
        for where, members in groups:
            if len(members) < 2:
                continue
            k = [r["summary"]["linear_iterations_per_solve"] for r in members]
            n0, n1 = members[0]["summary"]["n_dofs"], members[-1]["summary"]["n_dofs"]
            growth.append(f"{formulation}{where}: {k[0]:.1f} -> {k[-1]:.1f} Krylov iterations "
                          f"per solve from {n0:.0f} to {n1:.0f} DOFs "
                          f"({100 * (k[-1] / k[0] - 1):+.0f} %).")
    return growth


def scaling_text(rows: list[dict], th: bool = False) -> str:
    """The scaling section from the rows of run_scaling (th: the scaling-th group's)."""
    formulations = SCALING_TH_FORMULATIONS if th else SCALING_FORMULATIONS
    reference = {r["formulation"]: r for r in rows
                 if r["level"] == SCALING_REFERENCE and r["ok"]}
    lines = [SCALING_HEAD, "|" + "---|" * (SCALING_HEAD.count("|") - 1)]
    for formulation, _ in formulations:
        for r in rows:
            if r["formulation"] != formulation:
                continue
            if not r["ok"]:
                lines.append(f"| {r['level']} | {formulation} | failed: {r['error']} |")
                continue
            lines.append(f"| {r['level']} | {formulation} | "
                         + scaling_cells(r, reference.get(formulation)))
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)

    growth = scaling_growth(rows, formulations)
    for level, *_ in SCALING_TH_LEVELS if th else SCALING_LEVELS:
        done = [r for r in rows if r["level"] == level and r["ok"]
                and r["formulation"] != "penalty, kappa/C = 1e2"]
        if len(done) >= 2:
            k = [r["summary"]["linear_iterations_per_solve"] for r in done]
            growth.append(f"At {level} over the mixed formulations: {min(k):.1f} ... {max(k):.1f} "
                          "per solve.")
    solver = next((r["solver"] for r in rows if r.get("solver")), "?")
    title = SCALING_TH_TITLE if th else SCALING_TITLE
    group = "scaling-th" if th else "scaling"
    th_text = ("The Taylor-Hood element (`Discretization / Pressure element = continuous`, "
               "Q2-Q1), whose iterative solver has no augmented Lagrangian, on the levels "
               "of the scaling group above and on 32 x 11 cells refined twice (the first "
               "level above 500k DOFs with Q2-Q1). " if th else "")
    return (
        f"## {title}\n"
        f"Written by `scripts/bench --only {group}` (`--quick`: the two coarsest levels). "
        + th_text + "Land "
        "problem 2 (`parameters/land_problem2.prm`, C = 10 kPa) on the ventricle of 16 x 5 "
        "coarse cells and of 32 x 10 cells, each refined 0, 1, 2 times, 2 ranks, the "
        "iterative solver (" + solver
        + ("" if th else "; the penalty: FGMRES with the same p-multigrid on K")
        + "). The problem is the first two of ten equal load steps (2 kPa of the 10 kPa) "
        "with pure Newton (`Reuse factorization = false`: a new tangent and preconditioner "
        "set-up at every iteration), the same at every level, so that the largest run stays affordable; "
        "the per-iteration figures come from its real Newton iterations. Assembly and linear "
        "solver: rank 0's wall time in those timer sections (`/summary`), over the Newton "
        "iterations; the ratio is that of the time per Newton iteration per DOF to the 16 x 5 "
        f"level refined once ({'16.7k DOFs' if th else '17.9k DOFs mixed'}) of the same "
        "formulation. The CPU time is that "
        "of all processes of the run (set-up included), less sensitive to the other work on "
        "the machine than the wall times; the load average is the 1-minute one when the run "
        "ended (2 cores: above 2 the wall times are inflated).\n\n"
        + "\n".join(lines) + "\n\n" + " ".join(growth) + "\n")


#: The isotropic laws of the "laws" group, at the small-strain shear modulus of the isotropic
#: Guccione law of Land problem 2 (C/2 = 5 kPa): (law, entries of its subsection, the shear
#: modulus in its parameters). The unit test "Each isotropic law has the small-strain shear
#: modulus its documentation states" checks these sets.
LAWS_SHEAR_MODULUS = 5.0
ISOTROPIC_LAWS = [
    ("Guccione", {"C": "10", "b_f": "1", "b_t": "1", "b_fs": "1"}, "C/2"),
    ("neo-Hookean", {"mu": "5"}, "mu"),
    ("Mooney-Rivlin", {"c1": "2", "c2": "0.5"}, "2 (c1 + c2)"),
    ("Fung isotropic", {"mu": "10", "gamma": "0.5"}, "mu gamma"),
    ("Veronda-Westman", {"c1": "10", "gamma": "0.5"}, "c1 gamma"),
]
#: The small pressures [kPa] of the "laws" group's second table.
LAWS_SMALL_PRESSURES = ["0.01", "0.1"]
#: Formulations of the "laws" group: the shipped penalty file, and the incompressible mixed
#: formulation in 10 equal load steps (as in the mixed group).
LAWS_FORMULATIONS = [
    ("penalty, kappa = 1000 kPa", {}),
    ("incompressible, Q2-P1disc", {"Material/Incompressibility": "incompressible",
                                   "Load steps": "10",
                                   "Mechanics/Adaptive load steps": "false"}),
]


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


def laws_section(build: Path, workdir: Path) -> str:
    """Land problem 2 with each isotropic law at the same small-strain shear modulus: apex
    positions and cavity volume at 10 kPa, penalty and incompressible mixed. A run that stops
    short of 10 kPa (a limit point of the pressure-volume curve: no equilibrium under a
    larger pressure) is reported at its last converged pressure."""
    lines = ["| law | parameters [kPa, -] | formulation | DOFs | pressure reached [kPa] "
             "| endo apex z [mm] | endo apex displacement [mm] | epi apex z [mm] "
             "| cavity volume [mm³] | volume change [%] | load steps (cuts) "
             "| Newton iterations | wall [s] |"]
    lines.append("|" + "---|" * (lines[0].count("|") - 1))
    busy = False
    undeformed = []
    stopped = []
    for law, entries, modulus in ISOTROPIC_LAWS:
        changes = {"Passive law": law}
        changes.update({f"Material/{law}/{k}": v for k, v in entries.items()})
        text = ", ".join(f"{k} = {v}" for k, v in entries.items()) + \
            f" ({modulus} = {LAWS_SHEAR_MODULUS:g})"
        for formulation, extra in LAWS_FORMULATIONS:
            case = Case("laws", "land_problem2.prm", f"{law}, {formulation}",
                        {**changes, **extra})
            print(f"running Land problem 2, {case.label} on {case.ranks} rank(s) ...",
                  flush=True)
            r = run(case, build, workdir)
            state = r if r["ok"] else r.get("last_converged")
            if state is None:
                lines.append(f"| {law} | {text} | {formulation} | failed: {r['error']} |")
                continue
            v = state["values"]
            v0, v1 = state["volume"]
            undeformed.append(v0)
            cells = (f"| {state['pressure']:.3g} | {v['endo_apex_z']:.3f} "
                     f"| {v['endo_apex_z'] + 17.0:.3f} | {v['epi_apex_z']:.3f} | {v1:.1f} "
                     f"| {100.0 * (v1 / v0 - 1.0):.1f} |")
            if r["ok"]:
                assert abs(r["pressure"] - 10.0) < 1e-9, "the run did not reach 10 kPa"
                busy = busy or r["busy"]
                mark = " *" if r["busy"] else ""
                lines.append(f"| {law} | {text} | {formulation} | {r['dofs']} {cells} "
                             f"{r['steps']} ({r['cut']}) | {r['newton']} "
                             f"| {r['wall']:.1f}{mark} |")
            else:
                stopped.append(f"{law} ({formulation})")
                lines.append(f"| {law} | {text} | {formulation} | {cells} stopped † | | |")
    if busy:
        lines.append(BUSY_NOTE)
    if stopped:
        lines.append("\n† Stopped short of 10 kPa (the load step could not be cut further): "
                     "without exponential stiffening, at this shear modulus the cavity keeps "
                     "growing under a pressure that hardly rises, or falls (a limit point of the "
                     "pressure-volume curve: the inflation instability of a rubber balloon), so "
                     "pressure-controlled loading finds no equilibrium; the row is the last "
                     "converged state: " + ", ".join(stopped) + ".")
    v0 = f"{undeformed[0]:.1f}" if undeformed else "?"

    # At small pressures every law is close to linear: the same shear modulus must give about
    # the same response (a check of the matched parameters).
    small = ["| law | " + " | ".join(
        f"endo apex displacement at {p} kPa [mm] | epi apex displacement at {p} kPa [mm] "
        f"| volume change at {p} kPa [%]" for p in LAWS_SMALL_PRESSURES) + " |"]
    small.append("|" + "---|" * (small[0].count("|") - 1))
    for law, entries, _ in ISOTROPIC_LAWS:
        cells = []
        for pressure in LAWS_SMALL_PRESSURES:
            changes = {"Passive law": law, "Pressure": pressure}
            changes.update({f"Material/{law}/{k}": v for k, v in entries.items()})
            case = Case("laws", "land_problem2.prm", f"{law}, {pressure} kPa", changes)
            print(f"running Land problem 2, {case.label} on {case.ranks} rank(s) ...",
                  flush=True)
            r = run(case, build, workdir)
            if not r["ok"]:
                cells.append(f"failed: {r['error']} | |")
                continue
            v = r["values"]
            volume0, volume1 = r["volume"]
            cells.append(f"{v['endo_apex_z'] + 17.0:.3e} | {v['epi_apex_z'] + 20.0:.3e} "
                         f"| {100.0 * (volume1 / volume0 - 1.0):.4f}")
        small.append(f"| {law} | " + " | ".join(cells) + " |")
    return (
        "## Land problem 2 with the isotropic laws at the same shear modulus\n"
        "`parameters/land_problem2.prm` (the 16 x 5 ventricle, Q2, direct solver, 10 kPa "
        "endocardial pressure, 2 ranks) with its law replaced by each isotropic law at the "
        f"small-strain shear modulus mu0 = {LAWS_SHEAR_MODULUS:g} kPa of the shipped isotropic "
        "Guccione law (C/2, C = 10 kPa); the formula in parentheses is mu0 in the law's "
        "parameters. Fung isotropic and Veronda-Westman use gamma = 1/2, the exponent that "
        "matches the Guccione exponent E:E to leading order (Ibar1 - 3 = 2 E:E + O(|E|^3) for an "
        "isochoric deformation). Formulations: the shipped penalty file (bulk modulus 1000 kPa, "
        "the file's adaptive load steps) and the incompressible mixed formulation in 10 equal "
        "load steps. Endocardial apex displacement: its deformed z less the reference -17 mm; "
        "cavity volume: the endocardium closed by the base plane (undeformed "
        f"{v0} mm³ on this mesh, exact 2492.13 mm³), and its change. Reference for Guccione: "
        "endocardial apex -26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm (-28.5 ... "
        "-28.1).\n\n" + "\n".join(lines) + "\n\n"
        "The same laws (penalty) at small pressures, where the matched shear modulus should "
        "give nearly the same response. The apex displacement is a small difference of wall "
        "thinning and elongation, so it is nonlinear already at these loads, and the laws part "
        "as the pressure grows, in two pairs whose energies agree to second order in the "
        "Green-Lagrange strain E: Veronda-Westman with gamma = 1/2 and the isotropic Guccione "
        "law (c1 (e^{gamma (I1 - 3)} - 1) - c1 gamma/2 (I2 - 3) = c1 gamma E:E + c1 gamma "
        "(2 gamma - 1) (tr E)^2 + O(|E|^3), since I1 - 3 = 2 tr E and I2 - 3 = 4 tr E "
        "+ 2 (tr E)^2 - 2 E:E), and Fung isotropic and neo-Hookean (mu/2 (e^{gamma (I1 - 3)} "
        "- 1) = mu gamma tr E + mu gamma^2 (tr E)^2 + ..., and tr E is itself of second order "
        "near J = 1).\n\n"
        + "\n".join(small) + "\n")


#: The per-beat quantities of the heartbeat table, by their names in the first
#: ventricle's /summary columns without its prefix (lv_EDV_mL: EDV_mL); see
#: heartbeat_column() for the aortic pressures.
HEARTBEAT_KEYS = ["EDV_mL", "ESV_mL", "SV_mL", "EF", "EDP_mmHg", "peak_pressure_mmHg",
                  "aortic_systolic_mmHg", "aortic_diastolic_mmHg", "dpdt_max", "dpdt_min",
                  "isovolumetric_contraction_duration", "ejection_duration",
                  "isovolumetric_relaxation_duration", "filling_duration",
                  "stroke_work_mmHg_mL", "activation_time_90", "total_activation_time",
                  "ep_steps", "periodicity"]
#: Where the aortic pressures are in a heartbeat on a 0D model: the Windkessel's aortic
#: root, else the closed loop's systemic arteries (old files: aortic_systolic_mmHg, ...).
AORTIC_COLUMNS = {"aortic_systolic_mmHg": ("aortic_root_pressure_max_mmHg",
                                           "systemic_arterial_pressure_max_mmHg"),
                  "aortic_diastolic_mmHg": ("aortic_root_pressure_min_mmHg",
                                            "systemic_arterial_pressure_min_mmHg")}


def heartbeat_column(summary: dict, key: str) -> str | None:
    """The /summary column of a HEARTBEAT_KEYS entry: the first ventricle's (lv_EDV_mL),
    the aortic pressure of AORTIC_COLUMNS, or the unprefixed name of an old file; None if
    the file has none of them."""
    found = ventricles(summary)
    prefix = f"{found[0]}_" if found and found[0] else ""
    candidates = [prefix + key, *AORTIC_COLUMNS.get(key, ()), key]
    return next((name for name in candidates if name in summary), None)


#: Physiological bounds of the default heartbeat (the heartbeat issue): key -> (low, high).
HEARTBEAT_BOUNDS = {"EDV_mL": (100, 160), "EF": (45, 65), "peak_pressure_mmHg": (90, 140),
                    "aortic_diastolic_mmHg": (60, 90),
                    "isovolumetric_contraction_duration": (20, 80),
                    "ejection_duration": (200, 350),
                    "isovolumetric_relaxation_duration": (40, 120)}


def run_default_heartbeat(name: str, ranks: int, build: Path, workdir: Path,
                          extra: str = "", output: str = "") -> tuple[dict, object]:
    """parameters/lv_heartbeat.prm with `extra` appended and `output` in its Output subsection
    (no fields), on `ranks` ranks: the row so far and the results (None if the run failed; the
    row is then the failed row)."""
    prm = workdir / f"{name}.prm"
    prm.write_text((ROOT / "parameters" / "lv_heartbeat.prm").read_text() + extra +
                   f"\nsubsection Output\n  set Run name = {name}\n"
                   f"  set Field output interval = 0\n{output}end\n")
    command = [str(build / "systole"), str(prm)]
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    out, busy = run_watched(command, workdir, ranks)
    row = {"ranks": ranks, "ok": out.returncode == 0, "busy": busy}
    if out.returncode != 0:
        return failed_row(row, out, workdir / "results" / name / "results.h5"), None
    return row, read_results(workdir / "results" / name / "results.h5")


def run_heartbeat(ranks: int, build: Path, workdir: Path) -> dict:
    """The default heartbeat (parameters/lv_heartbeat.prm) until periodic."""
    row, results = run_default_heartbeat(f"heartbeat_{ranks}", ranks, build, workdir)
    if results is None:
        return row
    stats = results.statistics
    row["dofs"] = int(stats["n_dofs"])
    row["wall"], row["memory"] = stats["wall_time"], stats["peak_memory_per_rank"]
    ts, summary = results.timeseries, results.summary
    row["beats"] = len(summary["beat"])
    row["periodic"] = bool(stats["periodic"])
    row["steps_per_beat"] = len(ts["time"]) / row["beats"]
    row["newton_per_step"] = float(np.sum(ts["newton_iterations"]) / len(ts["time"]))
    row["solves_per_step"] = float(np.sum(ts["mechanics_solves"]) / len(ts["time"]))
    row["summary"] = {k: v for k, v in summary.items()}
    if "ep_steps" in stats:
        nodes, steps = int(stats["ep_nodes"]), int(stats["ep_steps"])
        cycle = stats["cycle_seconds"]
        row["ep"] = {"nodes": nodes,
                     "steps_per_mechanics_step": steps / max(1.0, stats["steps"]),
                     "us_per_step_per_dof":
                         1e6 * stats["ep_integration_seconds"] / max(1, steps * nodes),
                     "share": 100 * stats["ep_seconds"] / cycle,
                     "mechanics_share": 100 * stats["mechanics_seconds"] / cycle,
                     "reading": stats["ep_transfer_seconds"]}
    return row


def heartbeat_section(rows: list[dict]) -> str:
    """Cost per beat on 1 and 2 ranks, and the summary of every beat (2-rank run)."""
    lines = ["## Default heartbeat (parameters/lv_heartbeat.prm)",
             "Runs until the end-diastolic volume changes by less than 1 % between beats. "
             "Wall time per beat includes the start-up (mesh, fibres) divided over the beats. "
             "Newton iterations per step count the chord iterations on an old factorization "
             "too.", "",
             "| ranks | DOFs | beats (periodic) | wall [s] | wall per beat [s] | steps per beat "
             "| mechanics solves per step | Newton iterations per step | peak memory per rank "
             "[MiB] |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['ranks']} | failed: {r['error']} |")
            continue
        busy = " *" if r.get("busy") else ""
        lines.append(f"| {r['ranks']} | {r['dofs']} | {r['beats']} ({'yes' if r['periodic'] else 'no'}) "
                     f"| {r['wall']:.1f}{busy} | {r['wall'] / r['beats']:.1f}{busy} "
                     f"| {r['steps_per_beat']:.0f} | {r['solves_per_step']:.2f} "
                     f"| {r['newton_per_step']:.2f} | {r['memory']:.0f} |")
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    with_ep = [r for r in rows if r["ok"] and "ep" in r]
    if with_ep:
        lines += ["", "Electrophysiology (the monodomain model on its own, refined mesh): time per "
                  "EP step per DOF = wall time integrating EP (rank 0; the ranks advance "
                  "together) / (ARKode steps x EP nodes); the shares are of the wall time of "
                  "the cardiac cycle (EP: "
                  "integrating and reading it at the mechanics points).", "",
                  "| ranks | EP nodes | EP steps per mechanics step | EP time per step per DOF "
                  "[µs] | reading EP at the mechanics points [s] | share in EP | share in the "
                  "mechanics |", "|---|---|---|---|---|---|---|"]
        for r in with_ep:
            e = r["ep"]
            lines.append(f"| {r['ranks']} | {e['nodes']} | {e['steps_per_mechanics_step']:.2f} "
                         f"| {e['us_per_step_per_dof']:.2f} | {e['reading']:.2f} "
                         f"| {e['share']:.1f} % | {e['mechanics_share']:.1f} % |")
    done = [r for r in rows if r["ok"]]
    if done:
        summary = done[-1]["summary"]
        columns = {k: heartbeat_column(summary, k) for k in HEARTBEAT_KEYS}
        lines += ["", f"Beat summaries ({done[-1]['ranks']} rank(s)); the last column checks the "
                  "last beat against the physiological bounds of the heartbeat issue:", "",
                  "| quantity | " + " | ".join(f"beat {int(b)}" for b in summary["beat"]) +
                  " | bounds |", "|---|" + "---|" * (len(summary["beat"]) + 1)]
        for k, column in columns.items():
            if column is None:
                continue
            values = " | ".join(f"{v:.4g}" for v in summary[column])
            bound = ""
            if k in HEARTBEAT_BOUNDS:
                low, high = HEARTBEAT_BOUNDS[k]
                last = summary[column][-1]
                bound = f"{low} ... {high}: " + ("yes" if low <= last <= high else "**no**")
            if k == "periodicity":
                bound = "< 0.01: " + ("yes" if summary[column][-1] < 0.01 else "**no**")
            lines.append(f"| {column} | {values} | {bound} |")
    return "\n".join(lines) + "\n"


BIV_TITLE = "BiV heartbeat cost (tests/runs/biv_heartbeat_coarse.prm)"


def run_biv(ranks: int, build: Path, workdir: Path) -> dict:
    """One beat of both ventricles of meshes/biv_hex_coarse.msh (the ctest's settings)."""
    name = f"biv_heartbeat_{ranks}"
    text = (ROOT / "tests" / "runs" / "biv_heartbeat_coarse.prm").read_text()
    text = text.replace("../../meshes/", str(ROOT / "meshes") + "/")
    prm = workdir / f"{name}.prm"
    prm.write_text(text + f"\nsubsection Output\n  set Run name = {name}\nend\n")
    command = [str(build / "systole"), str(prm)]
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    out, busy = run_watched(command, workdir, ranks)
    row = {"ranks": ranks, "ok": out.returncode == 0, "busy": busy}
    path = workdir / "results" / name / "results.h5"
    if out.returncode != 0:
        return failed_row(row, out, path)
    results = read_results(path)
    stats, summary = results.statistics, results.summary
    row.update(dofs=int(stats["n_dofs"]), wall=stats["wall_time"],
               memory=stats["peak_memory_per_rank"], beats=len(summary["beat"]),
               steps=int(stats["steps"]), solves=int(stats["coupled_solves"]),
               newton=int(stats["newton_iterations"]),
               krylov=int(stats["linear_iterations"]), summary=summary)
    return row


def biv_section(rows: list[dict]) -> str:
    """Cost of one BiV beat on 1 and 2 ranks and the beat's summary of both ventricles."""
    lines = [f"## {BIV_TITLE}",
             "One beat from the unloaded state, uniform activation, on the 580-cell structured "
             "BiV, Q1 (the ctest), MUMPS: the linear solver counts one iteration per direct "
             "solve (back substitution), so its column is the number of linear solves. Newton "
             "iterations count the chord iterations too.", "",
             "| ranks | DOFs | wall per beat [s] | steps | coupled solves | Newton iterations "
             "| linear iterations | peak memory per rank [MiB] |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['ranks']} | failed: {r['error']} |")
            continue
        busy = " *" if r.get("busy") else ""
        lines.append(f"| {r['ranks']} | {r['dofs']} | {r['wall'] / r['beats']:.1f}{busy} "
                     f"| {r['steps']} | {r['solves']} | {r['newton']} | {r['krylov']} "
                     f"| {r['memory']:.0f} |")
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    done = [r for r in rows if r["ok"]]
    if done:
        summary = done[-1]["summary"]
        lines += ["", "| ventricle | EDV [mL] | ESV [mL] | EF [%] | peak [mmHg] |",
                  "|---|---|---|---|---|"]
        for c in ("lv", "rv"):
            lines.append(f"| {c} | {summary[f'{c}_EDV_mL'][-1]:.1f} "
                         f"| {summary[f'{c}_ESV_mL'][-1]:.1f} | {summary[f'{c}_EF'][-1]:.1f} "
                         f"| {summary[f'{c}_peak_pressure_mmHg'][-1]:.1f} |")
    return "\n".join(lines) + "\n"


#: Bounds of the periodic state of the closed loop (the heartbeat issue's bands for the LV in
#: the closed loop; physiology.md's typical right ventricle).
CIRCULATION_BOUNDS = {
    "lv_EDV_mL": (100, 160), "lv_EF": (45, 65), "lv_peak_pressure_mmHg": (90, 140),
    "systemic_arterial_pressure_min_mmHg": (60, 90), "la_pressure_mean_mmHg": (5, 15),
    "rv_EF": (45, 60), "rv_peak_pressure_mmHg": (20, 30),
}


def run_circulation(name: str, text: str, build: Path, workdir: Path) -> dict:
    """One Problem = circulation run (1 rank): its time series, summary, log and wall time."""
    prm = workdir / f"{name}.prm"
    prm.write_text(text + f"\nsubsection Output\n  set Run name = {name}\nend\n")
    out, busy = run_watched([str(build / "systole"), str(prm)], workdir, 1)
    if out.returncode != 0:
        return {"ok": False, "error": (out.stderr.strip().splitlines() or ["?"])[0]}
    results = read_results(workdir / "results" / name / "results.h5")
    wall = results.statistics["wall_time"]
    steps = int(results.statistics["arkode_steps"])
    return {"ok": True, "busy": busy, "timeseries": results.timeseries,
            "summary": results.summary, "wall": wall, "steps": steps}


def circulation_section(build: Path, workdir: Path) -> str:
    """The 0D closed loop: agreement with the independent reference over 5 beats, and the
    periodic state of parameters/circulation_closed_loop.prm."""
    from systole_post.closed_loop_reference import STATES, reference_solution

    title = "0D closed loop (Problem = circulation)"
    lines = [f"## {title}",
             "The closed loop of physiology.md (Regazzoni et al. 2022, elastance ventricles, "
             "the defaults of subsection Circulation) integrated by `systole` (ARKode, implicit "
             "DIRK of order 5, analytic Jacobian, valve events by root finding).", "",
             "Against the independent SciPy implementation of `scripts/systole_post/"
             "closed_loop_reference.py` (Radau, rtol 1e-10): 5 beats, app at relative "
             "tolerance 1e-10 and absolute volume tolerance 1e-9 mL, compared at its 4001 "
             "output times (every 1 ms, exact); the difference is the largest over the run "
             "divided by the state's largest magnitude (the pytest and ctest "
             "`run.circulation_closed_loop_reference` require < 1e-6).", ""]
    text = ("set Problem = circulation\nsubsection Time\n  set Time step = 1\nend\n"
            "subsection Circulation\n  set Number of beats = 5\n  set Periodicity tolerance = 0\n"
            "  set Relative tolerance = 1e-10\n  set Absolute volume tolerance = 1e-9\nend\n")
    tight = run_circulation("closed_loop_reference", text, build, workdir)
    if not tight["ok"]:
        lines.append(f"failed: {tight['error']}")
    else:
        ts = tight["timeseries"]
        reference = reference_solution(ts["time"] / 1000.0)
        lines += ["| state | largest value | largest difference | relative |", "|---|---|---|---|"]
        for i, (name, _) in enumerate(STATES):
            scale = np.max(np.abs(reference[i]))
            diff = np.max(np.abs(ts[name] - reference[i]))
            lines.append(f"| {name} | {scale:.4g} | {diff:.2e} | {diff / scale:.2e} |")
        volume = ts["total_blood_volume_mL"]
        drift = np.max(np.abs(volume - volume[0])) / volume[0]
        lines += ["", f"Blood volume {volume[0]:.3f} mL, largest relative change over the 5 "
                  f"beats {drift:.1e} (required < 1e-8). {tight['steps']} ARKode steps, "
                  f"{tight['wall']:.1f} s wall time (mostly writing and flushing the 4001 "
                  "rows)."]

    shipped = run_circulation("circulation_closed_loop",
                              (ROOT / "parameters" / "circulation_closed_loop.prm").read_text(),
                              build, workdir)
    lines += ["", "Periodic state of `parameters/circulation_closed_loop.prm` (until both EDVs "
              "change by less than 1e-4 between beats; relative tolerance 1e-8; EDV, EDP and "
              "ESV at the valve closures, extremes and means over the 1 ms rows and the valve "
              "events of the last beat):", ""]
    if not shipped["ok"]:
        lines.append(f"failed: {shipped['error']}")
        return "\n".join(lines) + "\n"
    summary = shipped["summary"]
    n = len(summary["beat"])
    lines += [f"{n} beats to periodicity (last EDV change {summary['periodicity'][-1]:.1e}), "
              f"{shipped['wall']:.1f} s.", "",
              "| quantity | last beat | bounds |", "|---|---|---|"]
    keys = ["lv_EDV_mL", "lv_ESV_mL", "lv_SV_mL", "lv_EF", "lv_EDP_mmHg",
            "lv_peak_pressure_mmHg", "systemic_arterial_pressure_max_mmHg",
            "systemic_arterial_pressure_min_mmHg", "systemic_arterial_pressure_mean_mmHg",
            "la_pressure_mean_mmHg", "rv_EDV_mL", "rv_ESV_mL", "rv_SV_mL", "rv_EF",
            "rv_peak_pressure_mmHg", "pulmonary_arterial_pressure_max_mmHg",
            "pulmonary_arterial_pressure_min_mmHg", "ra_pressure_mean_mmHg",
            "lv_stroke_work_mmHg_mL", "total_blood_volume_mL"]
    for k in keys:
        bound = ""
        if k in CIRCULATION_BOUNDS:
            low, high = CIRCULATION_BOUNDS[k]
            bound = f"{low} ... {high}: " + ("yes" if low <= summary[k][-1] <= high else "**no**")
        lines.append(f"| {k} | {summary[k][-1]:.4g} | {bound} |")
    lines += ["", "Aortic pressures are those of the systemic arterial compliance; the bounds "
              "are the LV bands of the heartbeat issue for its closed loop and physiology.md's "
              "typical right ventricle (reported, not asserted)."]
    return "\n".join(lines) + "\n"


CELL_MEASURES = ("resting_potential_mV", "peak_potential_mV", "APD90_ms", "peak_calcium_uM")
CELL_BEATS = 3


def run_cell(name: str, cell_type: str, dt: float, build: Path, workdir: Path) -> dict:
    """One Problem = cell run of the ten Tusscher-Panfilov cell (1 rank, CELL_BEATS beats)."""
    text = (f"set Problem = cell\nsubsection Time\n  set End time = {1000 * CELL_BEATS}\n"
            "  set Time step = 5\nend\nsubsection Electrophysiology\n"
            f"  set Ionic model = ten Tusscher-Panfilov\n  set Time step = {dt}\n"
            f"  subsection ten Tusscher-Panfilov\n    set Cell type = {cell_type}\n  end\nend\n")
    return run_circulation(name, text, build, workdir)


def cell_section(build: Path, workdir: Path) -> str:
    """The ten Tusscher-Panfilov cell (Problem = cell) against SciPy on the model files."""
    from systole_post.ten_tusscher_reference import reference_beats

    title = "Single cell: ten Tusscher-Panfilov 2006 against SciPy"
    prm = (ROOT / "parameters" / "cell_ttp.prm").read_text()
    shipped_dt = float(re.search(r"subsection Electrophysiology.*?set Time step\s*=\s*([\d.]+)",
                                 prm, re.DOTALL).group(1))
    lines = [f"## {title}",
             "One cell paced at 1 Hz from the model file's initial state (Problem = cell, "
             "the stimulus of the .ode file: 52 pA/pF for 1 ms at 10 ms of every beat), "
             f"{CELL_BEATS} beats, integrated by `systole` (ARK-4(2)3 with an empty implicit "
             "part, the 12 gates by Rush-Larsen after every step, Strang's splitting with "
             "merged half steps) and by SciPy's BDF (rtol 1e-8, atol 1e-10) on the Python that "
             "gotranx generates from the same .ode files (`scripts/systole_post/cellmodels`, "
             "an independent code path; `systole_post/ten_tusscher_reference.py`), measured "
             "the same way: resting potential at the stimulus onset, peak potential, APD90 "
             "(time above V_rest + 0.1 (V_peak - V_rest)), peak cytosolic calcium. The .ode "
             "file lets the stimulus current enter dK_i/dt, systole does not (an external "
             "current): 6e-3 mM of K_i per beat, 1e-3 mV of resting potential. The pytest and "
             "ctest `run.cell_ten_tusscher_panfilov_reference` require 0.5 % in every "
             f"measure of every beat at the time step of `parameters/cell_ttp.prm` "
             f"({shipped_dt} ms).", ""]
    lines += ["| variant | beat | quantity | systole | SciPy | relative difference |",
              "|---|---|---|---|---|---|"]
    worst = {}
    for cell_type in ("endocardial", "mid-myocardial", "epicardial"):
        r = run_cell(f"cell_{cell_type}", cell_type, shipped_dt, build, workdir)
        if not r["ok"]:
            lines.append(f"| {cell_type} | failed: {r['error']} | | | | |")
            continue
        reference = reference_beats(cell_type, CELL_BEATS)
        for beat, expected in enumerate(reference):
            for name in CELL_MEASURES:
                got, want = r["summary"][name][beat], expected[name]
                error = abs(got - want) / abs(want)
                worst[cell_type] = max(worst.get(cell_type, 0.0), error)
                lines.append(f"| {cell_type} | {beat} | {name} | {got:.5f} | {want:.5f} | "
                             f"{error:.1e} |")
    lines += ["", "Largest relative difference: " + ", ".join(
        f"{k} {v:.1e}" for k, v in worst.items()) + ".", "",
        "The epicardial cell with other time steps (the largest relative difference over "
        "the four measures and the beats; the peak potential, sampled at the steps, sets it):",
        "", "| time step [ms] | largest relative difference | measure | ARKode steps | "
        "wall [s] |", "|---|---|---|---|---|"]
    reference = reference_beats("epicardial", CELL_BEATS)
    for dt in (0.005, 0.01, 0.02, 0.05, 0.1):
        r = run_cell(f"cell_dt_{dt}", "epicardial", dt, build, workdir)
        if not r["ok"]:
            lines.append(f"| {dt} | failed: {r['error']} | | | |")
            continue
        errors = [(abs(r["summary"][n][b] - e[n]) / abs(e[n]), n)
                  for b, e in enumerate(reference) for n in CELL_MEASURES]
        error, measure = max(errors)
        lines.append(f"| {dt} | {error:.1e} | {measure} | {r['steps']} | {r['wall']:.1f} |")
    return "\n".join(lines) + "\n"


#: sqrt(sigma_l / sigma_t) of the Niederer et al. conductivities (the defaults).
EP_CV_RATIO = (0.1334 / 0.0176) ** 0.5
EP_PROBES = ["diagonal_1", "diagonal_2", "diagonal_3", "diagonal_4", "far_corner"]


def run_ep(label: str, changes: dict[str, str], ranks: int, build: Path, workdir: Path,
           tag: str = "", base: str = "ep_slab.prm") -> dict:
    """One electrophysiology run of parameters/<base> with changes: the EP cost line of
    its log and its /summary row (tag: to tell runs with the same label apart)."""
    text = with_changes((ROOT / "parameters" / base).read_text(), changes)
    name = re.sub(r"[^a-z0-9]+", "_", f"ep {tag} {label} {ranks}".lower())
    prm = workdir / f"{name}.prm"
    prm.write_text(text + f"\nsubsection Output\n  set Run name = {name}\n"
                   "  set Field output interval = 0\nend\n")
    command = [str(build / "systole"), str(prm)]
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    out, busy = run_watched(command, workdir, ranks)
    row = {"label": label, "ranks": ranks, "ok": out.returncode == 0, "busy": busy}
    if out.returncode != 0:
        return failed_row(row, out, workdir / "results" / name / "results.h5")
    results = read_results(workdir / "results" / name / "results.h5")
    stats = results.statistics
    row["dofs"], row["cells"] = int(stats["n_dofs"]), int(stats["n_cells"])
    row["wall"], row["memory"] = stats["wall_time"], stats["peak_memory_per_rank"]
    row["ep_seconds"], row["steps"] = stats["ep_seconds"], int(stats["ep_steps"])
    row["us_per_step_dof"] = 1e6 * row["ep_seconds"] / max(1, row["steps"] * row["dofs"])
    row["cg_per_solve"] = stats["linear_iterations"] / max(1.0, stats["linear_solves"])
    summary = results.summary
    row["summary"] = {k: float(v[-1]) for k, v in summary.items()}
    return row


def ep_cost_cells(r: dict) -> str:
    busy = " *" if r.get("busy") else ""
    return (f"{r['steps']} | {r['cg_per_solve']:.2f} | {r['us_per_step_dof']:.2f}{busy} "
            f"| {r['wall']:.1f}{busy} | {r['memory']:.0f} |")


EP_COST_HEAD = ("ARKode steps | CG iterations per stage solve | EP time per step per DOF [µs] "
                "| wall [s] | peak memory per rank [MiB] |")


def ep_slab_table(rows: list[dict]) -> str:
    """Activation times of the slab at each level, and their change from the level before."""
    lines = ["| resolution | ranks | DOFs | " + " | ".join(f"{p} [ms]" for p in EP_PROBES) +
             " | 90 % active [ms] | change from the previous level | " + EP_COST_HEAD,
             "|" + "---|" * 15]
    previous = None
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['label']} | {r['ranks']} | failed: {r['error']} |")
            continue
        s = r["summary"]
        times = [s[f"{p}_activation_time"] for p in EP_PROBES]
        change = ""
        if previous is not None and "Jacobi" not in r["label"]:
            old = [previous["summary"][f"{p}_activation_time"] for p in EP_PROBES]
            change = (f"far corner {100 * (times[-1] - old[-1]) / old[-1]:+.2f} %, max "
                      f"{max(abs(100 * (a - b) / b) for a, b in zip(times, old)):.2f} %")
        lines.append(f"| {r['label']} | {r['ranks']} | {r['dofs']} | " +
                     " | ".join(f"{t:.2f}" for t in times) +
                     f" | {s['activation_time_90']:.2f} | {change} | " + ep_cost_cells(r))
        if "Jacobi" not in r["label"]:
            previous = r
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    return "\n".join(lines)


def ep_step_table(rows: list[dict]) -> str:
    """Activation times for decreasing time steps, against the smallest."""
    done = [r for r in rows if r["ok"]]
    finest = done[-1]["summary"] if done else {}
    lines = ["| time step | DOFs | " + " | ".join(f"{p} [ms]" for p in EP_PROBES) +
             " | max difference from the smallest step [ms] | " + EP_COST_HEAD,
             "|" + "---|" * 13]
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['label']} | failed: {r['error']} |")
            continue
        times = [r["summary"][f"{p}_activation_time"] for p in EP_PROBES]
        diff = max(abs(t - finest[f"{p}_activation_time"]) for t, p in zip(times, EP_PROBES))
        lines.append(f"| {r['label']} | {r['dofs']} | " + " | ".join(f"{t:.4f}" for t in times) +
                     f" | {diff:.1e} | " + ep_cost_cells(r))
    return "\n".join(lines)


def ep_cable(model: str, direction: str, h: float) -> dict[str, str]:
    """A 20 mm cable along x (along the fibres) or y (across), cross-section 1 x 1 mm, a
    stimulus plane (the first 1.5 mm), probes at 8 and 16 mm."""
    along = direction == "along"
    n = str(round(20 / h))
    speed = {"Aliev-Panfilov": 0.12, "Mitchell-Schaeffer": 0.33}[model]
    end = 16 / (speed if along else speed / EP_CV_RATIO) * 1.15 + 10
    return {"Global refinements": "0",
            "End time": f"{end:.0f}",
            "Geometry/Box/Upper corner": "20, 1, 1" if along else "1, 20, 1",
            "Geometry/Box/Cells": f"{n}, 2, 2" if along else f"2, {n}, 2",
            "Electrophysiology/Ionic model": model,
            "Electrophysiology/Stimuli": ("plane: box 0 0 0 1.5 1 1 from 0 for 2 at 50" if along
                                          else "plane: box 0 0 0 1 1.5 1 from 0 for 2 at 50"),
            "Electrophysiology/Probes": ("near: 8, 0.5, 0.5; far: 16, 0.5, 0.5" if along
                                         else "near: 0.5, 8, 0.5; far: 0.5, 16, 0.5")}


def ep_cv_table(rows: list[tuple[str, float, dict, dict]]) -> str:
    """Conduction velocities (8 mm between the probes) and their ratio."""
    lines = ["| ionic model | h [mm] | CV along [m/s] | CV across [m/s] | ratio | "
             f"ratio / sqrt(sigma_l/sigma_t) - 1 |", "|---|---|---|---|---|---|"]
    for model, h, along, across in rows:
        if not (along["ok"] and across["ok"]):
            lines.append(f"| {model} | {h} | failed: {along.get('error', across.get('error'))} |")
            continue
        cv = [8 / (r["summary"]["far_activation_time"] - r["summary"]["near_activation_time"])
              for r in (along, across)]
        lines.append(f"| {model} | {h} | {cv[0]:.4f} | {cv[1]:.4f} | {cv[0] / cv[1]:.3f} "
                     f"| {100 * (cv[0] / cv[1] / EP_CV_RATIO - 1):+.2f} % |")
    return "\n".join(lines)


#: Conductivities [mS/mm] (along, across) giving 0.6 / 0.25 m/s with Mitchell-Schaeffer on
#: converged cables, and those of parameters/lv_heartbeat.prm (calibrated on its EP mesh).
EP_LV_CONVERGED = ("0.432", "0.0758")


def ep_lv_cable(direction: str, h: float, sigma: tuple[str, str], build: Path,
                workdir: Path) -> float:
    """Mitchell-Schaeffer conduction velocity [m/s] on a cable (ep_cable) with conductivities
    `sigma`, fixed steps of 0.1 ms."""
    changes = ep_cable("Mitchell-Schaeffer", direction, h)
    changes.update({"Electrophysiology/Longitudinal conductivity": sigma[0],
                    "Electrophysiology/Transverse conductivity": sigma[1],
                    "Electrophysiology/Time step": "0.1"})
    r = run_ep(f"{direction} {h} {sigma[0]} {sigma[1]}", changes, 1, build, workdir, tag="lv")
    if not r["ok"]:
        return float("nan")
    s = r["summary"]
    return 8 / (s["far_activation_time"] - s["near_activation_time"])


def ep_lv_section(build: Path, workdir: Path, quick: bool) -> str:
    """The activation of the default heartbeat's ventricle (its EP parameters, the
    electrophysiology problem alone) on its mechanics mesh refined 1 ... 3 (4) times with the
    converged-cable conductivities, and with the heartbeat's calibrated ones; the cables."""
    text = (ROOT / "parameters" / "lv_heartbeat.prm").read_text()
    calibrated = tuple(re.search(rf"set {name} conductivity\s*=\s*(\S+)", text).group(1)
                       for name in ("Longitudinal", "Transverse"))
    cable_lines = ["| conductivities along / across [mS/mm] | h [mm] | CV along [m/s] "
                   "| CV across [m/s] |", "|---|---|---|---|"]
    for sigma in (EP_LV_CONVERGED, calibrated):
        for h in (0.0625, 1.25):
            print(f"running the cables, sigma {sigma}, h = {h} mm ...", flush=True)
            along = ep_lv_cable("along", h, sigma, build, workdir)
            across = ep_lv_cable("across", h, sigma, build, workdir)
            cable_lines.append(f"| {sigma[0]} / {sigma[1]} | {h} | {along:.4f} | {across:.4f} |")

    runs = [(r, EP_LV_CONVERGED) for r in ((1, 2, 3) if quick else (1, 2, 3, 4))]
    runs.append((3, calibrated))
    rows = []
    for r, sigma in runs:
        print(f"running the ventricle's activation, mechanics mesh refined {r} times, sigma "
              f"{sigma} ...", flush=True)
        row = run_ep(f"{r}", {"Problem": "electrophysiology",
                              "Geometry/Global refinements": str(r),
                              "Time/End time": "150", "Time/Time step": "1",
                              "Electrophysiology/Longitudinal conductivity": sigma[0],
                              "Electrophysiology/Transverse conductivity": sigma[1],
                              "Electrophysiology/Adaptive time step": "false",
                              "Electrophysiology/Time step": "0.1"},
                     2, build, workdir, tag=f"lv {sigma[0]}", base="lv_heartbeat.prm")
        row["sigma"] = sigma
        rows.append(row)
    lines = ["| refinements of the mechanics mesh | conductivities [mS/mm] | cells | nodes "
             "| across the wall [mm] | activated | 90 % active [ms] | total activation time "
             "[ms] | change of the 90 % time from the previous level | " + EP_COST_HEAD,
             "|" + "---|" * 14]
    previous = None
    for r in rows:
        sigma = f"{r['sigma'][0]} / {r['sigma'][1]}"
        if not r["ok"]:
            lines.append(f"| {r['label']} | {sigma} | failed: {r['error']} |")
            continue
        s = r["summary"]
        change = ""
        same = previous is not None and previous["sigma"] == r["sigma"]
        if same and np.isfinite(previous["summary"]["activation_time_90"]):
            old = previous["summary"]["activation_time_90"]
            change = f"{100 * (s['activation_time_90'] - old) / old:+.1f} %"
        lines.append(f"| {r['label']} | {sigma} | {r['cells']} | {r['dofs']} "
                     f"| {10 / 2 ** int(r['label']):.2f} | {100 * s['activated_fraction']:.1f} % "
                     f"| {s['activation_time_90']:.2f} | {s['total_activation_time']:.2f} "
                     f"| {change} | " + ep_cost_cells(r))
        previous = r
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    return ("## Electrophysiology: the default heartbeat's ventricle\n"
            "The electrophysiology of `parameters/lv_heartbeat.prm` alone (Mitchell-Schaeffer, "
            "endocardial stimulus, rule-based fibres, Q1) on its mechanics mesh (64 cells, one "
            "across the 10 mm wall) refined 1 to 4 times, fixed steps of 0.1 ms, 150 ms, 2 "
            f"ranks: with the conductivities {EP_LV_CONVERGED[0]} / {EP_LV_CONVERGED[1]} "
            "mS/mm (0.6 / 0.25 m/s, the human speeds of physiology.md, on converged cables), "
            f"and with the heartbeat's {calibrated[0]} / {calibrated[1]} mS/mm, calibrated "
            "for its EP mesh (3 refinements, 1.25 mm across the wall) on cables of that cell "
            "size (sigma <- sigma (CV_target / CV)^2, two iterations). The heartbeat runs EP "
            "with adaptive steps (at most 2 ms).\n\nMitchell-Schaeffer cables (20 mm, "
            "velocities between 8 and 16 mm; 1 rank):\n\n" + "\n".join(cable_lines) +
            "\n\nThe ventricle:\n\n" + "\n".join(lines) + "\n")


def ep_sections(build: Path, workdir: Path, quick: bool) -> dict[str, str]:
    """Refinement of the Niederer slab (h with dt, then dt alone) and the conduction
    velocities along and across the fibres."""
    sections = {}
    levels = [(0, 0.4), (1, 0.2)] + ([] if quick else [(2, 0.1)])
    for model, end in (("Aliev-Panfilov", 300), ("Mitchell-Schaeffer", 120)):
        rows = []
        for r, dt in levels:
            label = f"h = {0.5 / 2 ** r} mm, dt = {dt} ms"
            print(f"running the {model} slab, {label} ...", flush=True)
            rows.append(run_ep(label, {"Global refinements": str(r), "End time": str(end),
                                       "Time/Time step": "2",
                                       "Electrophysiology/Ionic model": model,
                                       "Electrophysiology/Time step": str(dt)},
                               2, build, workdir, tag=model))
        if model == "Aliev-Panfilov":
            print("running the Aliev-Panfilov slab with the Jacobi preconditioner ...", flush=True)
            rows.append(run_ep("h = 0.25 mm, dt = 0.2 ms, CG + Jacobi",
                               {"Global refinements": "1", "Time/Time step": "2",
                                "Electrophysiology/Time step": "0.2",
                                "Electrophysiology/Preconditioner": "Jacobi"}, 2, build, workdir))
        title = f"Electrophysiology: Niederer slab, {model}"
        sections[title] = (
            f"## {title}\n`parameters/ep_slab.prm` (Niederer et al. 2011: 20 x 7 x 3 mm, fibres "
            "along x, 1.5 mm corner stimulus 50 µA/mm³ for 2 ms, sigma_l = 0.1334, sigma_t = "
            f"0.0176 mS/mm) with the {model} model, Q1, h and the EP time step refined together. "
            "Activation times at the points 1/5 ... 5/5 of the diagonal from the stimulated corner "
            "(first upstroke through -30 mV, interpolated in time); the change from the previous "
            "level is that of the far corner and the largest over the five points. The published "
            "benchmark used "
            "the ten Tusscher-Panfilov model (far corner about 40 ms when converged), so only the "
            "convergence is comparable. EP time per step per DOF: wall time in the EP time "
            "integration (the slowest rank) / (ARKode steps x DOFs); CG + BoomerAMG unless "
            "noted.\n\n"
            + ep_slab_table(rows) + "\n")
        print(sections[title], flush=True)

    rows = []
    for dt in (0.8, 0.4, 0.2, 0.1, 0.05):
        print(f"running the Aliev-Panfilov slab, h = 0.5 mm, dt = {dt} ms ...", flush=True)
        changes = {"Global refinements": "0", "Time/Time step": "4",
                   "Electrophysiology/Time step": str(dt)}
        rows.append(run_ep(f"{dt} ms", changes, 1, build, workdir))
    title = "Electrophysiology: time step"
    sections[title] = (
        f"## {title}\nThe Aliev-Panfilov slab at h = 0.5 mm (1 rank) with decreasing EP time "
        "steps (IMEX ARK-4(2)3, SUNDIALS' ARK324L2SA pair; the steps end at the stimulus "
        "switching times, so the charge delivered is exact and the method keeps its order; "
        "inside the 2 ms stimulus the 0.8 ms steps are shortened to 2/3 ms). The time-step "
        "error is far below the mesh error of the tables above.\n\n" + ep_step_table(rows) + "\n")
    print(sections[title], flush=True)

    cv_rows = []
    for model in ("Aliev-Panfilov", "Mitchell-Schaeffer"):
        for h in (0.25, 0.125, 0.0625):
            runs = []
            for direction in ("along", "across"):
                print(f"running the {model} cable {direction} the fibres, h = {h} mm ...",
                      flush=True)
                runs.append(run_ep(f"cable {direction} {model} {h}",
                                   ep_cable(model, direction, h), 1, build, workdir))
            cv_rows.append((model, h, *runs))
    title = "Electrophysiology: conduction velocity along and across the fibres"
    sections[title] = (
        f"## {title}\n20 mm cables (1 x 1 mm, 2 x 2 cells across) along x (fibres along the "
        "cable) and along y (fibres across it), stimulated over their first 1.5 mm; CV = 8 mm "
        "over the activation-time difference between 8 and 16 mm, far from the stimulus and "
        f"the sealed end. Expected ratio sqrt(sigma_l/sigma_t) = {EP_CV_RATIO:.3f} (the "
        "monodomain with one ionic model scales speeds with sqrt(D)). The Aliev-Panfilov "
        "travelling-wave speed sqrt(D k/(2T)) (1 - 2a) is 0.120 m/s along the fibres.\n\n"
        + ep_cv_table(cv_rows) + "\n")
    print(sections[title], flush=True)
    return sections


#: The benchmark's points: P1 the stimulated corner ... P8 the far corner, P9 the centre.
NIEDERER_POINTS = [f"P{i}" for i in range(1, 10)]

#: Activation times [ms] at P1 ... P9 of an independent code on the same benchmark:
#: fenicsx-beat (P1 tetrahedra, operator splitting with generalized Rush-Larsen), as printed
#: in its demos/niederer_benchmark.py, keyed by (h [mm], dt [ms]).
NIEDERER_FENICSX_BEAT = {
    (0.5, 0.05): [1.25, 51.1, 34.9, 58.9, 14.1, 49.5, 34.0, 56.65, 26.05],
    (0.5, 0.01): [1.22, 50.85, 33.96, 58.05, 13.98, 49.36, 33.07, 55.91, 25.64],
    (0.5, 0.005): [1.215, 50.775, 33.825, 57.96, 13.97, 49.345, 32.945, 55.825, 25.595],
    (0.2, 0.05): [1.25, 29.7, 32.9, 40.2, 9.55, 30.0, 32.95, 39.9, 18.9],
    (0.2, 0.01): [1.24, 29.09, 31.25, 38.66, 9.34, 29.4, 31.29, 38.42, 18.14],
    (0.2, 0.005): [1.235, 29.015, 31.05, 38.475, 9.315, 29.32, 31.08, 38.235, 18.045],
    (0.1, 0.05): [1.25, 26.85, 33.3, 40.35, 8.4, 27.5, 33.85, 40.55, 18.95],
    (0.1, 0.01): [1.23, 25.64, 31.46, 38.08, 8.03, 26.24, 31.94, 38.21, 17.95],
    (0.1, 0.005): [1.225, 25.5, 31.26, 37.81, 7.99, 26.09, 31.72, 37.93, 17.835],
}


def niederer_levels(quick: bool, full: bool = False) -> list[tuple[float, float, str]]:
    """The (h [mm], dt [ms], mass matrix) triples run: the benchmark's grid as far as 2 cores
    allow, with the lumped mass and the consistent one; `full` adds the consistent mass at
    h = 0.1 mm with dt = 0.01 and 0.005 ms (the benchmark's finest; many hours on 2 cores)."""
    lumped = [(0.5, 0.05), (0.5, 0.01), (0.5, 0.005), (0.2, 0.05), (0.2, 0.01), (0.2, 0.005),
              (0.1, 0.05)]
    consistent = [(0.5, 0.05), (0.2, 0.05), (0.5, 0.01), (0.5, 0.005), (0.2, 0.01),
                  (0.2, 0.005), (0.1, 0.05)]
    if quick:
        lumped, consistent = lumped[:4], consistent[:2]
    elif full:
        consistent += [(0.1, 0.01), (0.1, 0.005)]
    return [(h, dt, "lumped") for h, dt in lumped] + \
        [(h, dt, "consistent") for h, dt in consistent]


def niederer_section(build: Path, workdir: Path, quick: bool, full: bool = False) -> str:
    """The Niederer et al. 2011 benchmark with its own cell model (parameters/niederer_ttp.prm)
    at the benchmark's resolutions, activation times at P1 ... P9 beside those of an
    independent code, and the EP cost of ten Tusscher-Panfilov against Mitchell-Schaeffer."""
    rows = []
    for h, dt, mass in niederer_levels(quick, full):
        cells = f"{round(20 / h)}, {round(7 / h)}, {round(3 / h)}"
        label = f"h = {h} mm, dt = {dt} ms, {mass} mass"
        print(f"running the Niederer benchmark (ten Tusscher-Panfilov), {label} ...", flush=True)
        row = run_ep(label, {"Cells": cells, "Electrophysiology/Time step": str(dt),
                             "Electrophysiology/Mass matrix": mass},
                     2, build, workdir, tag="ttp", base="niederer_ttp.prm")
        row["key"] = (h, dt)
        row["mass"] = mass
        rows.append(row)
    # The cost of the cell model: the same slab and steps with Mitchell-Schaeffer.
    print("running the Niederer slab with Mitchell-Schaeffer, h = 0.5 mm, dt = 0.05 ms ...",
          flush=True)
    ms = run_ep("h = 0.5 mm, dt = 0.05 ms", {"Ionic model": "Mitchell-Schaeffer",
                                              "Activation threshold": "-30",
                                              "Electrophysiology/Mass matrix": "lumped"},
                2, build, workdir, tag="ms", base="niederer_ttp.prm")
    return niederer_text(rows, ms)


def niederer_text(rows: list[dict], ms: dict) -> str:
    """The Niederer section from the rows of niederer_section (each with its "key" (h, dt))
    and the Mitchell-Schaeffer row of the cost comparison."""
    lines = ["| resolution | DOFs | " + " | ".join(NIEDERER_POINTS) +
             " | fenicsx-beat P8 [ms] | max difference from fenicsx-beat [ms] | " + EP_COST_HEAD,
             "|" + "---|" * 18]
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['label']} | failed: {r['error']} |")
            continue
        times = [r["summary"][f"{p}_activation_time"] for p in NIEDERER_POINTS]
        other = NIEDERER_FENICSX_BEAT[r["key"]]
        finite = [abs(a - b) for a, b in zip(times, other) if math.isfinite(a)]
        diff = f"{max(finite):.2f}" if finite else ""
        if len(finite) < len(times):
            diff += f" ({len(times) - len(finite)} not activated)"
        lines.append(f"| {r['label']} | {r['dofs']} | " +
                     " | ".join(f"{t:.2f}" for t in times) +
                     f" | {other[7]:.2f} | {diff} | " + ep_cost_cells(r))
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    cost = ""
    ttp = next((r for r in rows if r["ok"] and r["key"] == (0.5, 0.05)
                and r.get("mass", "lumped") == "lumped"), None)
    if ttp and ms and ms["ok"]:
        busy = " (a run was marked busy: the ratio is less certain)" if (
            ttp.get("busy") or ms.get("busy")) else ""
        cost = (f"\n\nEP cost of the cell model on the h = 0.5 mm slab, dt = 0.05 ms, 2 ranks: "
                f"ten Tusscher-Panfilov {ttp['us_per_step_dof']:.2f} µs per step per DOF, "
                f"Mitchell-Schaeffer {ms['us_per_step_dof']:.2f} µs; ratio "
                f"{ttp['us_per_step_dof'] / ms['us_per_step_dof']:.1f}{busy}.")
    return ("## Electrophysiology: the Niederer et al. 2011 benchmark\n"
            "`parameters/niederer_ttp.prm`: the benchmark as defined (20 x 7 x 3 mm, fibres "
            "along x, epicardial ten Tusscher-Panfilov 2006 cells, sigma_l = 0.1334, sigma_t = "
            "0.0176 mS/mm, chi = 140 /mm, C_m = 0.01 µF/mm², 1.5 mm corner cube at 50 µA/mm³ "
            "for 2 ms), Q1 with the Gauss-Lobatto lumped mass or the consistent one "
            "(`Electrophysiology / Mass matrix`; the ionic currents at the nodes either way), "
            "IMEX ARKode (SUNDIALS' "
            "ARK324L2SA, order 3) with fixed steps dt and Rush-Larsen gates. Activation time: first upward crossing of 0 mV [ms] at "
            "the benchmark's points P1 = (0, 0, 0) (stimulated corner), P2 = (0, 7, 0), P3 = "
            "(20, 0, 0), P4 = (20, 7, 0), P5 = (0, 0, 3), P6 = (0, 7, 3), P7 = (20, 0, 3), "
            "P8 = (20, 7, 3) (far corner), P9 = (10, 3.5, 1.5); nan: not activated within 80 "
            "ms. The independent values: fenicsx-beat's table for the same (h, dt) (P1 "
            "tetrahedra, operator splitting; its demos/niederer_benchmark.py). The benchmark "
            "paper reports its consensus solution at the finest resolution, h = 0.1 mm, dt = "
            "0.005 ms.\n\n" + "\n".join(lines) + cost + "\n")


def run_checkpoint(ranks: int, build: Path, workdir: Path, interval: int = 10) -> dict:
    """One beat of the default heartbeat with a checkpoint every `interval` steps: the write
    time per checkpoint and the size of the last checkpoint by part (from /statistics)."""
    row, results = run_default_heartbeat(
        f"checkpoint_{ranks}", ranks, build, workdir,
        extra="\nsubsection Circulation\n  set Number of beats = 1\nend\n",
        output=f"  set Checkpoint interval = {interval}\n")
    if results is None:
        return row
    st = results.statistics
    row["n"] = int(st["checkpoints"])
    row["seconds"] = st["checkpoint_seconds"] / max(1, row["n"])
    row["dofs"] = int(st["mechanics_dofs"])
    row["wall"] = st["wall_time"]
    row["ep_nodes"] = int(st["ep_nodes"])
    folder = workdir / results.statistics_text["last_checkpoint"]
    sizes = {"mechanics": 0, "ep": 0, "state": 0}
    for f in folder.iterdir():
        part = "mechanics" if f.name.startswith("mechanics") else \
            "ep" if f.name.startswith("ep.") else "state"
        sizes[part] += f.stat().st_size
    row["sizes"] = sizes
    return row


def checkpoint_section(rows: list[dict]) -> str:
    """Checkpoint size per DOF and write time of the default heartbeat."""
    lines = ["## Checkpoints of the default heartbeat (parameters/lv_heartbeat.prm)",
             "One beat with `Output / Checkpoint interval = 10`. A checkpoint holds the mechanics "
             "mesh with its attached data (three displacement vectors: the last two accepted "
             "states and the iterate of the held factorization; the tension of that iterate and "
             "the activation records per quadrature point), the EP mesh with the potential, the "
             "ionic states and the activation times per node, and the small state (`state.bin`: "
             "BDF history, beat recorder, counters), plus the parameters and the manifest. The "
             "write time includes the CRC-32 manifest and fsync, not the refactorization a "
             "resume needs.", "",
             "| ranks | mechanics DOFs | EP nodes | checkpoints | write time [s] | mechanics part "
             "[bytes per DOF] | EP part [bytes per node] | state.bin etc. [kB] | total [kB] | run "
             "wall time [s] |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if not r["ok"]:
            lines.append(f"| {r['ranks']} | failed: {r.get('error', '')} |||||||||")
            continue
        s = r["sizes"]
        lines.append(f"| {r['ranks']} | {r['dofs']} | {r['ep_nodes']} | {r['n']} | "
                     f"{r['seconds']:.3f} | {s['mechanics'] / r['dofs']:.0f} | "
                     f"{s['ep'] / r['ep_nodes']:.0f} | {s['state'] / 1024:.1f} | "
                     f"{sum(s.values()) / 1024:.0f} | {r['wall']:.1f} |")

POSTPROCESS_TITLE = "Postprocessors: analytic deformations and the AHA partition"


def postprocess_section(build: Path) -> str:
    """The analytic checks of the postprocessors (tests/unit/postprocess): run them and
    report what each one checks and whether it passed."""
    checks = [
        ("Homogeneous stretch along the fibres*",
         "u = (lambda - 1)(f0 . X) f0, lambda = 1.15, a uniform fibre frame, on the default "
         "ventricle (16 x 5 cells, Q2, MappingQ2, no Dirichlet part): at every quadrature point "
         "lambda_f = J = lambda and e . E e = (lambda^2 - 1)/2 (f0 . e)^2 for e = e_c, e_l, e_r "
         "of the wall coordinates' frame, to 1e-10; the nodal fibre_stretch and J (lumped L2 "
         "projection) equal lambda to 1e-10"),
        ("Simple shear*",
         "u = gamma (e_z . X) e_x, gamma = 0.2: E = (gamma (a x b + b x a) + gamma^2 b x b)/2 "
         "in every frame direction, J = 1, lambda_f = sqrt(1 + 2 f0 . E f0), to 1e-10"),
        ("A uniform dilation*",
         "u = (lambda - 1)(X - c) about an off-axis point, lambda = 1.1: long_axis_shortening "
         "= 1 - lambda, wall_thickening = lambda - 1, torsion = 0, to 1e-10"),
        ("A prescribed twist*",
         "rotation by phi about the long axis up to the top of the apical ring, 0 from the "
         "bottom of the basal ring, linear between (phi = -12, 7.5, 25 degrees): torsion = "
         "phi and long_axis_shortening = 0 to 1e-10"),
        ("The 17 AHA segments of the default ventricle*",
         "every segment holds points of at least one cell; the segment volumes add up to the "
         "wall volume (GridTools::volume with the same mapping) to 1e-10 relative"),
        ("A stretch along the fibre gives*",
         "pointwise: random frames, F = I + (lambda - 1) f0 x f0, S = s0 f0 x f0: the fibre "
         "and first principal Cauchy stress equal lambda s0 to 1e-12"),
    ]
    lines = [f"## {POSTPROCESS_TITLE}",
             "The postprocessors of `Postprocess / List of postprocessors` against deformations "
             "with closed-form values (`tests/unit/postprocess`, run now):", "",
             "| check | what | passed |", "|---|---|---|"]
    for name, what in checks:
        out = subprocess.run([str(build / "tests" / "systole-unit"), name],
                             capture_output=True, text=True)
        lines.append(f"| {name.rstrip('*')} | {what} | "
                     f"{'yes' if out.returncode == 0 else '**no**'} |")
    return "\n".join(lines) + "\n"


#: The heartbeat with ten Tusscher-Panfilov calcium and Land tension: the coarse one of the
#: tests (801 DOFs, the whole wall stimulated) for the sweeps, the full one with --full.
LAND_COARSE = ROOT / "tests" / "runs" / "lv_heartbeat_ttp_land_coarse.prm"
LAND_FULL = ROOT / "parameters" / "lv_heartbeat_ttp_land.prm"
#: Land without length dependence: h(lambda) = 1 and Ca50 independent of the stretch.
NO_LENGTH_DEPENDENCE = {"Active tension/Land/beta0": "0", "Active tension/Land/beta1": "0"}
#: The preloads (atrial pressures [mmHg]) and afterloads (peripheral resistances [mmHg s/mL])
#: of the sweeps; the base files leave both at their defaults, 10 and 1.
LAND_PRELOADS = (6, 10, 14)
LAND_AFTERLOADS = (0.7, 1.0, 1.4)


def land_cases(full: bool) -> dict[str, dict[str, str]]:
    """The runs of the land group by name: the preload sweep with and without the length
    dependence, and the afterload sweep without its x1 run, which is the preload run at 10
    mmHg with the length dependence (the same parameters)."""
    prm = LAND_FULL if full else LAND_COARSE
    text = prm.read_text()
    assert "Atrial pressure" not in text and "Peripheral resistance" not in text, (
        f"{prm.name} sets the atrial pressure or the peripheral resistance: the afterload x1 "
        "run is no longer the preload run at 10 mmHg")
    # The coarse one with the full one's reference tension and mitral valve resistance.
    base = {} if full else {"Active tension/Land/Reference tension": "200",
                            "Circulation/Mitral valve resistance": "0.0075"}
    cases = {}
    for label, extra in (("with", {}), ("without", NO_LENGTH_DEPENDENCE)):
        for edp in LAND_PRELOADS:
            cases[f"land_preload_{label}_{edp}"] = {**base, **extra,
                                                     "Circulation/Atrial pressure": str(edp)}
    for factor in LAND_AFTERLOADS:
        if factor != 1.0:
            cases[f"land_afterload_{factor:g}"] = {
                **base, "Circulation/Atrial pressure": "10",
                "Circulation/Peripheral resistance": f"{factor:g}"}
    return cases


def land_afterload_name(factor: float) -> str:
    """The run of the afterload factor (x1: the preload run at 10 mmHg with the length
    dependence)."""
    return "land_preload_with_10" if factor == 1.0 else f"land_afterload_{factor:g}"


def run_land_heartbeat(name: str, prm: Path, changes: dict[str, str], beats: int, ranks: int,
                       build: Path, workdir: Path) -> dict:
    """One heartbeat of `prm` with `changes` for `beats` beats: land_row of its results."""
    changes = {**changes, "Circulation/Number of beats": str(beats),
               "Output/Run name": name, "Output/Field output interval": "0",
               "Output/Checkpoint interval": "0"}
    path = workdir / f"{name}.prm"
    path.write_text(with_changes(prm.read_text(), changes))
    command = [str(build / "systole"), str(path)]
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    out, busy = run_watched(command, workdir, ranks)
    return land_row(name, workdir, out, busy, ranks)


def land_row(name: str, workdir: Path, out: subprocess.CompletedProcess, busy: bool,
             ranks: int, beat: int = -1) -> dict:
    """The numbers of one land run from its results file: the summary of its beat `beat` (a
    row index of /summary; the last one by default), the
    pressures at the aortic valve's opening and closure (end-systolic), the LV pressure and
    the mean active tension when the beat starts, and the cost."""
    row = {"name": name, "ok": out.returncode == 0, "busy": busy, "ranks": ranks}
    h5 = workdir / "results" / name / "results.h5"
    if out.returncode != 0:
        return failed_row(row, out, h5)
    import h5py  # the valve events (/events) are not part of systole_post's Results

    results = read_results(h5)
    summary, stats, ts = results.summary, results.statistics, results.timeseries
    with h5py.File(h5, "r") as f:
        events = {k: f["events"][k][()] for k in f["events"]}
    row["summary"] = {k: float(v[beat]) for k, v in summary.items()}
    aortic = (events["beat"] == summary["beat"][beat]) & (events["valve"] == 1)
    closes, opens = aortic & (events["opens"] == 0), aortic & (events["opens"] == 1)
    row["esp"] = float(events["lv_pressure_mmHg"][closes][0]) if np.any(closes) else float("nan")
    row["opening_pressure"] = (float(events["lv_pressure_mmHg"][opens][0]) if np.any(opens)
                               else float("nan"))
    # The end of the previous filling, when the beat starts (its stimulus): the LV pressure
    # (below the atrial pressure, the filling was still going on; EDP, the pressure at the
    # mitral valve's closure, is the atrial pressure whatever the filling reached) and the
    # mean active tension over the quadrature points (the diastolic residue).
    start = summary["start_time"][beat]
    row["start_pressure"] = float(np.interp(start, ts["time"], ts["lv_pressure_mmHg"]))
    row["start_tension"] = float(np.interp(start, ts["time"], ts["mean_active_tension"]))
    row["wall"] = stats["wall_time"]
    row["dofs"] = int(stats["n_dofs"])
    row["beats"] = int(stats["beats"])
    row["periodic"] = bool(stats["periodic"])
    row["newton"] = int(stats["newton_iterations"])
    row["steps"] = int(stats["steps"])
    row["ep_nodes"] = int(stats.get("ep_nodes", 0))
    row["ep_seconds"] = stats.get("ep_seconds", float("nan"))
    return row


def land_section(build: Path, workdir: Path, full: bool, jobs: int = 1) -> str:
    """Frank-Starling (preload sweep with and without Land's length dependence) and the ESPVR
    (afterload sweep) of the heartbeat with ten Tusscher-Panfilov and Land, 2 beats each;
    `jobs` runs at a time (2 ranks each with one, 1 rank each with more)."""
    from concurrent.futures import ThreadPoolExecutor

    prm = LAND_FULL if full else LAND_COARSE
    ranks = 2 if jobs == 1 else 1

    def one(item: tuple[str, dict[str, str]]) -> tuple[str, dict]:
        name, changes = item
        print(f"running {name} on {ranks} rank(s) ...", flush=True)
        return name, run_land_heartbeat(name, prm, changes, 2, ranks, build, workdir)

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        rows = dict(pool.map(one, land_cases(full).items()))
    return land_text(rows, full, jobs)


def land_text(rows: dict[str, dict], full: bool, jobs: int = 1) -> str:
    """The land section from the rows of land_section by run name."""
    prm = LAND_FULL if full else LAND_COARSE
    preload = {(label, edp): rows[f"land_preload_{label}_{edp}"]
               for label in ("with", "without") for edp in LAND_PRELOADS}
    afterload = {factor: rows[land_afterload_name(factor)] for factor in LAND_AFTERLOADS}
    ranks = next(iter(rows.values()))["ranks"]

    def cells(r: dict) -> str:
        if not r["ok"]:
            return f"failed: {r['error']} | | | | |"
        s = r["summary"]
        return (f"{r['start_pressure']:.2f} | {s['lv_EDP_mmHg']:.2f} | {s['lv_EDV_mL']:.1f} | "
                f"{s['lv_SV_mL']:.2f} | {r['start_tension']:.3f}")

    first = next((r for r in rows.values() if r["ok"]), None)
    size = (f"{first['dofs']} mechanics DOFs, {first['ep_nodes']} EP nodes, " if first else "")
    how = f"{ranks} ranks" if jobs == 1 else f"{ranks} rank each, {jobs} runs at a time"
    lines = [f"## Excitation-contraction coupling: Frank-Starling and the ESPVR "
             f"({'parameters/lv_heartbeat_ttp_land.prm' if full else 'the coarse ventricle'})",
             "The heartbeat with ten Tusscher-Panfilov 2006 (epicardial) calcium driving the Land "
             "et al. 2017 tension, coupled two-way with the mechanics "
             f"({prm.relative_to(ROOT)}{'' if full else ' with T_ref = 200 kPa and the mitral valve resistance 0.0075 mmHg s/mL'}; {size}{how}; "
             "2 beats each from the unloaded state, the second one reported; `scripts/bench "
             f"--only land{' --full' if full else ''}`"
             f"{'' if full else ' (--full: parameters/lv_heartbeat_ttp_land.prm)'}). "
             "Preload: the 3-element Windkessel's atrial (filling) pressure 6, 10, 14 mmHg, with "
             "the paper's length dependence and without it (beta0 = beta1 = 0: h(lambda) = 1, "
             "Ca50 independent of the stretch); p_0: the LV pressure when the reported beat "
             "starts (its stimulus), i.e. where the filling got to (EDP, the pressure at the "
             "mitral valve's closure, equals the atrial pressure by the valve law); T_0: the "
             "mean active tension over the mechanics' quadrature points then (the diastolic "
             "residue). "
             "Afterload: the peripheral resistance x0.7, x1 (the run at 10 mmHg with the length "
             "dependence), x1.4; the end-systolic point is the LV pressure and volume at the "
             "aortic valve's closure.", "",
             "| atrial pressure [mmHg] | with length dependence: p_0 [mmHg] | EDP [mmHg] | EDV "
             "[mL] | SV [mL] | T_0 [kPa] | without: p_0 [mmHg] | EDP [mmHg] | EDV [mL] | SV [mL] "
             "| T_0 [kPa] |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for edp in LAND_PRELOADS:
        lines.append(f"| {edp} | {cells(preload[('with', edp)])} | "
                     f"{cells(preload[('without', edp)])} |")

    def value(label: str, edp: int, key: str) -> float:
        r = preload[(label, edp)]
        return r["summary"][key] if r["ok"] else float("nan")

    def change(label: str, key: str) -> float:
        return value(label, LAND_PRELOADS[-1], key) - value(label, LAND_PRELOADS[0], key)

    with_sv = [value("with", e, "lv_SV_mL") for e in LAND_PRELOADS]
    monotone = all(b > a for a, b in zip(with_sv, with_sv[1:]))
    gain_with, gain_without = change("with", "lv_SV_mL"), change("without", "lv_SV_mL")
    edv_with, edv_without = change("with", "lv_EDV_mL"), change("without", "lv_EDV_mL")
    esv_with, esv_without = change("with", "lv_ESV_mL"), change("without", "lv_ESV_mL")
    lines += ["", f"Stroke volume from 6 to 14 mmHg: {gain_with:+.2f} mL with the length "
              f"dependence ({'monotonic' if monotone else 'NOT monotonic'}), "
              f"{gain_without:+.2f} mL without it "
              f"({'more' if gain_with > gain_without else 'NOT more'} with it). "
              f"EDV {edv_with:+.2f} mL with, {edv_without:+.2f} mL without; ESV "
              f"{esv_with:+.2f} mL with, {esv_without:+.2f} mL without; the Starling slope "
              f"dSV/dEDV {gain_with / edv_with:.3f} with, {gain_without / edv_without:.3f} "
              "without.", "",
              "| peripheral resistance | ESV [mL] | ESP [mmHg] | EDV [mL] | SV [mL] | peak "
              "[mmHg] |", "|---|---|---|---|---|---|"]
    points = []
    for factor, r in afterload.items():
        if not r["ok"]:
            lines.append(f"| x{factor:g} | failed: {r['error']} |")
            continue
        s = r["summary"]
        points.append((s["lv_ESV_mL"], r["esp"]))
        lines.append(f"| x{factor:g} | {s['lv_ESV_mL']:.2f} | {r['esp']:.2f} | "
                     f"{s['lv_EDV_mL']:.1f} | {s['lv_SV_mL']:.2f} | "
                     f"{s['lv_peak_pressure_mmHg']:.1f} |")
    if len(points) == 3:
        v, p = np.array(points).T
        slope, intercept = np.polyfit(v, p, 1)
        fit = slope * v + intercept
        r2 = 1 - np.sum((p - fit) ** 2) / np.sum((p - np.mean(p)) ** 2)
        lines += ["", f"ESPVR: P_es = {slope:.3f} (V_es - {-intercept / slope:.1f} mL) mmHg "
                  f"(elastance {slope:.3f} mmHg/mL), R^2 = {r2:.4f}."]
    walls = [r for r in rows.values() if r["ok"]]
    if walls:
        per_beat = [r["wall"] / r["beats"] for r in walls]
        busy = any(r["busy"] for r in walls)
        lines += ["", f"Wall time per beat ({how}): {min(per_beat):.1f} to "
                  f"{max(per_beat):.1f} s ({sum(r['newton'] for r in walls) / sum(r['steps'] for r in walls):.2f} "
                  "Newton iterations per step)"
                  f"{'; other work loaded the machine, so the times are inflated' if busy else ''}."]
    return "\n".join(lines) + "\n"



def run_inverse(base: str, name: str, build: Path, workdir: Path, ranks: int = 2) -> dict:
    """One Problem = unloading or calibration run of parameters/<base> on `ranks` ranks:
    /statistics (counts and the mechanics' timer sections), /summary, the calibration
    tables."""
    text = (ROOT / "parameters" / base).read_text()
    prm = workdir / f"{name}.prm"
    prm.write_text(text + f"\nsubsection Output\n  set Run name = {name}\n"
                   "  set Field output interval = 0\nend\n")
    command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
               str(build / "systole"), str(prm)]
    out, busy = run_watched(command, workdir, ranks)
    if out.returncode != 0:
        lines = out.stderr.strip().splitlines() or ["?"]
        return {"ok": False, "base": base,
                "error": next((line for line in lines if "error" in line), lines[0])}
    path = workdir / "results" / name / "results.h5"
    results = read_results(path)
    row = {"ok": True, "busy": busy, "base": base, "stats": results.statistics,
           "summary": {k: float(v[-1]) for k, v in results.summary.items()}}
    import h5py
    with h5py.File(path, "r") as f:
        for group in ("calibration/edpvr", "calibration/parameters", "calibration/fit"):
            if group in f:
                row[group] = {k: f[group][k][()] for k in f[group]}
    return row


def timer_seconds(stats: dict, *words: str) -> float:
    """Sum of the /statistics timer sections whose name holds every word."""
    return sum(v for k, v in stats.items()
               if k.startswith("timer: ") and all(w in k for w in words))


def inverse_section(build: Path, workdir: Path) -> str:
    """The cost of unloading (parameters/lv_unloading.prm) and of the Klotz calibration on
    the unloaded reference (parameters/lv_calibration.prm), 2 ranks, and the fitted EDPVR
    against Klotz's curve recomputed here from the formulas."""
    print("running parameters/lv_unloading.prm on 2 ranks ...", flush=True)
    unloading = run_inverse("lv_unloading.prm", "bench_unloading", build, workdir)
    print("running parameters/lv_calibration.prm on 2 ranks (takes a while) ...", flush=True)
    calibration = run_inverse("lv_calibration.prm", "bench_calibration", build, workdir)
    lines = ["## Cost of unloading and calibration (2 ranks)",
             "Written by `scripts/bench --only inverse`: the default ventricle (16 x 5 cells, "
             "Q2) on 2 ranks (`mpirun -np 2`). Counts from `/statistics`; the assembly and "
             "linear-solver times are the mechanics' TimerOutput sections summed over the "
             "meshes built on every trial reference (rank 0's wall times). A forward solve is "
             "one Newton solve (a load step or a finite-difference solve); an unloading "
             "inflation is one load-stepped inflation of a trial reference to the image "
             "pressure.\n",
             "| case | DOFs | fixed-point iterations | unloading inflations | forward solves "
             "(calibration) | TAO iterations | Newton iterations | assembly [s] | "
             "linear solves [s] | wall [s] |",
             "|" + "---|" * 10]
    for label, r in (("unloading (`lv_unloading.prm`)", unloading),
                     ("Klotz calibration on the unloaded reference (`lv_calibration.prm`)",
                      calibration)):
        if not r["ok"]:
            lines.append(f"| {label} | failed: {r['error']} |")
            continue
        st = r["stats"]
        if "tao_iterations" in st:
            newton = (f"{st['newton_iterations']:.0f} + {st['unloading_newton_iterations']:.0f} "
                      "(unloading)")
            cells = (f"{st['fixed_point_iterations']:.0f} | {st['unloading_inflations']:.0f} | "
                     f"{st['forward_solves']:.0f} | {st['tao_iterations']:.0f} | {newton}")
        else:
            cells = (f"{st['fixed_point_iterations']:.0f} | {st['forward_solves']:.0f} | – | – | "
                     f"{st['newton_iterations']:.0f}")
        star = " \\*" if r["busy"] else ""
        lines.append(f"| {label} | {st['n_dofs']:.0f} | {cells} | "
                     f"{timer_seconds(st, 'assembl'):.1f} | {timer_seconds(st, 'linear solver'):.1f} | "
                     f"{st['wall_time']:.0f}{star} |")
    if any(r.get("busy") for r in (unloading, calibration)):
        lines.append(BUSY_NOTE)
    if calibration["ok"] and "calibration/edpvr" in calibration:
        e, fit = calibration["calibration/edpvr"], calibration["calibration/fit"]
        par, st = calibration["calibration/parameters"], calibration["stats"]
        edp, edv = float(fit["klotz_edp_mmHg"][0]), float(fit["klotz_edv_mL"][0])
        v0 = edv * (0.6 - 0.006 * edp)  # Klotz 2006: 0.006 per mmHg of EDP_m
        v30 = v0 + (edv - v0) / (edp / 27.78) ** (1 / 2.76)
        names = [n.decode() if isinstance(n, bytes) else str(n) for n in par["name"]]
        fitted = ", ".join(f"{n} = {v:.4g} ± {s:.2g}" + (" (at a bound)" if b else "")
                           for n, v, s, b in zip(names, par["fitted"],
                                                 par["standard_deviation"], par["at_bound"]))
        reason = fit["reason"][0]
        reason = reason.decode() if isinstance(reason, bytes) else str(reason)
        lines += ["", f"Klotz's curve through ({edp:g} mmHg, {edv:.3f} mL, the image's cavity), "
                  f"recomputed here: V0 = {v0:.3f} mL, V30 = {v30:.3f} mL. Fitted (± one "
                  f"standard deviation): {fitted}; relative residual norm "
                  f"{float(fit['residual_norm'][0]):.4f}; TAO's reason {reason} after "
                  f"{float(fit['tao_iterations'][0]):.0f} iterations and "
                  f"{float(fit['evaluations'][0]):.0f} evaluations; unloaded "
                  f"cavity {st['unloaded_volume_mL']:.2f} mL (reload error "
                  f"{st['reload_max_error_mm']:.2g} mm).\n",
                  "| p [mmHg] | Klotz [mL] | fitted [mL] | error | initial values [mL] |",
                  "|---|---|---|---|---|"]
        for p, v, v_init in zip(e["pressure_mmHg"], e["volume_mL"], e["initial_volume_mL"]):
            klotz = v0 + (v30 - v0) * (p / 27.78) ** (1 / 2.76)
            lines.append(f"| {p:g} | {klotz:.1f} | {v:.1f} | {100 * (v / klotz - 1):+.1f} % | "
                         f"{v_init:.1f} |")
    return "\n".join(lines) + "\n"



def write_docs(output: Path, sections: dict[str, str], replace_only: bool) -> None:
    """Replace the given sections of the existing file and keep the others (new sections
    are appended): sections that no group writes (tables of the tests, studies run by hand)
    survive a full run. replace_only is kept for the callers; both modes merge."""
    header = ("# Verification\n\nThe sections of the `scripts/bench` groups are rewritten by it; "
              "the others hold studies run by hand or by the tests, as they say. Values are the "
              "deformed coordinates [mm] at the last load step; timings are wall-clock seconds "
              "on this machine (2 cores), including start-up, and vary by some 10 %.\n\n")
    if output.exists():
        old = output.read_text()
        parts = re.split(r"^(?=## )", old, flags=re.MULTILINE)[1:]
        kept = {part.splitlines()[0][3:].strip(): part.rstrip("\n") + "\n" for part in parts}
        kept.update(sections)
        sections = kept
    output.write_text(header + "\n".join(sections.values()))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", type=Path, default=ROOT / "build")
    parser.add_argument("--quick", action="store_true", help="skip the finest levels")
    parser.add_argument("--full", action="store_true",
                        help="land: sweep parameters/lv_heartbeat_ttp_land.prm (hours) in place "
                        "of the coarse ventricle; niederer: also h = 0.1 mm with dt = 0.01 and "
                        "0.005 ms (many hours)")
    parser.add_argument("--jobs", type=int, default=1,
                        help="land: runs at a time (1: 2 ranks each; more: 1 rank each)")
    parser.add_argument("--output", type=Path, default=ROOT / "docs" / "verification.md")
    parser.add_argument("--only", choices=["p1", "p2", "p2-mixed", "p3", "fibres", "heartbeat", "ep",
                                           "ep-lv", "mixed", "circulation",
                                           "laws", "cell", "checkpoint", "postprocess",
                                           "niederer", "land", "inverse", "biv", "scaling",
                                           "scaling-th", "large", "arostica", "tet",
                                           "badinput"],
                        help="run one group and replace its sections of the output (the other "
                        "sections are kept)")
    parser.add_argument("--no-write", action="store_true",
                        help="print the tables only; do not touch the output")
    args = parser.parse_args()

    levels = [0, 1] if args.quick else [0, 1, 2]
    p1 = [Case("p1", "land_problem1.prm", f"10x1x1 cells, {r} refinement(s), Q2",
               {"Global refinements": str(r)}) for r in levels]
    p1 += [Case("p1", "land_problem1.prm", "10x1x1 cells, 1 refinement, Q2", {"Global refinements": "1"}, 1)]
    # The penalty formulation's convergence in the bulk modulus (land_problem1.prm itself is
    # incompressible and mixed now; the mixed group sweeps kappa for the mixed formulation).
    kappa = [Case("p1", "land_problem1.prm", f"1 refinement, Q2 penalty, kappa = {k} kPa",
                  {"Global refinements": "1", "Material/Incompressibility": "penalty",
                   "Mechanics/Volumetric integration": "reduced",
                   "Material/Volumetric/Bulk modulus": str(k)}) for k in (200, 1000, 5000)]
    def ventricle(a: int, b: int, r: int) -> dict[str, str]:
        """a x b coarse cells (around the axis x from apex to base), r global refinements."""
        return {"Global refinements": str(r),
                "Geometry/Ellipsoid/Cells around circumference": str(a),
                "Geometry/Ellipsoid/Cells from apex to base": str(b)}

    p2 = [Case("p2", "land_problem2.prm", f"8x3x1 cells, {r} refinement(s), Q2", ventricle(8, 3, r))
          for r in levels]
    p2 += [Case("p2", "land_problem2.prm", "16x5x1 cells, 0 refinement(s), Q2", ventricle(16, 5, 0))]
    p2 += [Case("p2", "land_problem2.prm", "8x3x1 cells, 1 refinement, Q2", ventricle(8, 3, 1), 1)]

    # Problem 2 incompressible (mixed Q2-P1disc) in 10 equal load steps on both mesh families
    # of the scaling group, up to 511k DOFs (the iterative solver there: 'auto').
    p2i_levels = [(16, 5, 0), (16, 5, 1), (32, 10, 0), (32, 10, 1)] + (
        [] if args.quick else [(16, 5, 2), (32, 10, 2)])
    mixed10 = {"Material/Incompressibility": "incompressible", "Load steps": "10",
               "Mechanics/Adaptive load steps": "false"}
    p2i = [Case("p2-mixed", "land_problem2.prm", f"{a}x{b}x1 cells, {r} refinement(s), Q2-P1disc",
                {**ventricle(a, b, r), **mixed10})
           for a, b, r in p2i_levels]
    # The chord iterations the other way from the default ('auto': Anderson-accelerated,
    # depth 5, from 50 000 DOFs with the direct solver): accelerated below, plain above, on the
    # 16 x 5 levels the direct solver takes.
    def chords(depth: str, label: str, levels: list) -> list:
        return [Case("p2-mixed", "land_problem2.prm",
                     f"{a}x{b}x1 cells, {r} refinement(s), Q2-P1disc, {label}",
                     {**ventricle(a, b, r), **mixed10,
                      "Mechanics/Chord acceleration depth": depth})
                for a, b, r in levels]
    # The coarse test ventricle (8 x 3, 24 cells) and the coarsest mesh with two cells through
    # the wall: how far the wall resolution moves the epicardial apex.
    p2i += [Case("p2-mixed", "land_problem2.prm", "8x3x1 cells, 0 refinement(s), Q2-P1disc",
                 {**ventricle(8, 3, 0), **mixed10}),
            Case("p2-mixed", "land_problem2.prm", "16x5x2 cells, 0 refinement(s), Q2-P1disc",
                 {**ventricle(16, 5, 0), **mixed10, "Geometry/Ellipsoid/Cells through wall": "2"})]
    # The same study with the continuous pressure (Taylor-Hood Q2-Q1), from the 24-cell
    # ventricle on (on the finest level the iterative solver, without the augmented
    # Lagrangian: that is Q2-P1disc's only).
    p2th_levels = [(8, 3, 0), (16, 5, 0), (16, 5, 1), (32, 10, 0), (32, 10, 1)] + (
        [] if args.quick else [(16, 5, 2), (32, 10, 2)])
    p2i += [Case("p2-mixed", "land_problem2.prm", f"{a}x{b}x1 cells, {r} refinement(s), Q2-Q1",
                 {**ventricle(a, b, r), **mixed10, "Discretization/Pressure element": "continuous"})
            for a, b, r in p2th_levels]
    p2i += chords("5", "accelerated chords", [(16, 5, 0), (16, 5, 1)])
    p2i += chords("0", "plain chords", [] if args.quick else [(16, 5, 2)])

    # Problem 3: refine the coarse mesh (cells around x from apex to base) and globally.
    p3_levels = [(8, 3, 0), (16, 5, 0), (8, 3, 1), (16, 5, 1)] + ([] if args.quick else [(8, 3, 2)])
    # (land_problem3.prm itself is incompressible and refined at the apex now.)
    p3_penalty = {"Material/Incompressibility": "penalty",
                  "Material/Volumetric/Bulk modulus": "1000"}
    p3 = [Case("p3", "land_problem3.prm", f"{a}x{b}x1 cells, {r} refinement(s), Q2",
               {**ventricle(a, b, r), **p3_penalty, "Geometry/Local refinements": "0"})
          for a, b, r in p3_levels]

    # Problem 3 refined at the apex (the fibre direction is undefined on the axis): global
    # level and local refinements within 1.5 mm of the mid-wall apex.
    p3a_levels = [(8, 3, 1, 1), (8, 3, 1, 2)] + ([] if args.quick else [
        (16, 5, 1, 2), (8, 3, 2, 1), (8, 3, 1, 3), (16, 5, 1, 3), (8, 3, 2, 2)])
    p3a = [Case("p3", "land_problem3.prm",
                f"{a}x{b}x1 cells, {r} refinement(s), apex refined {l} time(s), Q2",
                {**ventricle(a, b, r), **p3_penalty, "Geometry/Local refinements": str(l),
                 "Geometry/Local refinement radius": "1.5"}) for a, b, r, l in p3a_levels]

    # The same, incompressible (mixed Q2-P1disc, as in Land et al. 2015): the penalty
    # formulation's Newton fails at 6 % of the load once the cells on the axis are 4 levels
    # deep (docs/verification.md), the mixed one does not.
    # Ordered by the level of the cells on the axis (global + local refinements).
    p3i_levels = [(8, 3, 1, 0), (8, 3, 1, 1), (8, 3, 2, 0), (8, 3, 1, 2)] + ([] if args.quick else [
        (8, 3, 2, 1), (8, 3, 1, 3), (8, 3, 2, 2), (8, 3, 1, 4)])
    p3i = [Case("p3", "land_problem3.prm",
                f"{a}x{b}x1 cells, {r} refinement(s), apex refined {l} time(s), Q2-P1disc",
                {**ventricle(a, b, r), "Geometry/Local refinements": str(l),
                 "Geometry/Local refinement radius": "1.5",
                 "Material/Incompressibility": "incompressible"})
           for a, b, r, l in p3i_levels]

    # Refined at each apex point in turn (0.75 mm around it), incompressible: the level of
    # the cells at the point sets its value (docs/verification.md).
    p3p = [Case("p3", "land_problem3.prm",
                f"8x3x1 cells, 1 refinement, {l} more within 0.75 mm of the {name} apex, Q2-P1disc",
                {**ventricle(8, 3, 1), "Geometry/Local refinements": str(l),
                 "Geometry/Local refinement center": center,
                 "Geometry/Local refinement radius": "0.75",
                 "Material/Incompressibility": "incompressible"})
           for name, center in (("endocardial", "0, 0, -17"), ("epicardial", "0, 0, -20"))
           for l in ((3,) if args.quick else (3, 4))]

    fibre_cases = [("Land, 8x3x1 cells, 1 refinement", {**LAND_LV, "Global refinements": "1"}),
                   ("Land, 8x3x1 cells, 2 refinements", {**LAND_LV, "Global refinements": "2"}),
                   ("human-size, 16x5x1 cells, 0 refinements", {**HUMAN_LV, "Global refinements": "0"}),
                   ("human-size, 16x5x1 cells, 1 refinement", {**HUMAN_LV, "Global refinements": "1"}),
                   ("human-size, 16x5x1 cells, 2 refinements", {**HUMAN_LV, "Global refinements": "2"})]

    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp)
        sections = {}
        for title, cases, columns, note in (
            ("Land problem 1 (beam): deflection", p1, ["beam_tip_z"],
             "Reference: 4.17 mm, converged codes 4.151 ... 4.185 mm. Incompressible, mixed "
             "Q2-P1disc (parameters/land_problem1.prm)."),
            ("Land problem 1: bulk modulus", kappa, ["beam_tip_z"],
             "The penalty result as the bulk modulus grows (near-incompressibility)."),
            ("Land problem 2 (inflation)", p2, ["endo_apex_z", "epi_apex_z"],
             "Reference: endocardial apex -26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm "
             "(-28.5 ... -28.1). Bulk modulus 1000 kPa."),
            ("Land problem 2: incompressible, up to 511k DOFs", p2i,
             ["endo_apex_z", "epi_apex_z"],
             "Incompressible (mixed Q2-P1disc, the isochoric part of the Guccione law), 10 "
             "equal load steps, on the two mesh families of the scaling group (16 x 5 and "
             "32 x 10 coarse cells, refined 0-2 times), 2 ranks, the `auto` linear solver "
             "(direct up to 200 000 DOFs, iterative above) and the default Mechanics / Chord "
             "acceleration depth = auto (the direct solver's chord iterations Anderson-"
             "accelerated with depth 5 from 50 000 DOFs, plain below); 'accelerated chords': "
             "depth 5, 'plain chords': depth 0. The rows 'Q2-Q1' are the same study with the "
             "continuous pressure (Taylor-Hood, `Discretization / Pressure element = "
             "continuous`; at 467k DOFs the iterative solver without the augmented "
             "Lagrangian, which is Q2-P1disc's only). Reference: "
             "endocardial apex "
             "-26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm (-28.5 ... -28.1)."),
            ("Land problem 3 (inflation and active contraction)", p3,
             ["endo_apex_z", "epi_apex_z", "midwall_apex_z", "midwall_equator_x",
              "midwall_equator_y", "midwall_equator_z"],
             "Analytic helix fibres +90/-90 degrees, T_a = 60 kPa, 15 kPa, bulk modulus 1000 kPa. "
             "The mesh is refined both ways: more coarse cells (around the axis x from apex to "
             "base; `Geometry / Ellipsoid`) and global refinement. Points: the endocardial "
             "(0, 0, -17) and epicardial (0, 0, -20) apex, and the midwall line at v = 0 "
             "(t = 0.5) at its apex (0, 0, -18.5) and at the equator (-8.5, 0, 0). Sign check: "
             "the midwall line at v = 0 twists toward +y (midwall_equator_y > 0). The reference "
             "values are checked independently of this table."),
            ("Land problem 3: refinement at the apex", p3a,
             ["endo_apex_z", "epi_apex_z", "midwall_apex_z", "midwall_equator_y"],
             "The analytic helix fibre direction is undefined on the axis, so the apex "
             "displacements converge slowly under global refinement. Here the cells with a "
             "vertex within 1.5 mm of the mid-wall apex (0, 0, -18.5) are refined again "
             "(`Geometry / Local refinements`, hanging nodes), on top of the global level."),
            ("Land problem 3: incompressible, refined at the apex", p3i,
             ["endo_apex_z", "epi_apex_z", "midwall_apex_z", "midwall_equator_y"],
             "Incompressible (mixed Q2-P1disc, `Material / Incompressibility = incompressible`, "
             "as in Land et al. 2015), otherwise the cases of the penalty table above: the "
             "cells with a vertex within 1.5 mm of the mid-wall apex are refined again on top "
             "of the global level. The level of the cells at the apex points (global + "
             "local refinements) sets the apex values."),
            ("Land problem 3: refined at each apex", p3p,
             ["endo_apex_z", "epi_apex_z", "midwall_apex_z", "midwall_equator_y"],
             "Incompressible (mixed Q2-P1disc). 8x3x1 cells refined once, then the cells with "
             "a vertex within 0.75 mm of one apex point, (0, 0, -17) or (0, 0, -20), 3 or 4 "
             "more times (`Geometry / Local refinement center`): the cells at that point are 4 "
             "or 5 levels deep, the rest of the axis much coarser."),
        ):
            if args.only and cases[0].problem != args.only:
                continue
            rows = []
            for case in cases:
                print(f"running {case.problem} {case.label} on {case.ranks} rank(s) ...", flush=True)
                rows.append(run(case, args.build, workdir))
            extra = ((p3_axis_note(rows) if cases is p3i else
                      p3_point_note(rows) if cases is p3p else p3_note(rows))
                     if cases[0].problem == "p3" else
                     p2_band_note(rows, "Q2-P1disc") + p2_band_note(rows, "Q2-Q1")
                     if cases is p2i else "")
            chords = cases[0].problem in ("p3", "p2-mixed")
            sections[title] = f"## {title}\n{note}{extra}\n\n{table(rows, columns, chords=chords)}\n"
            print(sections[title], flush=True)

        if args.only in (None, "fibres"):
            rows = []
            for label, changes in fibre_cases:
                print(f"running systole-fibres on the {label} ventricle ...", flush=True)
                rows.append(run_fibres(label, changes, args.build, workdir))
            print("running systole-unit [dti-bench] ...", flush=True)
            sections["Fibre generators"] = fibre_section(rows, run_dti_bench(args.build))
            print(sections["Fibre generators"], flush=True)

        if args.only in (None, "heartbeat"):
            rows = []
            for ranks in (2, 1):
                print(f"running the default heartbeat on {ranks} rank(s) ...", flush=True)
                rows.append(run_heartbeat(ranks, args.build, workdir))
            rows.sort(key=lambda r: r["ranks"])
            sections["Default heartbeat (parameters/lv_heartbeat.prm)"] = heartbeat_section(rows)
            print(sections["Default heartbeat (parameters/lv_heartbeat.prm)"], flush=True)

        if args.only in (None, "biv"):
            rows = []
            for ranks in (2, 1):
                print(f"running one BiV beat on {ranks} rank(s) ...", flush=True)
                rows.append(run_biv(ranks, args.build, workdir))
            rows.sort(key=lambda r: r["ranks"])
            sections[BIV_TITLE] = biv_section(rows)
            print(sections[BIV_TITLE], flush=True)

        if args.only in (None, "badinput"):
            # The bad-input sweep: 600 mutated parameter cases and every mesh case.
            from bad_input_sweep import SECTION_TITLE
            print("running the bad-input sweep (about 15 minutes) ...", flush=True)
            markdown = workdir / "bad_input.md"
            subprocess.run([sys.executable, str(ROOT / "scripts" / "bad_input_sweep.py"),
                            "--systole", str(args.build / "systole"), "--sample", "600",
                            "--markdown", str(markdown)], check=False)
            sections[SECTION_TITLE] = markdown.read_text()
            print(sections[SECTION_TITLE], flush=True)

        if args.only in (None, "checkpoint"):
            title = "Checkpoints of the default heartbeat (parameters/lv_heartbeat.prm)"
            print("running one beat of the default heartbeat with checkpoints ...", flush=True)
            sections[title] = checkpoint_section([run_checkpoint(2, args.build, workdir)])
            print(sections[title], flush=True)

        if args.only in (None, "ep"):
            sections.update(ep_sections(args.build, workdir, args.quick))
        if args.only in (None, "land"):
            title = ("Excitation-contraction coupling: Frank-Starling and the ESPVR "
                     f"({'parameters/lv_heartbeat_ttp_land.prm' if args.full else 'the coarse ventricle'})")
            sections[title] = land_section(args.build, workdir, args.full, args.jobs)
            print(sections[title], flush=True)
        if args.only in (None, "niederer"):
            title = "Electrophysiology: the Niederer et al. 2011 benchmark"
            sections[title] = niederer_section(args.build, workdir, args.quick, args.full)
            print(sections[title], flush=True)
        if args.only in (None, "inverse"):
            title = "Cost of unloading and calibration (2 ranks)"
            sections[title] = inverse_section(args.build, workdir)
            print(sections[title], flush=True)
        if args.only in (None, "ep-lv"):
            title = "Electrophysiology: the default heartbeat's ventricle"
            sections[title] = ep_lv_section(args.build, workdir, args.quick)
            print(sections[title], flush=True)
        if args.only in (None, "mixed"):
            title = "Mechanics: penalty and mixed formulations, direct and iterative solvers"
            sections[title] = mixed_section(args.build, workdir, args.quick)
            print(sections[title], flush=True)
        for group, title in (("scaling", SCALING_TITLE), ("scaling-th", SCALING_TH_TITLE)):
            if args.only in (None, group):
                sections[title] = scaling_section(args.build, workdir, args.quick,
                                                  th=group == "scaling-th")
                print(sections[title], flush=True)
        if args.only in (None, "tet"):
            from bench_tet import TITLE as TET_TITLE, tet_section
            sections[TET_TITLE] = tet_section(args.build, workdir, args.full, run, Case)
            print(sections[TET_TITLE], flush=True)
        if args.only in (None, "large"):
            sections[LARGE_TITLE] = large_section(args.build, workdir)
            print(sections[LARGE_TITLE], flush=True)
        if args.only in (None, "arostica"):
            sections[AROSTICA_TITLE] = arostica_section(args.build, workdir, args.quick)
            print(sections[AROSTICA_TITLE], flush=True)
        if args.only in (None, "laws"):
            title = "Land problem 2 with the isotropic laws at the same shear modulus"
            sections[title] = laws_section(args.build, workdir)
            print(sections[title], flush=True)

        if args.only in (None, "circulation"):
            title = "0D closed loop (Problem = circulation)"
            print("running the 0D closed loop ...", flush=True)
            sections[title] = circulation_section(args.build, workdir)
            print(sections[title], flush=True)

        if args.only in (None, "cell"):
            title = "Single cell: ten Tusscher-Panfilov 2006 against SciPy"
            print("running the single cells ...", flush=True)
            sections[title] = cell_section(args.build, workdir)

        if args.only in (None, "postprocess"):
            title = POSTPROCESS_TITLE
            sections[title] = postprocess_section(args.build)
            print(sections[title], flush=True)

    if args.no_write:
        return 0
    write_docs(args.output, sections, replace_only=args.only is not None)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
