"""An independent implementation of the 0D closed loop of reference/physiology.md.

The closed-loop circulation of Regazzoni et al. 2022 (J. Comput. Phys. 457:111083) with the
parameters and initial state of reference/physiology.md ("Closed-loop circulation"), written
from that file in its units (mL, mmHg, s), not from the C++ code, and integrated with SciPy's
Radau. scripts/tests/test_closed_loop_reference.py and scripts/bench (group circulation)
compare the app's Problem = circulation against it.
"""

import numpy as np
from scipy.integrate import solve_ivp

PERIOD = 0.8  # s

# Chambers: E_A, E_B [mmHg/mL], t_C, T_C, T_R [s], V_0 [mL]. The atria start 0.2 s before
# the ventricles of the next beat: at 0.7 s of a 0.8 s beat.
CHAMBERS = {
    "la": (0.07, 0.18, 0.7, 0.17, 0.17, 4.0),
    "lv": (4.482, 0.170, 0.1, 0.25, 0.4, 42.0),
    "ra": (0.06, 0.07, 0.7, 0.17, 0.17, 4.0),
    "rv": (0.200, 0.029, 0.1, 0.25, 0.4, 16.0),
}
R_MIN, R_MAX = 0.0075, 75006.2  # mmHg s/mL
# R [mmHg s/mL], C [mL/mmHg], L [mmHg s^2/mL]
SYSTEMIC_ARTERIES = (0.733, 1.372, 0.005)
SYSTEMIC_VEINS = (0.32, 11.363, 0.0005)
PULMONARY_ARTERIES = (0.046, 20.0, 0.0005)
PULMONARY_VEINS = (0.0015, 16.0, 0.0005)

# (column of the results file, initial value in mL, mmHg or mL/s)
STATES = [
    ("la_volume_mL", 87.183),
    ("lv_volume_mL", 118.520),
    ("ra_volume_mL", 86.833),
    ("rv_volume_mL", 166.177),
    ("systemic_arterial_pressure_mmHg", 87.675),
    ("systemic_venous_pressure_mmHg", 35.898),
    ("pulmonary_arterial_pressure_mmHg", 19.545),
    ("pulmonary_venous_pressure_mmHg", 15.004),
    ("systemic_arterial_flow_mL_per_s", 71.104),
    ("systemic_venous_flow_mL_per_s", 94.039),
    ("pulmonary_arterial_flow_mL_per_s", 94.084),
    ("pulmonary_venous_flow_mL_per_s", 473.279),
]


def activation(t, t_c, t_contraction, t_relaxation):
    """The raised-cosine activation e(t) in [0, 1], t - t_C taken modulo the period."""
    tau = (t - t_c) % PERIOD
    if tau < t_contraction:
        return 0.5 * (1.0 - np.cos(np.pi * tau / t_contraction))
    if tau < t_contraction + t_relaxation:
        return 0.5 * (1.0 + np.cos(np.pi * (tau - t_contraction) / t_relaxation))
    return 0.0


def chamber_pressure(name, t, volume):
    """p = (E_B + E_A e(t)) (V - V_0) [mmHg]."""
    e_a, e_b, t_c, t_contraction, t_relaxation, v_0 = CHAMBERS[name]
    return (e_b + e_a * activation(t, t_c, t_contraction, t_relaxation)) * (volume - v_0)


def valve_flow(p_up, p_down):
    """Non-ideal diode: R_min while p_up > p_down, R_max otherwise [mL/s]."""
    return (p_up - p_down) / (R_MIN if p_up > p_down else R_MAX)


def rhs(t, y):
    """dy/dt of the closed loop, y as in STATES (mL, mmHg, mL/s; t in s)."""
    v_la, v_lv, v_ra, v_rv, p_as, p_vs, p_ap, p_vp, q_as, q_vs, q_ap, q_vp = y
    p_la = chamber_pressure("la", t, v_la)
    p_lv = chamber_pressure("lv", t, v_lv)
    p_ra = chamber_pressure("ra", t, v_ra)
    p_rv = chamber_pressure("rv", t, v_rv)
    q_mv, q_av = valve_flow(p_la, p_lv), valve_flow(p_lv, p_as)
    q_tv, q_pv = valve_flow(p_ra, p_rv), valve_flow(p_rv, p_ap)
    (r_as, c_as, l_as), (r_vs, c_vs, l_vs) = SYSTEMIC_ARTERIES, SYSTEMIC_VEINS
    (r_ap, c_ap, l_ap), (r_vp, c_vp, l_vp) = PULMONARY_ARTERIES, PULMONARY_VEINS
    return [
        q_vp - q_mv,
        q_mv - q_av,
        q_vs - q_tv,
        q_tv - q_pv,
        (q_av - q_as) / c_as,
        (q_as - q_vs) / c_vs,
        (q_pv - q_ap) / c_ap,
        (q_ap - q_vp) / c_vp,
        (-r_as * q_as - (p_vs - p_as)) / l_as,
        (-r_vs * q_vs - (p_ra - p_vs)) / l_vs,
        (-r_ap * q_ap - (p_vp - p_ap)) / l_ap,
        (-r_vp * q_vp - (p_la - p_vp)) / l_vp,
    ]


def blood_volume(y):
    """Chamber volumes plus C p of the four compliances [mL]."""
    compliances = [c for _, c, _ in (SYSTEMIC_ARTERIES, SYSTEMIC_VEINS, PULMONARY_ARTERIES,
                                     PULMONARY_VEINS)]
    return np.sum(y[:4], axis=0) + np.tensordot(compliances, y[4:8], axes=1)


def reference_solution(times_s):
    """The reference at the given times [s]: array (12, n)."""
    y0 = [value for _, value in STATES]
    atol = [1e-9] * 12  # mL, mmHg, mL/s
    solution = solve_ivp(rhs, (0.0, times_s[-1]), y0, method="Radau", t_eval=times_s,
                         rtol=1e-10, atol=atol)
    if not solution.success:
        raise RuntimeError(f"solve_ivp failed: {solution.message}")
    return solution.y
