"""The group 'cell': the ten Tusscher-Panfilov cell (Problem = cell) against SciPy."""

from __future__ import annotations

import re
from pathlib import Path

from .circulation import run_circulation
from .core import ROOT


CELL_MEASURES = ("resting_potential_mV", "peak_potential_mV", "APD90_ms", "peak_calcium_uM")
CELL_BEATS = 3


def run_cell(name: str, cell_type: str, dt: float, build: Path, workdir: Path) -> dict:
    """One Problem = cell run of the ten Tusscher-Panfilov cell (1 rank, CELL_BEATS beats)."""
    text = (f"set Problem = cell\nsubsection Time\n  set End time = {1000 * CELL_BEATS}\n"
            "  set Time step = 5\nend\nsubsection Electrophysiology\n"
            f"  set Ionic model = ten Tusscher-Panfilov\n  set Time step = {dt}\n"
            f"  subsection ten Tusscher-Panfilov\n    set Cell type = {cell_type}\n  end\nend\n")
    return run_circulation(name, text, build, workdir)


def cell_section(build: Path, workdir: Path) -> str:
    """The ten Tusscher-Panfilov cell (Problem = cell) against SciPy on the model files."""
    from systole_post.ten_tusscher_reference import reference_beats

    title = "Single cell: ten Tusscher-Panfilov 2006 against SciPy"
    prm = (ROOT / "parameters" / "cell_ttp.prm").read_text()
    shipped_dt = float(re.search(r"subsection Electrophysiology.*?set Time step\s*=\s*([\d.]+)",
                                 prm, re.DOTALL).group(1))
    lines = [f"## {title}",
             "One cell paced at 1 Hz from the model file's initial state (Problem = cell, "
             "the stimulus of the .ode file: 52 pA/pF for 1 ms at 10 ms of every beat), "
             f"{CELL_BEATS} beats, integrated by `systole` (ARK-4(2)3 with an empty implicit "
             "part, the 12 gates by Rush-Larsen after every step, Strang's splitting with "
             "merged half steps) and by SciPy's BDF (rtol 1e-8, atol 1e-10) on the Python that "
             "gotranx generates from the same .ode files (`scripts/systole_post/cellmodels`, "
             "an independent code path; `systole_post/ten_tusscher_reference.py`), measured "
             "the same way: resting potential at the stimulus onset, peak potential, APD90 "
             "(time above V_rest + 0.1 (V_peak - V_rest)), peak cytosolic calcium. The .ode "
             "file lets the stimulus current enter dK_i/dt, systole does not (an external "
             "current): 6e-3 mM of K_i per beat, 1e-3 mV of resting potential. The pytest and "
             "ctest `run.cell_ten_tusscher_panfilov_reference` require 0.5 % in every "
             f"measure of every beat at the time step of `parameters/cell_ttp.prm` "
             f"({shipped_dt} ms).", ""]
    lines += ["| variant | beat | quantity | systole | SciPy | relative difference |",
              "|---|---|---|---|---|---|"]
    worst = {}
    for cell_type in ("endocardial", "mid-myocardial", "epicardial"):
        r = run_cell(f"cell_{cell_type}", cell_type, shipped_dt, build, workdir)
        if not r["ok"]:
            lines.append(f"| {cell_type} | failed: {r['error']} | | | | |")
            continue
        reference = reference_beats(cell_type, CELL_BEATS)
        for beat, expected in enumerate(reference):
            for name in CELL_MEASURES:
                got, want = r["summary"][name][beat], expected[name]
                error = abs(got - want) / abs(want)
                worst[cell_type] = max(worst.get(cell_type, 0.0), error)
                lines.append(f"| {cell_type} | {beat} | {name} | {got:.5f} | {want:.5f} | "
                             f"{error:.1e} |")
    lines += ["", "Largest relative difference: " + ", ".join(
        f"{k} {v:.1e}" for k, v in worst.items()) + ".", "",
        "The epicardial cell with other time steps (the largest relative difference over "
        "the four measures and the beats; the peak potential, sampled at the steps, sets it):",
        "", "| time step [ms] | largest relative difference | measure | ARKode steps | "
        "wall [s] |", "|---|---|---|---|---|"]
    reference = reference_beats("epicardial", CELL_BEATS)
    for dt in (0.005, 0.01, 0.02, 0.05, 0.1):
        r = run_cell(f"cell_dt_{dt}", "epicardial", dt, build, workdir)
        if not r["ok"]:
            lines.append(f"| {dt} | failed: {r['error']} | | | |")
            continue
        errors = [(abs(r["summary"][n][b] - e[n]) / abs(e[n]), n)
                  for b, e in enumerate(reference) for n in CELL_MEASURES]
        error, measure = max(errors)
        lines.append(f"| {dt} | {error:.1e} | {measure} | {r['steps']} | {r['wall']:.1f} |")
    return "\n".join(lines) + "\n"


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "Single cell: ten Tusscher-Panfilov 2006 against SciPy"
    print("running the single cells ...", flush=True)
    return {title: cell_section(args.build, workdir)}
