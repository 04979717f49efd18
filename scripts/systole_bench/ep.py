"""The group 'ep': the Niederer slab refined in h and dt, the EP time step, and the conduction
velocities along and across the fibres. Its runs and cost cells serve 'ep-lv' and 'niederer'.
"""

from __future__ import annotations

import re
from pathlib import Path

from systole_post.results import read_results

from .core import BUSY_NOTE, ROOT, failed_row, run_watched, with_changes


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


def slab_sections(build: Path, workdir: Path, quick: bool) -> dict[str, str]:
    """The Niederer slab with each model, h and dt refined together."""
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
    return sections


def time_step_section(build: Path, workdir: Path) -> dict[str, str]:
    """The Aliev-Panfilov slab at h = 0.5 mm with decreasing EP time steps."""
    rows = []
    for dt in (0.8, 0.4, 0.2, 0.1, 0.05):
        print(f"running the Aliev-Panfilov slab, h = 0.5 mm, dt = {dt} ms ...", flush=True)
        changes = {"Global refinements": "0", "Time/Time step": "4",
                   "Electrophysiology/Time step": str(dt)}
        rows.append(run_ep(f"{dt} ms", changes, 1, build, workdir))
    title = "Electrophysiology: time step"
    section = (
        f"## {title}\nThe Aliev-Panfilov slab at h = 0.5 mm (1 rank) with decreasing EP time "
        "steps (IMEX ARK-4(2)3, SUNDIALS' ARK324L2SA pair; the steps end at the stimulus "
        "switching times, so the charge delivered is exact and the method keeps its order; "
        "inside the 2 ms stimulus the 0.8 ms steps are shortened to 2/3 ms). The time-step "
        "error is far below the mesh error of the tables above.\n\n" + ep_step_table(rows) + "\n")
    print(section, flush=True)
    return {title: section}


def cv_section(build: Path, workdir: Path) -> dict[str, str]:
    """The conduction velocities along and across the fibres on cables."""
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
    section = (
        f"## {title}\n20 mm cables (1 x 1 mm, 2 x 2 cells across) along x (fibres along the "
        "cable) and along y (fibres across it), stimulated over their first 1.5 mm; CV = 8 mm "
        "over the activation-time difference between 8 and 16 mm, far from the stimulus and "
        f"the sealed end. Expected ratio sqrt(sigma_l/sigma_t) = {EP_CV_RATIO:.3f} (the "
        "monodomain with one ionic model scales speeds with sqrt(D)). The Aliev-Panfilov "
        "travelling-wave speed sqrt(D k/(2T)) (1 - 2a) is 0.120 m/s along the fibres.\n\n"
        + ep_cv_table(cv_rows) + "\n")
    print(section, flush=True)
    return {title: section}


def ep_sections(build: Path, workdir: Path, quick: bool) -> dict[str, str]:
    """Refinement of the Niederer slab (h with dt, then dt alone) and the conduction
    velocities along and across the fibres."""
    return {**slab_sections(build, workdir, quick), **time_step_section(build, workdir),
            **cv_section(build, workdir)}


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's sections {title: text}."""
    return ep_sections(args.build, workdir, args.quick)
