"""The reference's beat measures and model code (systole_post.ten_tusscher_reference)."""

import numpy as np

from systole_post.ten_tusscher_reference import VARIANTS, beat_measures, model_module


def test_a_trapezoidal_action_potential_has_the_apd90_of_its_90_percent_level():
    # Rest -80 mV at the onset 10 ms, upstroke to +20 mV at 11 ms, plateau to 300 ms,
    # repolarisation to -80 mV at 400 ms: the level -70 mV is crossed at 10.1 and 390 ms.
    t = np.arange(0.0, 600.0, 0.25)
    V = np.interp(t, [0, 10, 11, 300, 400, 600], [-80, -80, 20, 20, -80, -80])
    calcium = 0.1 + 0.9 * np.exp(-((t - 50) / 20) ** 2)
    m = beat_measures(t, V, calcium, onset=10.0)
    assert m["resting_potential_mV"] == -80
    assert m["peak_potential_mV"] == 20
    assert abs(m["APD90_ms"] - (390 - 10.1)) < 1e-9
    assert abs(m["peak_calcium_uM"] - 1.0) < 1e-12


def test_the_variants_differ_only_in_the_transient_outward_and_slow_rectifier_currents():
    epi, endo, mid = (model_module(v) for v in ("epicardial", "endocardial", "mid-myocardial"))
    assert set(VARIANTS) == {"epicardial", "endocardial", "mid-myocardial"}
    p_epi, p_endo, p_mid = (m.init_parameter_values() for m in (epi, endo, mid))
    g_to, g_Ks = epi.parameter_index("g_to"), epi.parameter_index("g_Ks")
    assert (p_epi[g_to], p_endo[g_to], p_mid[g_to]) == (0.294, 0.073, 0.294)
    assert (p_epi[g_Ks], p_endo[g_Ks], p_mid[g_Ks]) == (0.392, 0.392, 0.098)
    others = [i for i in range(len(p_epi)) if i not in (g_to, g_Ks)]
    assert np.array_equal(p_epi[others], p_endo[others])
    assert np.array_equal(p_epi[others], p_mid[others])
    assert np.array_equal(epi.init_state_values(), endo.init_state_values())
