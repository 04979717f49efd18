"""The group 'tet': Land problem 2 on tetrahedra against hexahedra (scripts/bench --only tet).

Two tables, every run on 2 ranks in one session (the machine is shared: compare within it):
1. Accuracy and cost: Land problem 2 (incompressible, 10 equal load steps, Taylor-Hood) on the
   tetrahedral ventricles of cardiac-geometries (the shipped 3 mm mesh, the reference meshes
   of ../shared/data/lv_tet when present, and with --full a finer one written by
   scripts/make_tet_meshes.py) and on the hexahedral ventricles of the same size, the apexes
   against the published band.
2. Cost per Newton iteration at about equal DOFs: the scaling group's problem (2 kPa in two
   load steps, pure Newton, the iterative solver), time per Newton iteration per DOF, Krylov
   iterations per solve, memory per DOF.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from .core import ROOT, Case, run

SHARED = ROOT.parent / "shared" / "data" / "lv_tet"
TITLE = "Mechanics on tetrahedra: Land problem 2, tetrahedra against hexahedra (2 ranks)"
#: Land problem 2's band along the long axis (x for the cardiac-geometries meshes, z for the
#: generated ones) [mm].
BAND = {"endo": (-26.9, -26.4), "epi": (-28.5, -28.1)}
#: The scaling group's problem (scaling.SCALING_PROBLEM): two load steps to 2 kPa, pure Newton.
PER_NEWTON = {"Pressure": "2", "Load steps": "2", "Mechanics/Reuse factorization": "false",
              "Mechanics/Linear solver": "iterative", "Mechanics/Inexact Newton": "false"}
HEX_TAYLOR_HOOD = {"Material/Incompressibility": "incompressible",
                   "Discretization/Pressure element": "continuous",
                   "Mechanics/Adaptive load steps": "false", "Load steps": "10",
                   "Mechanics/Newton relative tolerance": "1e-6"}


def tet_meshes(workdir: Path, full: bool) -> list[tuple[str, Path]]:
    """(label, .msh) of the tetrahedral ventricles of the study."""
    meshes = [("shipped, 3 mm", ROOT / "meshes" / "lv_ellipsoid_tet.msh")]
    if (SHARED / "psize1.5" / "lv_ellipsoid.msh").exists():
        meshes.append(("shared psize1.5", SHARED / "psize1.5" / "lv_ellipsoid.msh"))
    if full:
        out = workdir / "tet_1mm"
        done = subprocess.run([sys.executable, str(ROOT / "scripts" / "make_tet_meshes.py"),
                               "--out", str(out), "--only", "lv", "--lv-psize", "1.0"],
                              capture_output=True, text=True)
        if done.returncode == 0:
            meshes.append(("generated, 1 mm", out / "lv_ellipsoid_tet.msh"))
    return meshes


def apexes(row: dict, axis: str) -> str:
    """'endo / epi' [mm] with a mark for values outside the band."""
    cells = []
    for point in ("endo", "epi"):
        value = row["values"][f"{point}_apex_{axis}"]
        low, high = BAND[point]
        cells.append(f"{value:.3f}" + ("" if low <= value <= high else " (out)"))
    return " / ".join(cells)


def cost(row: dict) -> str:
    """Newton (chords), Krylov per solve, wall, per Newton iteration per DOF, memory per DOF."""
    s = row["summary"]
    n = max(1.0, s["newton_iterations"] + s.get("chord_iterations", 0.0))
    per_dof = 1e6 * (s["assembly_seconds"] + s["linear_solver_seconds"]) / n / s["n_dofs"]
    memory = 2 * row["memory"] * 2**20 / s["n_dofs"] / 1024
    busy = " *" if row.get("busy") else ""
    return (f"{s['newton_iterations']:.0f} ({s.get('chord_iterations', 0):.0f}) "
            f"| {s['linear_iterations_per_solve']:.1f} | {row['wall']:.1f}{busy} "
            f"| {per_dof:.1f}{busy} | {memory:.1f} |")


def tet_runs(build: Path, workdir: Path, full: bool) -> tuple[list, list]:
    """The runs of both tables: (cells, label, axis, row) and (cells, label, row)."""
    accuracy, per_newton = [], []
    for label, mesh in tet_meshes(workdir, full):
        changes = {"Mesh file": str(mesh)}
        print(f"running Land problem 2 on the tetrahedral ventricle {label} ...", flush=True)
        accuracy.append(("tetrahedra", label, "x",
                         run(Case("tet", "lv_tet_inflation.prm", label, changes), build, workdir)))
        per_newton.append(("tetrahedra", label, run(
            Case("tet-newton", "lv_tet_inflation.prm", label, {**changes, **PER_NEWTON}),
            build, workdir)))
    for a, b, r in ((16, 5, 1), (32, 10, 1)):
        label = f"{a}x{b}, {r} refinement(s), Q2-Q1"
        changes = {"Global refinements": str(r),
                   "Geometry/Ellipsoid/Cells around circumference": str(a),
                   "Geometry/Ellipsoid/Cells from apex to base": str(b), **HEX_TAYLOR_HOOD}
        print(f"running Land problem 2 on the hexahedral ventricle {label} ...", flush=True)
        accuracy.append(("hexahedra", label, "z",
                         run(Case("tet", "land_problem2.prm", label, changes), build, workdir)))
        per_newton.append(("hexahedra", label, run(
            Case("tet-newton", "land_problem2.prm", label, {**changes, **PER_NEWTON}),
            build, workdir)))
    return accuracy, per_newton


def tet_section(build: Path, workdir: Path, full: bool) -> str:
    """Both tables of the group, and Land problem 3 on tetrahedra."""
    accuracy, per_newton = tet_runs(build, workdir, full)
    lines = [f"## {TITLE}", "",
             "Generated by `scripts/bench --only tet` (`--full` adds a 1 mm tetrahedral mesh). "
             "Land problem 2, incompressible Taylor-Hood (P2-P1 on tetrahedra, Q2-Q1 on "
             "hexahedra), 10 equal load steps each converged to 1e-6 of its largest residual (as "
             "`parameters/lv_tet_inflation.prm`), the `auto` linear solver. Tetrahedra: the "
             "cardiac-geometries ventricle (flat facets, long axis x); hexahedra: the generated "
             "ventricle (curved Q2 geometry, long axis z). Band: endo -26.9 ... -26.4, epi "
             "-28.5 ... -28.1 mm. Per Newton iteration per DOF: (assembly + linear solver) / "
             "(Newton + chord iterations) / DOFs.", "",
             "| cells | mesh | DOFs | endo / epi apex [mm] | Newton (chord) iterations "
             "| Krylov iterations per solve | wall [s] | per iteration per DOF [µs] "
             "| 2 x peak memory per rank per DOF [KiB] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for cells, label, axis, row in accuracy:
        if not row["ok"]:
            lines.append(f"| {cells} | {label} | - | failed: {row['error']} | | | | | |")
            continue
        lines.append(f"| {cells} | {label} | {row['dofs']} | {apexes(row, axis)} | {cost(row)}")
    lines += ["", "The same meshes on the scaling group's problem (2 kPa in two load steps, pure "
              "Newton, the iterative solver: FGMRES with the p-multigrid P2/Q2 -> P1/Q1 Schur "
              "block preconditioner):", "",
              "| cells | mesh | DOFs | Newton (chord) iterations | Krylov iterations per solve "
              "| wall [s] | per iteration per DOF [µs] "
              "| 2 x peak memory per rank per DOF [KiB] |",
              "|---|---|---|---|---|---|---|---|"]
    for cells, label, row in per_newton:
        if not row["ok"]:
            lines.append(f"| {cells} | {label} | failed: {row['error']} | | | | | |")
            continue
        lines.append(f"| {cells} | {label} | {row['dofs']} | {cost(row)}")
    lines += p3_lines(build, workdir)
    if any(r.get("busy") for *_, r in accuracy + per_newton):
        lines += ["", "\\* The machine was busy during the run: the time is inflated."]
    return "\n".join(lines) + "\n"


#: Land problem 3 on the generated ventricle split into tetrahedra (Cell shape = tetrahedra):
#: 16 x 5 coarse hexahedra refined once, 24 tetrahedra each, Taylor-Hood, no local refinement.
P3_TET = {"Geometry/Cell shape": "tetrahedra", "Geometry/Ellipsoid/Cells around circumference": "16",
          "Geometry/Ellipsoid/Cells from apex to base": "5", "Local refinements": "0",
          "Discretization/Pressure element": "continuous"}
#: The hexahedral reference of problem 3 (bench group large: 32 x 10 refined twice, 511k DOFs).
P3_HEX = (-12.317, -15.487)


def p3_lines(build: Path, workdir: Path) -> list[str]:
    """Land problem 3 on the generated ventricle split into tetrahedra."""
    print("running Land problem 3 on the generated ventricle split into tetrahedra ...",
          flush=True)
    row = run(Case("tet-p3", "land_problem3.prm", "16x5, 1 refinement, tetrahedra", P3_TET),
              build, workdir)
    lines = ["", "Land problem 3 (`parameters/land_problem3.prm` with `Cell shape = tetrahedra`: "
             "16 x 5 coarse hexahedra refined once, each split into 24 tetrahedra, Taylor-Hood, "
             "no local refinement at the apex) against the hexahedral 511k-DOF values of the "
             f"group large ({P3_HEX[0]} / {P3_HEX[1]} mm):", "",
             "| mesh | DOFs | endo / epi apex z [mm] | difference to the hexahedral [mm] "
             "| Newton (chord) iterations | Krylov iterations per solve | wall [s] "
             "| per iteration per DOF [µs] | 2 x peak memory per rank per DOF [KiB] |",
             "|---|---|---|---|---|---|---|---|---|"]
    if not row["ok"]:
        return lines + [f"| 16x5, 1, tetrahedra | failed: {row['error']} | | | | | | | |"]
    endo, epi = row["values"]["endo_apex_z"], row["values"]["epi_apex_z"]
    lines.append(f"| 16x5, 1, tetrahedra | {row['dofs']} | {endo:.3f} / {epi:.3f} "
                 f"| {endo - P3_HEX[0]:+.3f} / {epi - P3_HEX[1]:+.3f} | {cost(row)}")
    return lines


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    text = tet_section(args.build, workdir, args.full)
    print(text, flush=True)
    return {TITLE: text}
