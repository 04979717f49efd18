"""The group 'land': excitation-contraction coupling, Frank-Starling and the ESPVR (ten
Tusscher-Panfilov calcium driving the Land et al. 2017 tension).
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np

from systole_post.results import read_results

from .core import ROOT, failed_row, run_watched, with_changes


#: The heartbeat with ten Tusscher-Panfilov calcium and Land tension: the coarse one of the
#: tests (801 DOFs, the whole wall stimulated) for the sweeps, the full one with --full.
LAND_COARSE = ROOT / "tests" / "runs" / "lv_heartbeat_ttp_land_coarse.prm"
LAND_FULL = ROOT / "parameters" / "lv_heartbeat_ttp_land.prm"
#: Land without length dependence: h(lambda) = 1 and Ca50 independent of the stretch.
NO_LENGTH_DEPENDENCE = {"Active tension/Land/beta0": "0", "Active tension/Land/beta1": "0"}
#: The preloads (atrial pressures [mmHg]) and afterloads (peripheral resistances [mmHg s/mL])
#: of the sweeps; the base files leave both at their defaults, 10 and 1.
LAND_PRELOADS = (6, 10, 14)
LAND_AFTERLOADS = (0.7, 1.0, 1.4)


def land_cases(full: bool) -> dict[str, dict[str, str]]:
    """The runs of the land group by name: the preload sweep with and without the length
    dependence, and the afterload sweep without its x1 run, which is the preload run at 10
    mmHg with the length dependence (the same parameters)."""
    prm = LAND_FULL if full else LAND_COARSE
    text = prm.read_text()
    assert "Atrial pressure" not in text and "Peripheral resistance" not in text, (
        f"{prm.name} sets the atrial pressure or the peripheral resistance: the afterload x1 "
        "run is no longer the preload run at 10 mmHg")
    # The coarse one with the full one's reference tension and mitral valve resistance.
    base = {} if full else {"Active tension/Land/Reference tension": "200",
                            "Circulation/Mitral valve resistance": "0.0075"}
    cases = {}
    for label, extra in (("with", {}), ("without", NO_LENGTH_DEPENDENCE)):
        for edp in LAND_PRELOADS:
            cases[f"land_preload_{label}_{edp}"] = {**base, **extra,
                                                     "Circulation/Atrial pressure": str(edp)}
    for factor in LAND_AFTERLOADS:
        if factor != 1.0:
            cases[f"land_afterload_{factor:g}"] = {
                **base, "Circulation/Atrial pressure": "10",
                "Circulation/Peripheral resistance": f"{factor:g}"}
    return cases


def land_afterload_name(factor: float) -> str:
    """The run of the afterload factor (x1: the preload run at 10 mmHg with the length
    dependence)."""
    return "land_preload_with_10" if factor == 1.0 else f"land_afterload_{factor:g}"


def run_land_heartbeat(name: str, prm: Path, changes: dict[str, str], beats: int, ranks: int,
                       build: Path, workdir: Path) -> dict:
    """One heartbeat of `prm` with `changes` for `beats` beats: land_row of its results."""
    changes = {**changes, "Circulation/Number of beats": str(beats),
               "Output/Run name": name, "Output/Field output interval": "0",
               "Output/Checkpoint interval": "0"}
    path = workdir / f"{name}.prm"
    path.write_text(with_changes(prm.read_text(), changes))
    command = [str(build / "systole"), str(path)]
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    out, busy = run_watched(command, workdir, ranks)
    return land_row(name, workdir, out, busy, ranks)


def land_row(name: str, workdir: Path, out: subprocess.CompletedProcess, busy: bool,
             ranks: int, beat: int = -1) -> dict:
    """The numbers of one land run from its results file: the summary of its beat `beat` (a
    row index of /summary; the last one by default), the
    pressures at the aortic valve's opening and closure (end-systolic), the LV pressure and
    the mean active tension when the beat starts, and the cost."""
    row = {"name": name, "ok": out.returncode == 0, "busy": busy, "ranks": ranks}
    h5 = workdir / "results" / name / "results.h5"
    if out.returncode != 0:
        return failed_row(row, out, h5)
    import h5py  # the valve events (/events) are not part of systole_post's Results

    results = read_results(h5)
    summary, stats, ts = results.summary, results.statistics, results.timeseries
    with h5py.File(h5, "r") as f:
        events = {k: f["events"][k][()] for k in f["events"]}
    row["summary"] = {k: float(v[beat]) for k, v in summary.items()}
    aortic = (events["beat"] == summary["beat"][beat]) & (events["valve"] == 1)
    closes, opens = aortic & (events["opens"] == 0), aortic & (events["opens"] == 1)
    row["esp"] = float(events["lv_pressure_mmHg"][closes][0]) if np.any(closes) else float("nan")
    row["opening_pressure"] = (float(events["lv_pressure_mmHg"][opens][0]) if np.any(opens)
                               else float("nan"))
    # The end of the previous filling, when the beat starts (its stimulus): the LV pressure
    # (below the atrial pressure, the filling was still going on; EDP, the pressure at the
    # mitral valve's closure, is the atrial pressure whatever the filling reached) and the
    # mean active tension over the quadrature points (the diastolic residue).
    start = summary["start_time"][beat]
    row["start_pressure"] = float(np.interp(start, ts["time"], ts["lv_pressure_mmHg"]))
    row["start_tension"] = float(np.interp(start, ts["time"], ts["mean_active_tension"]))
    row["wall"] = stats["wall_time"]
    row["dofs"] = int(stats["n_dofs"])
    row["beats"] = int(stats["beats"])
    row["periodic"] = bool(stats["periodic"])
    row["newton"] = int(stats["newton_iterations"])
    row["steps"] = int(stats["steps"])
    row["ep_nodes"] = int(stats.get("ep_nodes", 0))
    row["ep_seconds"] = stats.get("ep_seconds", float("nan"))
    return row


def land_section(build: Path, workdir: Path, full: bool, jobs: int = 1) -> str:
    """Frank-Starling (preload sweep with and without Land's length dependence) and the ESPVR
    (afterload sweep) of the heartbeat with ten Tusscher-Panfilov and Land, 2 beats each;
    `jobs` runs at a time (2 ranks each with one, 1 rank each with more)."""
    from concurrent.futures import ThreadPoolExecutor

    prm = LAND_FULL if full else LAND_COARSE
    ranks = 2 if jobs == 1 else 1

    def one(item: tuple[str, dict[str, str]]) -> tuple[str, dict]:
        name, changes = item
        print(f"running {name} on {ranks} rank(s) ...", flush=True)
        return name, run_land_heartbeat(name, prm, changes, 2, ranks, build, workdir)

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        rows = dict(pool.map(one, land_cases(full).items()))
    return land_text(rows, full, jobs)


def preload_cells(r: dict) -> str:
    """A run's cells of the preload table."""
    if not r["ok"]:
        return f"failed: {r['error']} | | | | |"
    s = r["summary"]
    return (f"{r['start_pressure']:.2f} | {s['lv_EDP_mmHg']:.2f} | {s['lv_EDV_mL']:.1f} | "
            f"{s['lv_SV_mL']:.2f} | {r['start_tension']:.3f}")


def land_how(rows: dict[str, dict], jobs: int) -> str:
    """How the runs ran: ranks, runs at a time."""
    ranks = next(iter(rows.values()))["ranks"]
    return f"{ranks} ranks" if jobs == 1 else f"{ranks} rank each, {jobs} runs at a time"


def land_head(rows: dict[str, dict], full: bool, jobs: int) -> list[str]:
    """The title, the note and the preload table's head."""
    prm = LAND_FULL if full else LAND_COARSE
    first = next((r for r in rows.values() if r["ok"]), None)
    size = (f"{first['dofs']} mechanics DOFs, {first['ep_nodes']} EP nodes, " if first else "")
    how = land_how(rows, jobs)
    lines = [f"## Excitation-contraction coupling: Frank-Starling and the ESPVR "
             f"({'parameters/lv_heartbeat_ttp_land.prm' if full else 'the coarse ventricle'})",
             "The heartbeat with ten Tusscher-Panfilov 2006 (epicardial) calcium driving the Land "
             "et al. 2017 tension, coupled two-way with the mechanics "
             f"({prm.relative_to(ROOT)}{'' if full else ' with T_ref = 200 kPa and the mitral valve resistance 0.0075 mmHg s/mL'}; {size}{how}; "
             "2 beats each from the unloaded state, the second one reported; `scripts/bench "
             f"--only land{' --full' if full else ''}`"
             f"{'' if full else ' (--full: parameters/lv_heartbeat_ttp_land.prm)'}). "
             "Preload: the 3-element Windkessel's atrial (filling) pressure 6, 10, 14 mmHg, with "
             "the paper's length dependence and without it (beta0 = beta1 = 0: h(lambda) = 1, "
             "Ca50 independent of the stretch); p_0: the LV pressure when the reported beat "
             "starts (its stimulus), i.e. where the filling got to (EDP, the pressure at the "
             "mitral valve's closure, equals the atrial pressure by the valve law); T_0: the "
             "mean active tension over the mechanics' quadrature points then (the diastolic "
             "residue). "
             "Afterload: the peripheral resistance x0.7, x1 (the run at 10 mmHg with the length "
             "dependence), x1.4; the end-systolic point is the LV pressure and volume at the "
             "aortic valve's closure.", "",
             "| atrial pressure [mmHg] | with length dependence: p_0 [mmHg] | EDP [mmHg] | EDV "
             "[mL] | SV [mL] | T_0 [kPa] | without: p_0 [mmHg] | EDP [mmHg] | EDV [mL] | SV [mL] "
             "| T_0 [kPa] |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    return lines


def starling_lines(preload: dict) -> list[str]:
    """Stroke volume, EDV and ESV from the lowest to the highest preload, with and without the
    length dependence."""
    def value(label: str, edp: int, key: str) -> float:
        r = preload[(label, edp)]
        return r["summary"][key] if r["ok"] else float("nan")

    def change(label: str, key: str) -> float:
        return value(label, LAND_PRELOADS[-1], key) - value(label, LAND_PRELOADS[0], key)

    with_sv = [value("with", e, "lv_SV_mL") for e in LAND_PRELOADS]
    monotone = all(b > a for a, b in zip(with_sv, with_sv[1:]))
    gain_with, gain_without = change("with", "lv_SV_mL"), change("without", "lv_SV_mL")
    edv_with, edv_without = change("with", "lv_EDV_mL"), change("without", "lv_EDV_mL")
    esv_with, esv_without = change("with", "lv_ESV_mL"), change("without", "lv_ESV_mL")
    return ["", f"Stroke volume from 6 to 14 mmHg: {gain_with:+.2f} mL with the length "
            f"dependence ({'monotonic' if monotone else 'NOT monotonic'}), "
            f"{gain_without:+.2f} mL without it "
            f"({'more' if gain_with > gain_without else 'NOT more'} with it). "
            f"EDV {edv_with:+.2f} mL with, {edv_without:+.2f} mL without; ESV "
            f"{esv_with:+.2f} mL with, {esv_without:+.2f} mL without; the Starling slope "
            f"dSV/dEDV {gain_with / edv_with:.3f} with, {gain_without / edv_without:.3f} "
            "without."]


def afterload_lines(afterload: dict) -> list[str]:
    """The afterload table and the ESPVR fitted through its end-systolic points."""
    lines = ["", "| peripheral resistance | ESV [mL] | ESP [mmHg] | EDV [mL] | SV [mL] | peak "
             "[mmHg] |", "|---|---|---|---|---|---|"]
    points = []
    for factor, r in afterload.items():
        if not r["ok"]:
            lines.append(f"| x{factor:g} | failed: {r['error']} |")
            continue
        s = r["summary"]
        points.append((s["lv_ESV_mL"], r["esp"]))
        lines.append(f"| x{factor:g} | {s['lv_ESV_mL']:.2f} | {r['esp']:.2f} | "
                     f"{s['lv_EDV_mL']:.1f} | {s['lv_SV_mL']:.2f} | "
                     f"{s['lv_peak_pressure_mmHg']:.1f} |")
    if len(points) == 3:
        v, p = np.array(points).T
        slope, intercept = np.polyfit(v, p, 1)
        fit = slope * v + intercept
        r2 = 1 - np.sum((p - fit) ** 2) / np.sum((p - np.mean(p)) ** 2)
        lines += ["", f"ESPVR: P_es = {slope:.3f} (V_es - {-intercept / slope:.1f} mL) mmHg "
                  f"(elastance {slope:.3f} mmHg/mL), R^2 = {r2:.4f}."]
    return lines


def wall_lines(rows: dict[str, dict], how: str) -> list[str]:
    """The wall time per beat over the runs."""
    lines = []
    walls = [r for r in rows.values() if r["ok"]]
    if walls:
        per_beat = [r["wall"] / r["beats"] for r in walls]
        busy = any(r["busy"] for r in walls)
        lines += ["", f"Wall time per beat ({how}): {min(per_beat):.1f} to "
                  f"{max(per_beat):.1f} s ({sum(r['newton'] for r in walls) / sum(r['steps'] for r in walls):.2f} "
                  "Newton iterations per step)"
                  f"{'; other work loaded the machine, so the times are inflated' if busy else ''}."]
    return lines


def land_text(rows: dict[str, dict], full: bool, jobs: int = 1) -> str:
    """The land section from the rows of land_section by run name."""
    preload = {(label, edp): rows[f"land_preload_{label}_{edp}"]
               for label in ("with", "without") for edp in LAND_PRELOADS}
    afterload = {factor: rows[land_afterload_name(factor)] for factor in LAND_AFTERLOADS}
    lines = land_head(rows, full, jobs)
    for edp in LAND_PRELOADS:
        lines.append(f"| {edp} | {preload_cells(preload[('with', edp)])} | "
                     f"{preload_cells(preload[('without', edp)])} |")
    lines += starling_lines(preload) + afterload_lines(afterload)
    lines += wall_lines(rows, land_how(rows, jobs))
    return "\n".join(lines) + "\n"


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = ("Excitation-contraction coupling: Frank-Starling and the ESPVR "
             f"({'parameters/lv_heartbeat_ttp_land.prm' if args.full else 'the coarse ventricle'})")
    text = land_section(args.build, workdir, args.full, args.jobs)
    print(text, flush=True)
    return {title: text}
