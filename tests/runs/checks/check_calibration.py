#!/usr/bin/env python3
"""Check a calibration's results file against the truth it was made from.

    check_calibration.py RESULTS.h5 [NAME=TRUE ...] [--recovered TOL] [--interval]
                         [--klotz TOL] [--max-sd REL]

Always: /calibration/parameters, /calibration/edpvr and /calibration/fit are there and
finite, the fit converged, volume_mL / target_volume_mL - 1 is the stored relative residual,
and /statistics counts the forward solves. --recovered TOL: every fitted NAME within TOL
(relative) of TRUE, and the fitted volumes on the (noise-free) targets to TOL / 10.
--interval: every TRUE inside the reported 95 % interval. --max-sd REL: every
standard deviation below REL times TRUE (the interval says something). --klotz TOL: the target volumes are
Klotz et al. 2006's curve through the stored (EDP, EDV) pair, computed here from the formulas
(A_n = 27.78 mmHg, B_n = 2.76), and the fitted volumes lie within TOL (relative) of it.
"""

import sys

import h5py
import numpy as np


def main(argv) -> int:
    args = argv[1:]
    path = args.pop(0)
    recovered = interval = klotz = max_sd = None
    truth = {}
    while args:
        a = args.pop(0)
        if a == "--recovered":
            recovered = float(args.pop(0))
        elif a == "--interval":
            interval = True
        elif a == "--max-sd":
            max_sd = float(args.pop(0))
        elif a == "--klotz":
            klotz = float(args.pop(0))
        else:
            name, value = a.split("=")
            truth[name] = float(value)

    failures = []
    with h5py.File(path, "r") as f:
        par = f["calibration/parameters"]
        names = [n.decode() if isinstance(n, bytes) else str(n) for n in par["name"][()]]
        fitted = dict(zip(names, par["fitted"][()]))
        lower = dict(zip(names, par["lower_95"][()]))
        upper = dict(zip(names, par["upper_95"][()]))
        sd = dict(zip(names, par["standard_deviation"][()]))
        edpvr = {k: f["calibration/edpvr"][k][()] for k in f["calibration/edpvr"]}
        fit = {k: f["calibration/fit"][k][()] for k in f["calibration/fit"]}
        solves = f["statistics/forward_solves"][()]

    for name in names:
        print(f"{name}: fitted {fitted[name]:.6g} +- {sd[name]:.3g}, "
              f"95 % [{lower[name]:.6g}, {upper[name]:.6g}]"
              + (f", true {truth[name]:.6g}" if name in truth else ""))
    for key, values in edpvr.items():
        if not np.all(np.isfinite(values)):
            failures.append(f"edpvr/{key} is not finite")
    if not fit["converged"][0] == 1:
        failures.append(f"the fit did not converge ({fit['reason'][0]})")
    ratio = edpvr["volume_mL"] / edpvr["target_volume_mL"] - 1
    if np.max(np.abs(ratio - edpvr["relative_residual"])) > 1e-12:
        failures.append("volume_mL / target_volume_mL - 1 is not the stored residual")
    if not solves > 0:
        failures.append("no forward solves in /statistics")
    print(f"forward solves {solves:.0f}, TAO iterations {fit['tao_iterations'][0]:.0f}, "
          f"residual norm {fit['residual_norm'][0]:.3e}")

    for name, value in truth.items():
        if name not in fitted:
            failures.append(f"no fitted parameter {name}")
            continue
        if recovered is not None and abs(fitted[name] / value - 1) > recovered:
            failures.append(f"{name}: fitted {fitted[name]:.6g} is not within "
                            f"{recovered:g} of {value:.6g}")
        if interval and not lower[name] <= value <= upper[name]:
            failures.append(f"{name}: {value:.6g} is outside the 95 % interval "
                            f"[{lower[name]:.6g}, {upper[name]:.6g}]")
        if max_sd is not None and not sd[name] < max_sd * value:
            failures.append(f"{name}: standard deviation {sd[name]:.3g} is not below "
                            f"{max_sd:g} of {value:.6g}")
    if recovered is not None and np.max(np.abs(ratio)) > recovered / 10:
        failures.append(f"fitted volumes off the noise-free targets by {np.max(np.abs(ratio)):.2e}")

    if klotz is not None:
        edp, edv = fit["klotz_edp_mmHg"][0], fit["klotz_edv_mL"][0]
        v0 = edv * (0.6 - 0.006 * edv)
        v30 = v0 + (edv - v0) / (edp / 27.78) ** (1 / 2.76)
        curve = v0 + (v30 - v0) * (edpvr["pressure_mmHg"] / 27.78) ** (1 / 2.76)
        if np.max(np.abs(curve / edpvr["target_volume_mL"] - 1)) > 1e-10:
            failures.append("the target volumes are not Klotz's curve")
        error = edpvr["volume_mL"] / curve - 1
        for p, e in zip(edpvr["pressure_mmHg"], error):
            print(f"  {p:6.2f} mmHg: fitted vs Klotz {100 * e:+.2f} %")
        if np.max(np.abs(error)) > klotz:
            failures.append(f"fitted EDPVR off Klotz's by {np.max(np.abs(error)):.3f} (> {klotz})")

    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
