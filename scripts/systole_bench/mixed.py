"""The group 'mixed': penalty and mixed formulations, direct and iterative solvers."""

from __future__ import annotations

from pathlib import Path

from .core import BUSY_NOTE, LAND2_PENALTY, Case, run


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


def mixed_series(build: Path, workdir: Path, quick: bool) -> dict[str, list]:
    """Land problem 1 refined 1, 2 (and 3) times: formulation -> [(refinements, row)]."""
    levels = [1, 2] + ([] if quick else [3])
    series = {}
    for formulation, changes in MIXED_FORMULATIONS:
        for r in levels:
            case = Case("mixed", "land_problem1.prm", f"{formulation}, {r} refinement(s)",
                        {"Global refinements": str(r), **changes})
            print(f"running Land problem 1, {case.label} on {case.ranks} rank(s) ...", flush=True)
            series.setdefault(formulation, []).append((r, run(case, build, workdir)))
    return series


def krylov_growth(series: dict[str, list]) -> list[str]:
    """How the iterative solver's Krylov iterations per solve grow with the refinement."""
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
    return growth


def kappa_sweep(series: dict[str, list], build: Path, workdir: Path) -> tuple[list, list[str]]:
    """The bulk-modulus sweep of the nearly incompressible formulation (iterative) at 1
    refinement, up to the incompressible run of the series: its rows and its growth line."""
    sweep, growth = [], []
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
    return sweep, growth


def p2_runs(build: Path, workdir: Path, quick: bool) -> list[tuple[str, dict]]:
    """Land problem 2, penalty and incompressible, refined 0 (and 1) times."""
    # Land problem 2 on the 16 x 5 ventricle and refined once: the penalty formulation
    # and the incompressible mixed formulation in 10 equal load steps.
    p2_rows = []
    for label, changes in (
            ("penalty (the file until 2026-12-07)", {}),
            ("incompressible, 10 equal load steps",
             {"Material/Incompressibility": "incompressible", "Load steps": "10",
              "Mechanics/Adaptive load steps": "false"}),
            ("incompressible, 10 equal load steps, pure Newton",
             {"Material/Incompressibility": "incompressible", "Load steps": "10",
              "Mechanics/Adaptive load steps": "false",
              "Mechanics/Reuse factorization": "false"})):
        for r in [0] + ([] if quick else [1]):
            case = Case("mixed", "land_problem2.prm", f"{label}, {r} refinement(s)",
                        {**LAND2_PENALTY, "Global refinements": str(r), **changes})
            print(f"running Land problem 2, {case.label} on {case.ranks} rank(s) ...", flush=True)
            p2_rows.append((f"{label}, {r}", run(case, build, workdir)))
    return p2_rows


def mixed_section(build: Path, workdir: Path, quick: bool) -> str:
    """Land problem 1 refined 1, 2 (and 3) times with the incompressible mixed formulation
    (direct and iterative solvers) and the penalty (direct), and a bulk-modulus sweep of the
    nearly incompressible formulation (iterative) at 1 refinement."""
    series = mixed_series(build, workdir, quick)
    rows = [(f"{r}", row) for formulation, _ in MIXED_FORMULATIONS
            for r, row in series[formulation]]
    growth = krylov_growth(series)
    sweep, sweep_growth = kappa_sweep(series, build, workdir)
    growth += sweep_growth
    p2_rows = p2_runs(build, workdir, quick)
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
        "Land problem 2 (`parameters/land_problem2.prm` as shipped until 2026-12-07: the 16 x 5 "
        "ventricle, Q2, direct solver), refined 0 (and 1) times: the penalty file and the incompressible mixed "
        "formulation (isochoric part of the Guccione law) in 10 equal load steps, with the "
        "default modified Newton and with pure Newton (Reuse factorization = false). Reference: "
        "endocardial apex -26.6 mm (-26.9 ... -26.4), epicardial apex -28.3 mm (-28.5 ... "
        "-28.1).\n\n"
        + mixed_table(p2_rows, "formulation, refinements", "endo / epi apex z [mm]") + "\n")


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "Mechanics: penalty and mixed formulations, direct and iterative solvers"
    text = mixed_section(args.build, workdir, args.quick)
    print(text, flush=True)
    return {title: text}
