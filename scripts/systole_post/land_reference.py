"""Land et al. 2017 (J. Mol. Cell. Cardiol. 106:68) active tension in NumPy/SciPy.

An independent code path for the C++ model (src/materials/land.cc): the same ODEs written from
the paper's equations, integrated with SciPy's ``solve_ivp`` (Radau, tight tolerances) instead
of the C++ backward Euler steps. Units: ms, µM, kPa.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

#: Land et al. 2017, Table 1 (shared/reference/physiology.md).
PARAMETERS = {
    "Tref": 120.0, "TRPN50": 0.35, "nTRPN": 2.0, "kTRPN": 0.1, "nTM": 2.4, "ku": 0.04,
    "kuw": 0.182, "kws": 0.012, "rw": 0.5, "rs": 0.25, "gammas": 0.0085, "gammaw": 0.615,
    "phi": 2.23, "Aeff": 25.0, "beta0": 2.3, "beta1": -2.4, "Ca50ref": 0.805,
}


def rhs(state, ca, lam, dlam, p=PARAMETERS):
    """d/dt of (XS, XW, CaTRPN, TmBlocked, zeta_s, zeta_w) at calcium ``ca`` [µM]."""
    xs, xw, trpn, tmb, zs, zw = state
    xs, xw, trpn = max(xs, 0.0), max(xw, 0.0), max(trpn, 0.0)
    kwu = p["kuw"] * (1 / p["rw"] - 1) - p["kws"]
    ksu = p["kws"] * p["rw"] * (1 / p["rs"] - 1)
    kb = p["ku"] * p["TRPN50"] ** p["nTM"] / (1 - p["rs"] - (1 - p["rs"]) * p["rw"])
    a = p["Aeff"] * p["rs"] / ((1 - p["rs"]) * p["rw"] + p["rs"])
    cw = p["phi"] * p["kuw"] * (1 - p["rw"]) / p["rw"]
    cs = p["phi"] * p["kws"] * p["rw"] * (1 - p["rs"]) / p["rs"]
    xu = 1 - tmb - xs - xw
    gwu = p["gammaw"] * abs(zw)
    gsu = p["gammas"] * max(zs, -1 - zs, 0.0)
    ca50 = p["Ca50ref"] + p["beta1"] * (min(lam, 1.2) - 1)
    up = min(trpn ** (-p["nTM"] / 2), 100.0) if trpn > 0 else 100.0
    return np.array([
        p["kws"] * xw - ksu * xs - gsu * xs,
        p["kuw"] * xu - kwu * xw - p["kws"] * xw - gwu * xw,
        p["kTRPN"] * ((max(ca, 0.0) / ca50) ** p["nTRPN"] * (1 - trpn) - trpn),
        kb * up * xu - p["ku"] * trpn ** (p["nTM"] / 2) * tmb,
        a * dlam - cs * zs,
        a * dlam - cw * zw,
    ])


def tension(state, lam, p=PARAMETERS):
    """T_a [kPa] of a state at stretch ``lam``."""
    xs, xw, _, _, zs, zw = state
    lm = min(lam, 1.2)
    h = max(0.0, 1 + p["beta0"] * (lm + min(lm, 0.87) - 1.87))
    return h * p["Tref"] / p["rs"] * ((zs + 1) * max(xs, 0.0) + zw * max(xw, 0.0))


def isometric_twitch(time, calcium, lam=1.0, p=PARAMETERS):
    """Tension [kPa] at ``time`` [ms] of a cell at fixed stretch ``lam`` driven by the calcium
    trace ``calcium`` [µM] (linear between the samples), from rest at ``time[0]``."""
    time, calcium = np.asarray(time, float), np.asarray(calcium, float)
    y0 = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    sol = solve_ivp(lambda t, y: rhs(y, np.interp(t, time, calcium), lam, 0.0, p),
                    (time[0], time[-1]), y0, method="Radau", t_eval=time, rtol=1e-8,
                    atol=1e-10, max_step=float(np.min(np.diff(time))) * 4)
    if not sol.success:
        raise RuntimeError(sol.message)
    return np.array([tension(y, lam, p) for y in sol.y.T])
