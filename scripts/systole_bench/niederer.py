"""The group 'niederer': the Niederer et al. 2011 benchmark."""

from __future__ import annotations

import math
from pathlib import Path

from .core import BUSY_NOTE
from .ep import EP_COST_HEAD, ep_cost_cells, run_ep


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


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "Electrophysiology: the Niederer et al. 2011 benchmark"
    text = niederer_section(args.build, workdir, args.quick, args.full)
    print(text, flush=True)
    return {title: text}
