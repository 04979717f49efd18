"""The 0D closed loop of `systole` (Problem = circulation) against an independent implementation.

The reference below is written from reference/physiology.md ("Closed-loop circulation",
Regazzoni et al. 2022) in that file's units (mL, mmHg, s), not from the C++ code, and is
integrated with SciPy's Radau at tight tolerances. The app runs 5 beats with its defaults
(which must be the physiology.md values) at tight tolerances; every state must agree to
1e-6 relative (the largest difference over the run divided by the state's largest
magnitude) at the output times, which must be exact multiples of the output interval, and
the blood volume must stay constant to 1e-8 relative.

The app is `$SYSTOLE_APP`, else `$SYSTOLE_BUILD/systole`, else `build/systole` of the
repository. Without it the tests are skipped, unless `SYSTOLE_REQUIRE_APP` is set (the
ctest entry run.circulation_closed_loop_reference sets both).
"""

import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from conftest import SCRIPTS_DIR

N_BEATS = 5
PERIOD = 0.8  # s
OUTPUT_INTERVAL_MS = 1.0

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
    assert solution.success, solution.message
    return solution.y


def app_path():
    if "SYSTOLE_APP" in os.environ:
        return Path(os.environ["SYSTOLE_APP"])
    build = os.environ.get("SYSTOLE_BUILD", str(SCRIPTS_DIR.parent / "build"))
    return Path(build) / "systole"


PARAMETERS = f"""# Written by scripts/tests/test_closed_loop_reference.py: the default closed loop.
set Problem = circulation
subsection Time
  set Time step = {OUTPUT_INTERVAL_MS}
end
subsection Circulation
  set Model                     = closed loop
  set Number of beats           = {N_BEATS}
  set Periodicity tolerance     = 0
  set Relative tolerance        = 1e-10
  set Absolute volume tolerance = 1e-9
end
subsection Output
  set Run name = closed_loop
end
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """Run the app once; returns (timeseries, summary) of its results file."""
    app = app_path()
    if not app.is_file():
        if os.environ.get("SYSTOLE_REQUIRE_APP"):
            pytest.fail(f"the systole app {app} does not exist")
        pytest.skip(f"the systole app {app} is not built")
    folder = tmp_path_factory.mktemp("closed_loop")
    (folder / "closed_loop.prm").write_text(PARAMETERS)
    subprocess.run([str(app), "closed_loop.prm"], cwd=folder, check=True, timeout=600,
                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    with h5py.File(folder / "results" / "closed_loop" / "results.h5", "r") as f:
        timeseries = {k: f["timeseries"][k][()] for k in f["timeseries"]}
        summary = {k: f["summary"][k][()] for k in f["summary"]}
    return timeseries, summary


@pytest.fixture(scope="module")
def reference(run):
    timeseries, _ = run
    return reference_solution(timeseries["time"] / 1000.0)


def test_output_times_are_exact_multiples_of_the_interval(run):
    timeseries, _ = run
    expected = np.arange(N_BEATS * 800 / OUTPUT_INTERVAL_MS + 1) * OUTPUT_INTERVAL_MS
    assert np.array_equal(timeseries["time"], expected)


def test_every_state_matches_the_independent_reference(run, reference):
    timeseries, _ = run
    errors = {}
    for i, (name, _) in enumerate(STATES):
        scale = np.max(np.abs(reference[i]))
        errors[name] = np.max(np.abs(timeseries[name] - reference[i])) / scale
    print("largest relative difference per state:",
          {name: f"{e:.2e}" for name, e in errors.items()})
    assert max(errors.values()) < 1e-6, errors


def test_chamber_pressures_match_the_elastance_law(run, reference):
    timeseries, _ = run
    times_s = timeseries["time"] / 1000.0
    for i, name in enumerate(("la", "lv", "ra", "rv")):
        expected = np.array([chamber_pressure(name, t, v) for t, v in zip(times_s, reference[i])])
        error = np.max(np.abs(timeseries[f"{name}_pressure_mmHg"] - expected))
        assert error < 1e-6 * np.max(np.abs(expected)), (name, error)


def test_total_blood_volume_is_constant(run):
    timeseries, summary = run
    volume = timeseries["total_blood_volume_mL"]
    y0 = np.array([value for _, value in STATES])
    assert volume[0] == pytest.approx(blood_volume(y0), rel=1e-12)
    drift = np.max(np.abs(volume - volume[0])) / volume[0]
    print(f"total blood volume {volume[0]:.6f} mL, largest relative change {drift:.2e}")
    assert drift < 1e-8
    assert np.all(summary["total_blood_volume_drift"] < 1e-8)


def test_summary_has_one_row_per_beat_per_ventricle(run, reference):
    _, summary = run
    assert list(summary["beat"]) == list(range(N_BEATS))
    for prefix in ("lv", "rv"):
        for column in ("EDV_mL", "ESV_mL", "EF", "peak_pressure_mmHg"):
            assert len(summary[f"{prefix}_{column}"]) == N_BEATS
    # EDV and ESV of the last beat (the volumes at the valve closures) against the
    # reference's largest and smallest volume at the 1 ms outputs: equal up to the
    # volume that the valves pass within 1 ms of their closure and the leaks.
    last = slice(int((N_BEATS - 1) * 800 / OUTPUT_INTERVAL_MS), None)
    for i, prefix in ((1, "lv"), (3, "rv")):
        volume = reference[i][last]
        assert summary[f"{prefix}_EDV_mL"][-1] == pytest.approx(volume.max(), rel=1e-4)
        assert summary[f"{prefix}_ESV_mL"][-1] == pytest.approx(volume.min(), rel=1e-4)
