"""Independent reference for the ten Tusscher-Panfilov 2006 cell: SciPy on the model file.

The right-hand side is the Python that gotranx generated from the model's ``.ode`` files
(``systole_post.cellmodels``, see its docstring), not the C++ model. It is integrated with
SciPy's ``solve_ivp`` (BDF, tight tolerances) piecewise between the stimulus switching times,
with the stimulus exactly as the .ode has it (``i_Stim = stim_amplitude``, which also enters
dK_i/dt), and each beat is measured as ``problem = cell`` of systole measures it:

- resting potential: V at the stimulus onset;
- peak potential: the maximum of V over the beat;
- APD90: the time V spends above V_rest + 0.1 (V_peak - V_rest), from the upward to the
  first downward crossing after the peak, interpolated linearly between samples;
- peak calcium: the maximum of Ca_i over the beat, in µM.
The maxima and crossings use the dense output on a grid of ``sample_step`` ms.
"""

import importlib

import numpy as np
from scipy.integrate import solve_ivp

#: Variant name of systole's "Cell type" -> gotranx module.
VARIANTS = {
    "epicardial": "tentusscher_panfilov_2006_epi_cell",
    "endocardial": "tentusscher_panfilov_2006_endo_cell",
    "mid-myocardial": "tentusscher_panfilov_2006_M_cell",
}


def model_module(cell_type):
    """The generated module of a variant ("epicardial", "endocardial", "mid-myocardial")."""
    return importlib.import_module(f"systole_post.cellmodels.{VARIANTS[cell_type]}")


def beat_measures(t, V, Ca_uM, onset):
    """The measures of one beat sampled at times ``t`` (from the stimulus onset ``onset`` on).

    Returns a dict with resting_potential_mV, peak_potential_mV, APD90_ms, peak_calcium_uM.
    """
    t, V, Ca_uM = (np.asarray(a, dtype=float) for a in (t, V, Ca_uM))
    keep = t >= onset - 1e-12
    t, V, Ca_uM = t[keep], V[keep], Ca_uM[keep]
    rest, peak = V[0], V.max()
    level = rest + 0.1 * (peak - rest)
    i_peak = int(np.argmax(V))

    def crossing(i):
        return t[i - 1] + (level - V[i - 1]) / (V[i] - V[i - 1]) * (t[i] - t[i - 1])

    up = next(i for i in range(1, i_peak + 1) if V[i - 1] <= level < V[i])
    down = next((i for i in range(i_peak + 1, len(V)) if V[i - 1] > level >= V[i]), None)
    apd = np.nan if down is None else crossing(down) - crossing(up)
    return {"resting_potential_mV": rest, "peak_potential_mV": peak, "APD90_ms": apd,
            "peak_calcium_uM": Ca_uM.max()}


def reference_beats(cell_type, n_beats, period=1000.0, stim_start=10.0, stim_duration=1.0,
                    stim_amplitude=-52.0, sample_step=0.005, rtol=1e-8, atol=1e-10):
    """Integrate ``n_beats`` beats from the model file's initial state; one dict per beat.

    The stimulus (``stim_amplitude`` pA/pF, the .ode's sign: negative depolarises) is on in
    [k period + stim_start, k period + stim_start + stim_duration].
    """
    model = model_module(cell_type)
    on = model.init_parameter_values(stim_amplitude=stim_amplitude, stim_start=stim_start,
                                     stim_duration=stim_duration, stim_period=period)
    off = model.init_parameter_values(stim_amplitude=0.0, stim_period=period)
    i_V, i_Ca = model.state_index("V"), model.state_index("Ca_i")
    y = model.init_state_values()
    beats = []
    for k in range(n_beats):
        t0 = k * period
        onset = t0 + stim_start
        segments = [(t0, onset, off), (onset, onset + stim_duration, on),
                    (onset + stim_duration, t0 + period, off)]
        times, V, Ca = [], [], []
        for a, b, parameters in segments:
            solution = solve_ivp(lambda t, z, p=parameters: model.rhs(t, z, p), (a, b), y,
                                 method="BDF", rtol=rtol, atol=atol, dense_output=True)
            assert solution.success, solution.message
            grid = np.append(np.arange(a, b, sample_step), b)
            values = solution.sol(grid)
            times.append(grid)
            V.append(values[i_V])
            Ca.append(1000.0 * values[i_Ca])
            y = solution.y[:, -1]
        beats.append(beat_measures(np.concatenate(times), np.concatenate(V),
                                   np.concatenate(Ca), onset))
    return beats
