"""The group 'ep-lv': electrophysiology on the default heartbeat's ventricle."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from .core import BUSY_NOTE, ROOT
from .ep import EP_COST_HEAD, ep_cable, ep_cost_cells, run_ep


#: Conductivities [mS/mm] (along, across) giving 0.6 / 0.25 m/s with Mitchell-Schaeffer on
#: converged cables, and those of parameters/lv_heartbeat.prm (calibrated on its EP mesh).
EP_LV_CONVERGED = ("0.432", "0.0758")


def ep_lv_cable(direction: str, h: float, sigma: tuple[str, str], build: Path,
                workdir: Path) -> float:
    """Mitchell-Schaeffer conduction velocity [m/s] on a cable (ep_cable) with conductivities
    `sigma`, fixed steps of 0.1 ms."""
    changes = ep_cable("Mitchell-Schaeffer", direction, h)
    changes.update({"Electrophysiology/Longitudinal conductivity": sigma[0],
                    "Electrophysiology/Transverse conductivity": sigma[1],
                    "Electrophysiology/Time step": "0.1"})
    r = run_ep(f"{direction} {h} {sigma[0]} {sigma[1]}", changes, 1, build, workdir, tag="lv")
    if not r["ok"]:
        return float("nan")
    s = r["summary"]
    return 8 / (s["far_activation_time"] - s["near_activation_time"])


def ep_lv_cable_lines(calibrated: tuple[str, str], build: Path, workdir: Path) -> list[str]:
    """The Mitchell-Schaeffer cables of both conductivities (table lines)."""
    cable_lines = ["| conductivities along / across [mS/mm] | h [mm] | CV along [m/s] "
                   "| CV across [m/s] |", "|---|---|---|---|"]
    for sigma in (EP_LV_CONVERGED, calibrated):
        for h in (0.0625, 1.25):
            print(f"running the cables, sigma {sigma}, h = {h} mm ...", flush=True)
            along = ep_lv_cable("along", h, sigma, build, workdir)
            across = ep_lv_cable("across", h, sigma, build, workdir)
            cable_lines.append(f"| {sigma[0]} / {sigma[1]} | {h} | {along:.4f} | {across:.4f} |")
    return cable_lines


def ep_lv_runs(calibrated: tuple[str, str], quick: bool, build: Path, workdir: Path) -> list[dict]:
    """The ventricle refined 1 ... 3 (4) times with the converged-cable conductivities and 3
    times with the calibrated ones: their rows."""
    runs = [(r, EP_LV_CONVERGED) for r in ((1, 2, 3) if quick else (1, 2, 3, 4))]
    runs.append((3, calibrated))
    rows = []
    for r, sigma in runs:
        print(f"running the ventricle's activation, mechanics mesh refined {r} times, sigma "
              f"{sigma} ...", flush=True)
        row = run_ep(f"{r}", {"Problem": "electrophysiology",
                              "Geometry/Global refinements": str(r),
                              "Time/End time": "150", "Time/Time step": "1",
                              "Electrophysiology/Longitudinal conductivity": sigma[0],
                              "Electrophysiology/Transverse conductivity": sigma[1],
                              "Electrophysiology/Adaptive time step": "false",
                              "Electrophysiology/Time step": "0.1"},
                     2, build, workdir, tag=f"lv {sigma[0]}", base="lv_heartbeat.prm")
        row["sigma"] = sigma
        rows.append(row)
    return rows


def ep_lv_table(rows: list[dict]) -> list[str]:
    """The ventricle's table lines."""
    lines = ["| refinements of the mechanics mesh | conductivities [mS/mm] | cells | nodes "
             "| across the wall [mm] | activated | 90 % active [ms] | total activation time "
             "[ms] | change of the 90 % time from the previous level | " + EP_COST_HEAD,
             "|" + "---|" * 14]
    previous = None
    for r in rows:
        sigma = f"{r['sigma'][0]} / {r['sigma'][1]}"
        if not r["ok"]:
            lines.append(f"| {r['label']} | {sigma} | failed: {r['error']} |")
            continue
        s = r["summary"]
        change = ""
        same = previous is not None and previous["sigma"] == r["sigma"]
        if same and np.isfinite(previous["summary"]["activation_time_90"]):
            old = previous["summary"]["activation_time_90"]
            change = f"{100 * (s['activation_time_90'] - old) / old:+.1f} %"
        lines.append(f"| {r['label']} | {sigma} | {r['cells']} | {r['dofs']} "
                     f"| {10 / 2 ** int(r['label']):.2f} | {100 * s['activated_fraction']:.1f} % "
                     f"| {s['activation_time_90']:.2f} | {s['total_activation_time']:.2f} "
                     f"| {change} | " + ep_cost_cells(r))
        previous = r
    if any(r.get("busy") for r in rows):
        lines.append(BUSY_NOTE)
    return lines


def ep_lv_section(build: Path, workdir: Path, quick: bool) -> str:
    """The activation of the default heartbeat's ventricle (its EP parameters, the
    electrophysiology problem alone) on its mechanics mesh refined 1 ... 3 (4) times with the
    converged-cable conductivities, and with the heartbeat's calibrated ones; the cables."""
    text = (ROOT / "parameters" / "lv_heartbeat.prm").read_text()
    calibrated = tuple(re.search(rf"set {name} conductivity\s*=\s*(\S+)", text).group(1)
                       for name in ("Longitudinal", "Transverse"))
    cable_lines = ep_lv_cable_lines(calibrated, build, workdir)
    lines = ep_lv_table(ep_lv_runs(calibrated, quick, build, workdir))
    return ("## Electrophysiology: the default heartbeat's ventricle\n"
            "The electrophysiology of `parameters/lv_heartbeat.prm` alone (Mitchell-Schaeffer, "
            "endocardial stimulus, rule-based fibres, Q1) on its mechanics mesh (64 cells, one "
            "across the 10 mm wall) refined 1 to 4 times, fixed steps of 0.1 ms, 150 ms, 2 "
            f"ranks: with the conductivities {EP_LV_CONVERGED[0]} / {EP_LV_CONVERGED[1]} "
            "mS/mm (0.6 / 0.25 m/s, the human speeds of physiology.md, on converged cables), "
            f"and with the heartbeat's {calibrated[0]} / {calibrated[1]} mS/mm, calibrated "
            "for its EP mesh (3 refinements, 1.25 mm across the wall) on cables of that cell "
            "size (sigma <- sigma (CV_target / CV)^2, two iterations). The heartbeat runs EP "
            "with adaptive steps (at most 2 ms).\n\nMitchell-Schaeffer cables (20 mm, "
            "velocities between 8 and 16 mm; 1 rank):\n\n" + "\n".join(cable_lines) +
            "\n\nThe ventricle:\n\n" + "\n".join(lines) + "\n")


def sections(args, workdir: Path) -> dict[str, str]:
    """The group's section {title: text}."""
    title = "Electrophysiology: the default heartbeat's ventricle"
    text = ep_lv_section(args.build, workdir, args.quick)
    print(text, flush=True)
    return {title: text}
