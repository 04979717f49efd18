"""The group 'inverse': the cost of unloading and calibration (2 ranks)."""

from __future__ import annotations

from pathlib import Path

from systole_post.results import read_results

from .core import BUSY_NOTE, ROOT, run_watched


def run_inverse(base: str, name: str, build: Path, workdir: Path, ranks: int = 2) -> dict:
    """One Problem = unloading or calibration run of parameters/<base> on `ranks` ranks:
    /statistics (counts and the mechanics' timer sections), /summary, the calibration
    tables."""
    text = (ROOT / "parameters" / base).read_text()
    prm = workdir / f"{name}.prm"
    prm.write_text(text + f"\nsubsection Output\n  set Run name = {name}\n"
                   "  set Field output interval = 0\nend\n")
    command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
               str(build / "systole"), str(prm)]
    out, busy = run_watched(command, workdir, ranks)
    if out.returncode != 0:
        lines = out.stderr.strip().splitlines() or ["?"]
        return {"ok": False, "base": base,
                "error": next((line for line in lines if "error" in line), lines[0])}
    path = workdir / "results" / name / "results.h5"
    results = read_results(path)
    row = {"ok": True, "busy": busy, "base": base, "stats": results.statistics,
           "summary": {k: float(v[-1]) for k, v in results.summary.items()}}
    import h5py
    with h5py.File(path, "r") as f:
        for group in ("calibration/edpvr", "calibration/parameters", "calibration/fit"):
            if group in f:
                row[group] = {k: f[group][k][()] for k in f[group]}
    return row


def timer_seconds(stats: dict, *words: str) -> float:
    """Sum of the /statistics timer sections whose name holds every word."""
    return sum(v for k, v in stats.items()
               if k.startswith("timer: ") and all(w in k for w in words))


def cost_row(label: str, r: dict) -> str:
    """One case's row of the cost table."""
    if not r["ok"]:
        return f"| {label} | failed: {r['error']} |"
    st = r["stats"]
    if "tao_iterations" in st:
        newton = (f"{st['newton_iterations']:.0f} + {st['unloading_newton_iterations']:.0f} "
                  "(unloading)")
        cells = (f"{st['fixed_point_iterations']:.0f} | {st['unloading_inflations']:.0f} | "
                 f"{st['forward_solves']:.0f} | {st['tao_iterations']:.0f} | {newton}")
    else:
        cells = (f"{st['fixed_point_iterations']:.0f} | {st['forward_solves']:.0f} | – | – | "
                 f"{st['newton_iterations']:.0f}")
    star = " \\*" if r["busy"] else ""
    return (f"| {label} | {st['n_dofs']:.0f} | {cells} | "
            f"{timer_seconds(st, 'assembl'):.1f} | {timer_seconds(st, 'linear solver'):.1f} | "
            f"{st['wall_time']:.0f}{star} |")


def edpvr_lines(calibration: dict) -> list[str]:
    """The fitted EDPVR against Klotz's curve recomputed from the formulas."""
    e, fit = calibration["calibration/edpvr"], calibration["calibration/fit"]
    par, st = calibration["calibration/parameters"], calibration["stats"]
    edp, edv = float(fit["klotz_edp_mmHg"][0]), float(fit["klotz_edv_mL"][0])
    v0 = edv * (0.6 - 0.006 * edp)  # Klotz 2006: 0.006 per mmHg of EDP_m
    v30 = v0 + (edv - v0) / (edp / 27.78) ** (1 / 2.76)
    names = [n.decode() if isinstance(n, bytes) else str(n) for n in par["name"]]
    fitted = ", ".join(f"{n} = {v:.4g} ± {s:.2g}" + (" (at a bound)" if b else "")
                       for n, v, s, b in zip(names, par["fitted"],
                                             par["standard_deviation"], par["at_bound"]))
    reason = fit["reason"][0]
    reason = reason.decode() if isinstance(reason, bytes) else str(reason)
    lines = ["", f"Klotz's curve through ({edp:g} mmHg, {edv:.3f} mL, the image's cavity), "
             f"recomputed here: V0 = {v0:.3f} mL, V30 = {v30:.3f} mL. Fitted (± one "
             f"standard deviation): {fitted}; relative residual norm "
             f"{float(fit['residual_norm'][0]):.4f}; TAO's reason {reason} after "
             f"{float(fit['tao_iterations'][0]):.0f} iterations and "
             f"{float(fit['evaluations'][0]):.0f} evaluations; unloaded "
             f"cavity {st['unloaded_volume_mL']:.2f} mL (reload error "
             f"{st['reload_max_error_mm']:.2g} mm).\n",
             "| p [mmHg] | Klotz [mL] | fitted [mL] | error | initial values [mL] |",
             "|---|---|---|---|---|"]
    for p, v, v_init in zip(e["pressure_mmHg"], e["volume_mL"], e["initial_volume_mL"]):
        klotz = v0 + (v30 - v0) * (p / 27.78) ** (1 / 2.76)
        lines.append(f"| {p:g} | {klotz:.1f} | {v:.1f} | {100 * (v / klotz - 1):+.1f} % | "
                     f"{v_init:.1f} |")
    return lines


def inverse_section(build: Path, workdir: Path) -> str:
    """The cost of unloading (parameters/lv_unloading.prm) and of the Klotz calibration on
    the unloaded reference (parameters/lv_calibration.prm), 2 ranks, and the fitted EDPVR
    against Klotz's curve recomputed here from the formulas."""
    print("running parameters/lv_unloading.prm on 2 ranks ...", flush=True)
    unloading = run_inverse("lv_unloading.prm", "bench_unloading", build, workdir)
    print("running parameters/lv_calibration.prm on 2 ranks (takes a while) ...", flush=True)
    calibration = run_inverse("lv_calibration.prm", "bench_calibration", build, workdir)
    lines = ["## Cost of unloading and calibration (2 ranks)",
             "Written by `scripts/bench --only inverse`: the default ventricle (16 x 5 cells, "
             "Q2) on 2 ranks (`mpirun -np 2`). Counts from `/statistics`; the assembly and "
             "linear-solver times are the mechanics' TimerOutput sections summed over the "
             "meshes built on every trial reference (rank 0's wall times). A forward solve is "
             "one Newton solve (a load step or a finite-difference solve); an unloading "
             "inflation is one load-stepped inflation of a trial reference to the image "
             "pressure.\n",
             "| case | DOFs | fixed-point iterations | unloading inflations | forward solves "
             "(calibration) | TAO iterations | Newton iterations | assembly [s] | "
             "linear solves [s] | wall [s] |",
             "|" + "---|" * 10]
    lines += [cost_row(label, r)
              for label, r in (("unloading (`lv_unloading.prm`)", unloading),
                               ("Klotz calibration on the unloaded reference "
                                "(`lv_calibration.prm`)", calibration))]
    if any(r.get("busy") for r in (unloading, calibration)):
        lines.append(BUSY_NOTE)
    if calibration["ok"] and "calibration/edpvr" in calibration:
        lines += edpvr_lines(calibration)
    return "\n".join(lines) + "\n"


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "Cost of unloading and calibration (2 ranks)"
    text = inverse_section(args.build, workdir)
    print(text, flush=True)
    return {title: text}
