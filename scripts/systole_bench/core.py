"""The shared machinery of the bench groups: a case (a parameter file with entries
replaced), running it through the systole app, reading its results file into a table row, the
common table, and writing docs/verification.md.

Timings are what this machine measured; they are reported, never asserted.
"""

from __future__ import annotations

import os
import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from systole_post.results import read_results


#: The repository (scripts/systole_bench/core.py is two levels below it).
ROOT = Path(__file__).resolve().parents[2]


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


def ventricle(a: int, b: int, r: int) -> dict[str, str]:
    """a x b coarse cells (around the axis x from apex to base), r global refinements."""
    return {"Global refinements": str(r),
            "Geometry/Ellipsoid/Cells around circumference": str(a),
            "Geometry/Ellipsoid/Cells from apex to base": str(b)}


#: parameters/land_problem2.prm as shipped until 2026-12-07, which the groups p2, laws and mixed
#: study: the penalty formulation (Bulk modulus 1000 kPa) on the 16 x 5 ventricle. (The file is
#: now the incompressible mixed formulation on 32 x 10 cells.)
LAND2_PENALTY = {"Material/Incompressibility": "penalty", **ventricle(16, 5, 0)}


def case_table(title: str, cases: list[Case], columns: list[str], note: str, build: Path,
               workdir: Path, extra=None, chords: bool = False) -> dict[str, str]:
    """Run the cases one after the other; their section {title: text}: the note, the text
    extra(rows) adds (if given), and the table of the given value columns (chords: also the
    chord iterations per step)."""
    rows = []
    for case in cases:
        print(f"running {case.problem} {case.label} on {case.ranks} rank(s) ...", flush=True)
        rows.append(run(case, build, workdir))
    text = extra(rows) if extra else ""
    section = f"## {title}\n{note}{text}\n\n{table(rows, columns, chords=chords)}\n"
    print(section, flush=True)
    return {title: section}
