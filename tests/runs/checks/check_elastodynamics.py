#!/usr/bin/env python3
"""Checks of Problem = elastodynamics runs against independent values.

    check_elastodynamics.py loads RESULTS.h5 SIGMA_MID SIGMA_PRE SIGMA_0
    check_elastodynamics.py lv RESULTS.h5

loads: the pressure and active_tension columns against the ODEs of Arostica et al. 2025
(benchmarks.md) integrated by SciPy's solve_ivp (Radau, rtol 1e-11), with the benchmark's
switch times and rates and the given amplitudes (SIGMA_MID [kPa], SIGMA_PRE [kPa/s],
SIGMA_0 [kPa]); within 1e-7 of the peak.

lv: the point 'apex' on the long axis stays on it (|x|, |y| below 1e-6 of its axial
motion: the mesh, fibres, loads and supports are symmetric under quarter turns about the
axis), the cavity grows under the pressure pulse, the energy balance kinetic + strain +
support + dissipated = work of the loads closes to 2 % of the work, and the viscosity and
dashpots dissipate.
"""

import sys

import numpy as np
from scipy.integrate import solve_ivp

from systole_post.results import read_results

A_MAX, A_MIN, T_DIAS, GAMMA = 5.0, -30.0, 0.484, 0.005  # 1/s, 1/s, s, s
ALPHA_PRE, ALPHA_MID = 5.0, 1.0  # 1/s


def activation(t, t_sys):
    f = 0.25 * (1 + np.tanh((t - t_sys) / GAMMA)) * (1 - np.tanh((t - T_DIAS) / GAMMA))
    return A_MAX * f + A_MIN * (1 - f)


def reference_loads(times_ms, sigma_mid, sigma_pre, sigma_0):
    """p(t) [kPa] and tau(t) [kPa] at times_ms, in the benchmark's seconds."""

    def rhs(t, y):
        p, tau = y
        g_pre = 0.5 * (1 - np.tanh((t - T_DIAS) / GAMMA))
        b = activation(t, 0.17) + ALPHA_PRE * g_pre + ALPHA_MID
        a = activation(t, 0.16)
        return [
            -abs(b) * p + sigma_mid * max(b, 0) + sigma_pre * max(g_pre, 0),
            -abs(a) * tau + sigma_0 * max(a, 0),
        ]

    t = np.asarray(times_ms) * 1e-3
    solution = solve_ivp(
        rhs, (0, t[-1]), [0.0, 0.0], method="Radau", t_eval=t, rtol=1e-11, atol=1e-13,
        max_step=5e-4,
    )
    assert solution.success, solution.message
    return solution.y[0], solution.y[1]


def check_loads(path, sigma_mid, sigma_pre, sigma_0):
    ts = read_results(path).timeseries
    time = ts["time"]
    assert time[-1] >= 999.999, f"the run ended at {time[-1]} ms"
    p_ref, tau_ref = reference_loads(time, sigma_mid, sigma_pre, sigma_0)
    failures = []
    for name, ref in (("pressure", p_ref), ("active_tension", tau_ref)):
        error = np.max(np.abs(ts[name] - ref))
        print(f"{name}: peak {ref.max():.6g} kPa at {time[np.argmax(ref)]:.0f} ms, "
              f"largest difference to solve_ivp {error:.3g} kPa")
        if not error <= 1e-7 * ref.max():
            failures.append(f"{name} differs from solve_ivp by {error:.3g} kPa")
    return failures


def check_lv(path):
    ts = read_results(path).timeseries
    failures = []
    x, y, z = ts["apex_x"], ts["apex_y"], ts["apex_z"]
    axial = np.max(np.abs(z - z[0]))
    lateral = max(np.max(np.abs(x - x[0])), np.max(np.abs(y - y[0])))
    print(f"apex point: axial motion {axial:.4g} mm, off the axis {lateral:.3g} mm")
    if not axial > 1e-3:
        failures.append(f"the apex point hardly moves ({axial} mm)")
    if not lateral <= 1e-6 * axial + 1e-12:
        failures.append(f"the apex point leaves the axis by {lateral} mm")
    volume = ts["volume"]
    print(f"cavity volume {volume[0]:.2f} -> max {volume.max():.2f} mm^3")
    if not volume.max() > volume[0] * 1.001:
        failures.append("the cavity does not grow under the pressure pulse")
    stored = ts["kinetic_energy"] + ts["strain_energy"] + ts["support_energy"]
    defect = stored + ts["dissipated_energy"] - ts["load_work"]
    work = np.max(np.abs(ts["load_work"]))
    relative = np.max(np.abs(defect)) / work
    dissipated = ts["dissipated_energy"][-1] / ts["load_work"][-1]
    print(f"energy balance: largest defect {relative:.3g} of the work "
          f"({work:.4g} uJ); dissipated {dissipated:.3g} of it")
    if not relative < 0.02:
        failures.append(f"the energy balance is off by {relative:.3g} of the work")
    if not dissipated > 1e-3:
        failures.append("nothing is dissipated")
    return failures


def main(argv):
    mode, path = argv[1], argv[2]
    if mode == "loads":
        failures = check_loads(path, *map(float, argv[3:6]))
    else:
        failures = check_lv(path)
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
