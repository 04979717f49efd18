"""The group 'fibres': the fibre generators' costs (systole-fibres, which writes no results
file: the rule-based solves it logs) and the DTI mapping time of the hidden unit test
[dti-bench].
"""

from __future__ import annotations

import re
import time
from pathlib import Path

from systole_post.results import read_results

from .core import BUSY_NOTE, ROOT, run_watched, with_changes


#: Ventricles of the fibre-generator costs: Geometry / Ellipsoid entries.
LAND_LV = {}
HUMAN_LV = {"Geometry/Ellipsoid/Endocardium short radius": "23",
            "Geometry/Ellipsoid/Endocardium long radius": "84",
            "Geometry/Ellipsoid/Epicardium short radius": "33",
            "Geometry/Ellipsoid/Epicardium long radius": "92",
            "Geometry/Ellipsoid/Cells around circumference": "16",
            "Geometry/Ellipsoid/Cells from apex to base": "5"}

#: The ventricles of the table: (label, Geometry entries).
CASES = [("Land, 8x3x1 cells, 1 refinement", {**LAND_LV, "Global refinements": "1"}),
         ("Land, 8x3x1 cells, 2 refinements", {**LAND_LV, "Global refinements": "2"}),
         ("human-size, 16x5x1 cells, 0 refinements", {**HUMAN_LV, "Global refinements": "0"}),
         ("human-size, 16x5x1 cells, 1 refinement", {**HUMAN_LV, "Global refinements": "1"}),
         ("human-size, 16x5x1 cells, 2 refinements", {**HUMAN_LV, "Global refinements": "2"})]

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


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    rows = []
    for label, changes in CASES:
        print(f"running systole-fibres on the {label} ventricle ...", flush=True)
        rows.append(run_fibres(label, changes, args.build, workdir))
    print("running systole-unit [dti-bench] ...", flush=True)
    text = fibre_section(rows, run_dti_bench(args.build))
    print(text, flush=True)
    return {"Fibre generators": text}
