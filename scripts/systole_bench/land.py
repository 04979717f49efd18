"""The group 'land': excitation-contraction coupling, Frank-Starling and the ESPVR (ten
Tusscher-Panfilov calcium driving the Land et al. 2017 tension).

The sweeps are studies (systole_post.study, the code of `scripts/systole-study`) of the recipes
parameters/studies/land_preload_with, land_preload_without and land_afterload: their `_coarse`
variants by default (tests/runs/lv_heartbeat_ttp_land_coarse.prm), the full-size ones with
--full (parameters/lv_heartbeat_ttp_land.prm). The tables come from the studies' table.h5.

Resume: each study runs in results/studies/<recipe>/, the folder `scripts/systole-study run
<recipe>` uses. A stopped group (Ctrl-C, SIGTERM: the running cases are stopped) run again skips
every finished case, whether the group or `systole-study` ran it, and reruns only the
interrupted ones. A failed case stays failed (its row says why) until `systole-study run
<recipe> --retry-failed` reruns it; delete the folder to start a study afresh.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from systole_post.study import (Interrupted, check_entries, default_command, load_study,
                                read_table, run_study)

from .core import ROOT

#: The recipes of the sweeps (parameters/studies/land_<sweep>[_coarse].toml).
RECIPES = ROOT / "parameters" / "studies"
#: Where `scripts/systole-study run` puts a recipe's study (results/studies/<recipe>/).
STUDIES = ROOT / "results" / "studies"
#: The sweeps: the preload with and without Land's length dependence, the afterload.
SWEEPS = ("preload_with", "preload_without", "afterload")
#: The varied parameter (its table column) of each sweep.
SWEEP_PARAMETER = {"preload_with": "preload", "preload_without": "preload",
                   "afterload": "resistance"}
#: The afterload sweep's reference run (x1: the peripheral resistance of the base file).
REFERENCE_RESISTANCE = 1.0


def recipe(sweep: str, full: bool) -> Path:
    """The study file of a sweep."""
    return RECIPES / f"land_{sweep}{'' if full else '_coarse'}.toml"


def run_sweeps(build: Path, full: bool, jobs: int = 1, studies: Path = STUDIES,
               command: list[str] | None = None) -> dict[str, dict[float, dict]]:
    """Run (or resume) the three studies, `jobs` cases at a time (2 ranks each with one, 1 rank
    each with more); return each sweep's rows by parameter value (sweep_rows). `command`
    replaces systole (tests: a fake runner; see run_study)."""
    ranks = 2 if jobs == 1 else 1
    systole = str(Path(build).resolve() / "systole")  # the cases run in their own folders
    rows = {}
    for sweep in SWEEPS:
        study = load_study(recipe(sweep, full))
        folder = studies / study.path.stem
        case_command = command
        if case_command is None:
            check_entries(study, systole)
            case_command = default_command(ranks, systole)
        print(f"running the study {study.path.relative_to(ROOT)} in {folder} ...", flush=True)
        try:
            run_study(study, folder, parallel=jobs, ranks=ranks, command=case_command)
        except Interrupted:
            print(f"land: stopped; run `scripts/bench --only land{' --full' if full else ''}` "
                  "again to resume (the finished cases are kept)", file=sys.stderr, flush=True)
            raise SystemExit(130) from None
        rows[sweep] = sweep_rows(read_table(folder), SWEEP_PARAMETER[sweep])
    return rows


def sweep_rows(table, parameter: str) -> dict[float, dict]:
    """The rows of a study table (one per case: its last beat) by the value of `parameter`,
    each a dict column -> value."""
    return {float(table.columns[parameter][i]):
            {name: values[i] for name, values in table.columns.items()}
            for i in range(table.n_rows)}


def ok(r: dict) -> bool:
    """Whether a case finished."""
    return r["status"] == "done"


def failed(r: dict) -> str:
    """A case that did not finish: its status and error line."""
    return f"{r['status']}: {r['error']}" if r["error"] else r["status"]


def preload_cells(r: dict) -> str:
    """A run's cells of the preload table: p_0, EDP, EDV, SV, T_0."""
    if not ok(r):
        return f"{failed(r)} | | | | |"
    return (f"{r['start_lv_pressure_mmHg']:.2f} | {r['lv_EDP_mmHg']:.2f} | {r['lv_EDV_mL']:.1f} | "
            f"{r['lv_SV_mL']:.2f} | {r['start_mean_active_tension']:.3f}")


