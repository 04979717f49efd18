"""The group 'circulation': the 0D closed loop (Problem = circulation) against its
independent SciPy reference, and the periodic state of the shipped file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from systole_post.results import read_results

from .core import ROOT, run_watched


#: Bounds of the periodic state of the closed loop (the heartbeat issue's bands for the LV in
#: the closed loop; physiology.md's typical right ventricle).
CIRCULATION_BOUNDS = {
    "lv_EDV_mL": (100, 160), "lv_EF": (45, 65), "lv_peak_pressure_mmHg": (90, 140),
    "systemic_arterial_pressure_min_mmHg": (60, 90), "la_pressure_mean_mmHg": (5, 15),
    "rv_EF": (45, 60), "rv_peak_pressure_mmHg": (20, 30),
}


def run_circulation(name: str, text: str, build: Path, workdir: Path) -> dict:
    """One Problem = circulation run (1 rank): its time series, summary, log and wall time."""
    prm = workdir / f"{name}.prm"
    prm.write_text(text + f"\nsubsection Output\n  set Run name = {name}\nend\n")
    out, busy = run_watched([str(build / "systole"), str(prm)], workdir, 1)
    if out.returncode != 0:
        return {"ok": False, "error": (out.stderr.strip().splitlines() or ["?"])[0]}
    results = read_results(workdir / "results" / name / "results.h5")
    wall = results.statistics["wall_time"]
    steps = int(results.statistics["arkode_steps"])
    return {"ok": True, "busy": busy, "timeseries": results.timeseries,
            "summary": results.summary, "wall": wall, "steps": steps}


def circulation_section(build: Path, workdir: Path) -> str:
    """The 0D closed loop: agreement with the independent reference over 5 beats, and the
    periodic state of parameters/circulation_closed_loop.prm."""
    title = "0D closed loop (Problem = circulation)"
    lines = [f"## {title}",
             "The closed loop of physiology.md (Regazzoni et al. 2022, elastance ventricles, "
             "the defaults of subsection Circulation) integrated by `systole` (ARKode, implicit "
             "DIRK of order 5, analytic Jacobian, valve events by root finding).", "",
             "Against the independent SciPy implementation of `scripts/systole_post/"
             "closed_loop_reference.py` (Radau, rtol 1e-10): 5 beats, app at relative "
             "tolerance 1e-10 and absolute volume tolerance 1e-9 mL, compared at its 4001 "
             "output times (every 1 ms, exact); the difference is the largest over the run "
             "divided by the state's largest magnitude (the pytest and ctest "
             "`run.circulation_closed_loop_reference` require < 1e-6).", ""]
    lines += reference_lines(build, workdir)
    return "\n".join(lines + periodic_lines(build, workdir)) + "\n"


def reference_lines(build: Path, workdir: Path) -> list[str]:
    """5 beats at tight tolerances against the independent SciPy reference."""
    from systole_post.closed_loop_reference import STATES, reference_solution

    lines = []
    text = ("set Problem = circulation\nsubsection Time\n  set Time step = 1\nend\n"
            "subsection Circulation\n  set Number of beats = 5\n  set Periodicity tolerance = 0\n"
            "  set Relative tolerance = 1e-10\n  set Absolute volume tolerance = 1e-9\nend\n")
    tight = run_circulation("closed_loop_reference", text, build, workdir)
    if not tight["ok"]:
        lines.append(f"failed: {tight['error']}")
    else:
        ts = tight["timeseries"]
        reference = reference_solution(ts["time"] / 1000.0)
        lines += ["| state | largest value | largest difference | relative |", "|---|---|---|---|"]
        for i, (name, _) in enumerate(STATES):
            scale = np.max(np.abs(reference[i]))
            diff = np.max(np.abs(ts[name] - reference[i]))
            lines.append(f"| {name} | {scale:.4g} | {diff:.2e} | {diff / scale:.2e} |")
        volume = ts["total_blood_volume_mL"]
        drift = np.max(np.abs(volume - volume[0])) / volume[0]
        lines += ["", f"Blood volume {volume[0]:.3f} mL, largest relative change over the 5 "
                  f"beats {drift:.1e} (required < 1e-8). {tight['steps']} ARKode steps, "
                  f"{tight['wall']:.1f} s wall time (mostly writing and flushing the 4001 "
                  "rows)."]
    return lines


def periodic_lines(build: Path, workdir: Path) -> list[str]:
    """The periodic state of parameters/circulation_closed_loop.prm against the bounds."""
    shipped = run_circulation("circulation_closed_loop",
                              (ROOT / "parameters" / "circulation_closed_loop.prm").read_text(),
                              build, workdir)
    lines = ["", "Periodic state of `parameters/circulation_closed_loop.prm` (until both EDVs "
             "change by less than 1e-4 between beats; relative tolerance 1e-8; EDV, EDP and "
             "ESV at the valve closures, extremes and means over the 1 ms rows and the valve "
             "events of the last beat):", ""]
    if not shipped["ok"]:
        lines.append(f"failed: {shipped['error']}")
        return lines
    summary = shipped["summary"]
    n = len(summary["beat"])
    lines += [f"{n} beats to periodicity (last EDV change {summary['periodicity'][-1]:.1e}), "
              f"{shipped['wall']:.1f} s.", "",
              "| quantity | last beat | bounds |", "|---|---|---|"]
    keys = ["lv_EDV_mL", "lv_ESV_mL", "lv_SV_mL", "lv_EF", "lv_EDP_mmHg",
            "lv_peak_pressure_mmHg", "systemic_arterial_pressure_max_mmHg",
            "systemic_arterial_pressure_min_mmHg", "systemic_arterial_pressure_mean_mmHg",
            "la_pressure_mean_mmHg", "rv_EDV_mL", "rv_ESV_mL", "rv_SV_mL", "rv_EF",
            "rv_peak_pressure_mmHg", "pulmonary_arterial_pressure_max_mmHg",
            "pulmonary_arterial_pressure_min_mmHg", "ra_pressure_mean_mmHg",
            "lv_stroke_work_mmHg_mL", "total_blood_volume_mL"]
    for k in keys:
        bound = ""
        if k in CIRCULATION_BOUNDS:
            low, high = CIRCULATION_BOUNDS[k]
            bound = f"{low} ... {high}: " + ("yes" if low <= summary[k][-1] <= high else "**no**")
        lines.append(f"| {k} | {summary[k][-1]:.4g} | {bound} |")
    lines += ["", "Aortic pressures are those of the systemic arterial compliance; the bounds "
              "are the LV bands of the heartbeat issue for its closed loop and physiology.md's "
              "typical right ventricle (reported, not asserted)."]
    return lines


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "0D closed loop (Problem = circulation)"
    print("running the 0D closed loop ...", flush=True)
    text = circulation_section(args.build, workdir)
    print(text, flush=True)
    return {title: text}
