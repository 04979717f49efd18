"""The groups 'scaling' and 'scaling-th': the iterative solver from 2.7k to 511k DOFs (Land
problem 2, 2 ranks), Q2-P1disc and the Taylor-Hood element.
"""

from __future__ import annotations

import os
import resource
from pathlib import Path

from .core import BUSY_NOTE, Case, run


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
#: solve: the second iteration of the second step.) Every solve to the Linear solver
#: tolerance (Inexact Newton = false): the Krylov iterations per solve measure the
#: preconditioner, not the forcing terms.
SCALING_PROBLEM = {"Pressure": "2", "Load steps": "2",
                   "Mechanics/Adaptive load steps": "false",
                   "Mechanics/Reuse factorization": "false",
                   "Mechanics/Linear solver": "iterative",
                   "Mechanics/Inexact Newton": "false"}


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
        "set-up at every iteration; `Inexact Newton = false`: every solve to the Linear solver "
        "tolerance), the same at every level, so that the largest run stays affordable; "
        "the per-iteration figures come from its real Newton iterations. Assembly and linear "
        "solver: rank 0's wall time in those timer sections (`/summary`), over the Newton "
        "iterations; the ratio is that of the time per Newton iteration per DOF to the 16 x 5 "
        f"level refined once ({'16.7k DOFs' if th else '17.9k DOFs mixed'}) of the same "
        "formulation. The CPU time is that "
        "of all processes of the run (set-up included), less sensitive to the other work on "
        "the machine than the wall times; the load average is the 1-minute one when the run "
        "ended (2 cores: above 2 the wall times are inflated).\n\n"
        + "\n".join(lines) + "\n\n" + " ".join(growth) + "\n")


def sections(args, workdir: Path) -> dict[str, str]:
    """The group 'scaling': its section {title: text}."""
    text = scaling_section(args.build, workdir, args.quick)
    print(text, flush=True)
    return {SCALING_TITLE: text}


def th_sections(args, workdir: Path) -> dict[str, str]:
    """The group 'scaling-th': its section {title: text}."""
    text = scaling_section(args.build, workdir, args.quick, th=True)
    print(text, flush=True)
    return {SCALING_TH_TITLE: text}
