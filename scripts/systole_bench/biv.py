"""The group 'biv': the BiV heartbeat's cost (tests/runs/biv_heartbeat_coarse.prm)."""

from __future__ import annotations

from pathlib import Path

from systole_post.results import read_results

from .core import BUSY_NOTE, ROOT, failed_row, run_watched


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


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    rows = []
    for ranks in (2, 1):
        print(f"running one BiV beat on {ranks} rank(s) ...", flush=True)
        rows.append(run_biv(ranks, args.build, workdir))
    rows.sort(key=lambda r: r["ranks"])
    text = biv_section(rows)
    print(text, flush=True)
    return {BIV_TITLE: text}