def land_how(jobs: int) -> str:
    """How the runs ran: ranks, runs at a time."""
    return "2 ranks" if jobs == 1 else f"1 rank each, {jobs} runs at a time"


def land_head(rows: dict[str, dict[float, dict]], full: bool, jobs: int) -> list[str]:
    """The title, the note and the preload table's head."""
    prm = "parameters/lv_heartbeat_ttp_land.prm" if full else \
        "tests/runs/lv_heartbeat_ttp_land_coarse.prm"
    first = next((r for sweep in rows.values() for r in sweep.values() if ok(r)), None)
    size = (f"{first['statistics_n_dofs']:.0f} mechanics DOFs, "
            f"{first['statistics_ep_nodes']:.0f} EP nodes, " if first else "")
    preloads = ", ".join(f"{v:g}" for v in rows["preload_with"])
    afterloads = ", ".join(f"x{v:g}" for v in rows["afterload"])
    recipes = ", ".join(recipe(sweep, full).name for sweep in SWEEPS)
    lines = [f"## Excitation-contraction coupling: Frank-Starling and the ESPVR "
             f"({'parameters/lv_heartbeat_ttp_land.prm' if full else 'the coarse ventricle'})",
             "The heartbeat with ten Tusscher-Panfilov 2006 (epicardial) calcium driving the Land "
             "et al. 2017 tension, coupled two-way with the mechanics "
             f"({prm}{'' if full else ' with T_ref = 200 kPa and the mitral valve resistance 0.0075 mmHg s/mL'}; {size}{land_how(jobs)}; "
             "2 beats each from the unloaded state, the second one reported; `scripts/bench "
             f"--only land{' --full' if full else ''}`"
             f"{'' if full else ' (--full: parameters/lv_heartbeat_ttp_land.prm)'}, "
             f"the studies parameters/studies/{{{recipes}}}). "
             f"Preload: the 3-element Windkessel's atrial (filling) pressure {preloads} mmHg, "
             "with the paper's length dependence and without it (beta0 = beta1 = 0: h(lambda) = "
             "1, Ca50 independent of the stretch); p_0: the LV pressure when the reported beat "
             "starts (its stimulus), i.e. where the filling got to (EDP, the pressure at the "
             "mitral valve's closure, equals the atrial pressure by the valve law); T_0: the "
             "mean active tension over the mechanics' quadrature points then (the diastolic "
             "residue). "
             f"Afterload: the peripheral resistance {afterloads} at 10 mmHg with the length "
             "dependence (x1: the same parameters as the preload run at 10 mmHg, run again); "
             "the end-systolic point is the LV pressure and volume at the aortic valve's "
             "closure.", "",
             "| atrial pressure [mmHg] | with length dependence: p_0 [mmHg] | EDP [mmHg] | EDV "
             "[mL] | SV [mL] | T_0 [kPa] | without: p_0 [mmHg] | EDP [mmHg] | EDV [mL] | SV [mL] "
             "| T_0 [kPa] |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    return lines


def starling_lines(with_rows: dict[float, dict], without_rows: dict[float, dict]) -> list[str]:
    """Stroke volume, EDV and ESV from the lowest to the highest preload, with and without the
    length dependence."""
    low, high = min(with_rows), max(with_rows)

    def change(sweep: dict[float, dict], key: str) -> float:
        values = [sweep[p][key] if ok(sweep[p]) else math.nan for p in (low, high)]
        return values[1] - values[0]

    with_sv = [r["lv_SV_mL"] if ok(r) else math.nan for _, r in sorted(with_rows.items())]
    monotone = all(b > a for a, b in zip(with_sv, with_sv[1:]))
    gain_with, gain_without = change(with_rows, "lv_SV_mL"), change(without_rows, "lv_SV_mL")
    edv_with, edv_without = change(with_rows, "lv_EDV_mL"), change(without_rows, "lv_EDV_mL")
    esv_with, esv_without = change(with_rows, "lv_ESV_mL"), change(without_rows, "lv_ESV_mL")
    return ["", f"Stroke volume from {low:g} to {high:g} mmHg: {gain_with:+.2f} mL with the "
            f"length dependence ({'monotonic' if monotone else 'NOT monotonic'}), "
            f"{gain_without:+.2f} mL without it "
            f"({'more' if gain_with > gain_without else 'NOT more'} with it). "
            f"EDV {edv_with:+.2f} mL with, {edv_without:+.2f} mL without; ESV "
            f"{esv_with:+.2f} mL with, {esv_without:+.2f} mL without; the Starling slope "
            f"dSV/dEDV {gain_with / edv_with:.3f} with, {gain_without / edv_without:.3f} "
            "without."]


def afterload_lines(afterload: dict[float, dict]) -> list[str]:
    """The afterload table and the ESPVR fitted through its end-systolic points (the LV
    pressure at the aortic valve's closure against the ESV)."""
    lines = ["", "| peripheral resistance | ESV [mL] | ESP [mmHg] | EDV [mL] | SV [mL] | peak "
             "[mmHg] |", "|---|---|---|---|---|---|"]
    points = []
    for factor, r in sorted(afterload.items()):
        if not ok(r):
            lines.append(f"| x{factor / REFERENCE_RESISTANCE:g} | {failed(r)} |")
            continue
        esp = r.get("valve1_closes_lv_pressure_mmHg", math.nan)
        if not math.isnan(esp):
            points.append((r["lv_ESV_mL"], esp))
        lines.append(f"| x{factor / REFERENCE_RESISTANCE:g} | {r['lv_ESV_mL']:.2f} | {esp:.2f} | "
                     f"{r['lv_EDV_mL']:.1f} | {r['lv_SV_mL']:.2f} | "
                     f"{r['lv_peak_pressure_mmHg']:.1f} |")
    if len(points) == len(afterload) >= 3:
        v, p = np.array(points).T
        slope, intercept = np.polyfit(v, p, 1)
        fit = slope * v + intercept
        r2 = 1 - np.sum((p - fit) ** 2) / np.sum((p - np.mean(p)) ** 2)
        lines += ["", f"ESPVR: P_es = {slope:.3f} (V_es - {-intercept / slope:.1f} mL) mmHg "
                  f"(elastance {slope:.3f} mmHg/mL), R^2 = {r2:.4f}."]
    return lines


def wall_lines(rows: dict[str, dict[float, dict]], jobs: int) -> list[str]:
    """The wall time per beat over the runs (Systole's own, /statistics), and Newton
    iterations per step."""
    done = [r for sweep in rows.values() for r in sweep.values() if ok(r)]
    if not done:
        return []
    per_beat = [r["statistics_wall_time"] / r["statistics_beats"] for r in done]
    newton = sum(r["statistics_newton_iterations"] for r in done)
    steps = sum(r["statistics_steps"] for r in done)
    return ["", f"Wall time per beat ({land_how(jobs)}): {min(per_beat):.1f} to "
            f"{max(per_beat):.1f} s ({newton / steps:.2f} Newton iterations per step); the "
            "machine is shared, so the times vary with its load."]


def land_text(rows: dict[str, dict[float, dict]], full: bool, jobs: int = 1) -> str:
    """The land section from the sweeps' rows (run_sweeps)."""
    with_rows, without_rows = rows["preload_with"], rows["preload_without"]
    assert sorted(with_rows) == sorted(without_rows), (
        "the preload recipes with and without the length dependence sweep different pressures")
    lines = land_head(rows, full, jobs)
    for edp in sorted(with_rows):
        lines.append(f"| {edp:g} | {preload_cells(with_rows[edp])} | "
                     f"{preload_cells(without_rows[edp])} |")
    lines += starling_lines(with_rows, without_rows) + afterload_lines(rows["afterload"])
    lines += wall_lines(rows, jobs)
    return "\n".join(lines) + "\n"


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text} (workdir is unused: the studies keep their folders
    in results/studies/ so that a rerun resumes them)."""
    title = ("Excitation-contraction coupling: Frank-Starling and the ESPVR "
             f"({'parameters/lv_heartbeat_ttp_land.prm' if args.full else 'the coarse ventricle'})")
    text = land_text(run_sweeps(args.build, args.full, args.jobs), args.full, args.jobs)
    print(text, flush=True)
    return {title: text}
