#!/usr/bin/env python3
"""Check a calibration's results file against the truth it was made from.

    check_calibration.py RESULTS.h5 [NAME=TRUE ...] [--recovered TOL] [--interval]
                         [--klotz TOL] [--max-sd REL] [--unloaded MESH.msh]
                         [--reference-error TOL] [--improves]

Always: /calibration/parameters, /calibration/edpvr and /calibration/fit are there and
finite, the fit converged, volume_mL / target_volume_mL - 1 is the stored relative residual,
and /statistics counts the forward solves. --recovered TOL: every fitted NAME within TOL
(relative) of TRUE, and the fitted volumes on the (noise-free) targets to TOL / 10.
--interval: every TRUE inside the reported 95 % interval. --max-sd REL: every
standard deviation below REL times TRUE (the interval says something). --klotz TOL: the target volumes are
Klotz et al. 2006's curve through the stored (EDP, EDV) pair, computed here from the formulas
(V0 = EDV (0.6 - 0.006 EDP), A_n = 27.78 mmHg, B_n = 2.76), and the fitted volumes lie within
TOL (relative) of it.
--unloaded MESH (Calibration / Reference = unloaded): the unloaded mesh's cavity volume,
computed here from MESH (hexahedra or tetrahedra, closed by the base plane), is the reported unloaded volume (to
1e-6) and below every fitted volume, and the reference reloads to the image's vertices within
0.1 mm. --improves (with --klotz): the fitted EDPVR is closer to Klotz's curve (norm of the
relative errors) than the EDPVR of the initial values. --reference-error TOL: the unloaded
reference lies within TOL [mm]
of the true one (a synthetic round trip).
"""

import sys


import h5py
import numpy as np

from systole_post.gmsh_mesh import cavity_volume, read_msh, triangle_cavity_volume


def main(argv) -> int:
    args = argv[1:]
    path = args.pop(0)
    recovered = interval = klotz = max_sd = unloaded = reference_error = improves = None
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
        elif a == "--improves":
            improves = True
        elif a == "--unloaded":
            unloaded = args.pop(0)
        elif a == "--reference-error":
            reference_error = float(args.pop(0))
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
        stats = {k: f["statistics"][k][()] for k in f["statistics"]
                 if f["statistics"][k].shape == ()}
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
        v0 = edv * (0.6 - 0.006 * edp)  # Klotz 2006: 0.006 per mmHg of EDP_m
        v30 = v0 + (edv - v0) / (edp / 27.78) ** (1 / 2.76)
        curve = v0 + (v30 - v0) * (edpvr["pressure_mmHg"] / 27.78) ** (1 / 2.76)
        if np.max(np.abs(curve / edpvr["target_volume_mL"] - 1)) > 1e-10:
            failures.append("the target volumes are not Klotz's curve")
        error = edpvr["volume_mL"] / curve - 1
        for p, e in zip(edpvr["pressure_mmHg"], error):
            print(f"  {p:6.2f} mmHg: fitted vs Klotz {100 * e:+.2f} %")
        initial = edpvr["initial_volume_mL"] / curve - 1
        print(f"  relative error norm: fitted {np.linalg.norm(error):.4f}, initial values "
              f"{np.linalg.norm(initial):.4f}")
        if improves and not np.linalg.norm(error) < np.linalg.norm(initial):
            failures.append("the fit is not closer to Klotz's curve than the initial values")
        if np.max(np.abs(error)) > klotz:
            failures.append(f"fitted EDPVR off Klotz's by {np.max(np.abs(error)):.3f} (> {klotz})")

    if unloaded is not None:
        m = read_msh(unloaded)
        if len(m.tetrahedra) > 0:
            # Closed by the plane of the base (through its centroid).
            lid = m.nodes[np.unique(m.faces(m.names["base"]))].mean(axis=0)
            volume = triangle_cavity_volume(m, "endocardium", lid) / 1000
        else:
            lid = m.nodes[m.quads[m.names["base"]]][..., 2].max()
            volume = cavity_volume(m, "endocardium", lid) / 1000
        print(f"unloaded mesh: cavity {volume:.6f} mL (reported "
              f"{stats['unloaded_volume_mL']:.6f} mL), image {stats['image_volume_mL']:.6f} mL, "
              f"reload error {stats['reload_max_error_mm']:.3g} mm, "
              f"{stats['fixed_point_iterations']:.0f} fixed-point iterations")
        if abs(volume / stats["unloaded_volume_mL"] - 1) > 1e-6:
            failures.append("the unloaded mesh's cavity is not the reported unloaded volume")
        if not volume < np.min(edpvr["volume_mL"]):
            failures.append("the unloaded cavity is not below the fitted volumes")
        if not stats["reload_max_error_mm"] <= 0.1:
            failures.append(f"the unloaded reference reloads to {stats['reload_max_error_mm']} "
                            f"mm of the image (> 0.1 mm)")
    if reference_error is not None:
        error = stats["reference_max_error_mm"]
        print(f"unloaded reference vs the true one: {error:.3g} mm")
        if not error <= reference_error:
            failures.append(f"the unloaded reference is {error} mm off the true one "
                            f"(> {reference_error})")

    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
