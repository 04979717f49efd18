"""The group 'heartbeat': the default heartbeat (parameters/lv_heartbeat.prm) on 2 and 1
ranks, its beat table and cost.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from systole_post.cavities import ventricles
from systole_post.results import read_results

from .core import BUSY_NOTE, ROOT, failed_row, run_watched


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


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    rows = []
    for ranks in (2, 1):
        print(f"running the default heartbeat on {ranks} rank(s) ...", flush=True)
        rows.append(run_heartbeat(ranks, args.build, workdir))
    rows.sort(key=lambda r: r["ranks"])
    text = heartbeat_section(rows)
    print(text, flush=True)
    return {"Default heartbeat (parameters/lv_heartbeat.prm)": text}
