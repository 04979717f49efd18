#!/usr/bin/env python3
"""Benchmarks of Systole: refinement studies of the Land et al. 2015 problems.

Runs each case through the systole app (1 or 2 MPI ranks), reads the results file and the
log (wall time, peak memory, Newton iterations), and writes docs/verification.md.
Timings are what this machine measured; they are reported, never asserted.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
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
    """Replace 'set NAME = ...' lines (each NAME must occur once) or append at top level."""
    for key, value in changes.items():
        pattern = re.compile(rf"^(\s*set {re.escape(key)}\s*=).*$", re.MULTILINE)
        if pattern.search(text):
            text = pattern.sub(rf"\g<1> {value}", text, count=1)
        else:
            raise KeyError(f"no entry '{key}' in the base file")
    return text


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
    out = subprocess.run(command, cwd=workdir, capture_output=True, text=True)
    row = {"case": case, "ok": out.returncode == 0}
    log = out.stdout
    if out.returncode != 0:
        row["error"] = (out.stderr.strip().splitlines() or ["?"])[0]
        return row
    row["dofs"] = int(re.search(r"(\d+) DOFs", log).group(1))
    match = re.search(r"Wall time ([\d.]+) s; peak memory ([\d.]+) MiB per rank", log)
    row["wall"], row["memory"] = float(match.group(1)), float(match.group(2))
    results = read_results(workdir / "results" / name / "results.h5")
    ts = results.timeseries
    row["values"] = {k: ts[k][-1] for k in ts if k.endswith(("apex_z", "tip_z", "equator_y"))}
    newton = ts["newton_iterations"][1:]
    row["steps"] = len(newton)
    row["newton"] = int(np.sum(newton))
    row["newton_per_step"] = " ".join(str(int(n)) for n in newton)
    row["cut"] = len(re.findall(r"cutting the load step", log))
    return row


def table(rows: list[dict], columns: list[str]) -> str:
    """Markdown table of finished runs."""
    head = "| resolution | ranks | DOFs | " + " | ".join(columns) + \
        " | load steps (cuts) | Newton iterations per step | wall [s] | peak memory per rank [MiB] |"
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        c = r["case"]
        if not r["ok"]:
            lines.append(f"| {c.label} | {c.ranks} | failed: {r['error']} |")
            continue
        values = " | ".join(f"{r['values'][k]:.3f}" for k in columns)
        lines.append(f"| {c.label} | {c.ranks} | {r['dofs']} | {values} | {r['steps']} ({r['cut']}) "
                     f"| {r['newton_per_step']} | {r['wall']:.1f} | {r['memory']:.0f} |")
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", type=Path, default=ROOT / "build")
    parser.add_argument("--quick", action="store_true", help="skip the finest levels")
    parser.add_argument("--output", type=Path, default=ROOT / "docs" / "verification.md")
    parser.add_argument("--only", choices=["p1", "p2", "p3"],
                        help="run one problem and print its table (docs are not rewritten)")
    args = parser.parse_args()

    levels = [0, 1] if args.quick else [0, 1, 2]
    p1 = [Case("p1", "land_problem1.prm", f"10x1x1 cells, {r} refinement(s), Q2",
               {"Global refinements": str(r)}) for r in levels]
    p1 += [Case("p1", "land_problem1.prm", "10x1x1 cells, 1 refinement, Q2", {"Global refinements": "1"}, 1)]
    kappa = [Case("p1", "land_problem1.prm", f"1 refinement, Q2, kappa = {k} kPa",
                  {"Global refinements": "1", "Bulk modulus": str(k)}) for k in (200, 1000, 5000)]
    p2 = [Case("p2", "land_problem2.prm", f"8x3x1 cells, {r} refinement(s), Q2",
               {"Global refinements": str(r)}) for r in levels]
    p2 += [Case("p2", "land_problem2.prm", "8x3x1 cells, 1 refinement, Q2", {"Global refinements": "1"}, 1)]

    p3 = [Case("p3", "land_problem3.prm", f"8x3x1 cells, {r} refinement(s), Q2",
               {"Global refinements": str(r)}) for r in [0, 1]]

    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp)
        sections = []
        for title, cases, columns, note in (
            ("Land problem 1 (beam): deflection", p1, ["beam_tip_z"],
             "Reference: 4.17 mm, converged codes 4.151 ... 4.185 mm. Bulk modulus 1000 kPa."),
            ("Land problem 1: bulk modulus", kappa, ["beam_tip_z"],
             "The penalty result as the bulk modulus grows (near-incompressibility)."),
            ("Land problem 2 (inflation)", p2, ["endo_apex_z", "epi_apex_z"],
             "Reference: endocardial apex -26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm "
             "(-28.5 ... -28.1). Bulk modulus 1000 kPa."),
            ("Land problem 3 (inflation and active contraction)", p3,
             ["endo_apex_z", "epi_apex_z", "midwall_equator_y"],
             "Analytic helix fibres +90/-90 degrees, T_a = 60 kPa, 15 kPa. The reference values are "
             "checked independently; sign check: the midwall line at v = 0 twists toward +y "
             "(midwall_equator_y > 0). Refinement 2 (35 000 DOFs) is not run: the direct solver "
             "needs about 6 s per Newton iteration there."),
        ):
            if args.only and cases[0].problem != args.only:
                continue
            rows = []
            for case in cases:
                print(f"running {case.problem} {case.label} on {case.ranks} rank(s) ...", flush=True)
                rows.append(run(case, args.build, workdir))
            sections.append(f"## {title}\n{note}\n\n{table(rows, columns)}\n")
            print(sections[-1], flush=True)

    header = ("# Verification\n\nWritten by `scripts/bench` (do not edit by hand). Values are the "
              "deformed z coordinates [mm] at the last load step; timings are wall-clock seconds "
              "on this machine (2 cores), including start-up, and vary by some 10 %.\n\n")
    if args.only:
        return 0
    args.output.write_text(header + "\n".join(sections))
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
