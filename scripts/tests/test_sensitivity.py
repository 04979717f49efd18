"""Sobol indices from the Gaussian-process emulator: the Ishigami function's exact indices,
cross-validation, and the analysis of a study table (with its plots)."""

import json

import numpy as np
import pytest
from scipy.stats import qmc

from systole_post import sensitivity as se
from systole_post.study import Table

PI = np.pi


def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices(a=7.0, b=0.1):
    """Exact first and total indices (Ishigami and Homma 1990; Sobol' and Levitan 1999)."""
    variance = a**2 / 8 + b * PI**4 / 5 + b**2 * PI**8 / 18 + 0.5
    v1 = 0.5 * (1 + b * PI**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = b**2 * PI**8 * (1 / 18 - 1 / 50)
    return np.array([v1, v2, 0.0]) / variance, np.array([v1 + v13, v2, v13]) / variance


def test_emulator_sobol_indices_of_the_ishigami_function_match_the_exact_values():
    low, high = [-PI] * 3, [PI] * 3
    x = qmc.scale(qmc.LatinHypercube(3, seed=1).random(200), low, high)
    emulator = se.fit_emulator(x, ishigami(x), low, high, restarts=2)
    indices = se.emulator_sobol(emulator, n=4096, draws=32)
    first, total = ishigami_indices()
    assert indices.first == pytest.approx(first, abs=0.05)
    assert indices.total == pytest.approx(total, abs=0.05)
    # The intervals contain the exact values and are informative.
    assert np.all((indices.first_ci[:, 0] <= first) & (first <= indices.first_ci[:, 1]))
    assert np.all((indices.total_ci[:, 0] <= total) & (total <= indices.total_ci[:, 1]))
    assert np.all(np.diff(indices.total_ci, axis=1) < 0.2)


def test_saltelli_estimators_on_a_linear_function_without_emulator():
    # y = x1 + 2 x2 on the unit square: S_i = a_i^2 / sum a^2, no interactions.
    indices = se.sobol_indices(lambda u: u[:, 0] + 2 * u[:, 1], d=2, n=1024, bootstrap=100)
    assert indices.first == pytest.approx([0.2, 0.8], abs=0.02)
    assert indices.total == pytest.approx([0.2, 0.8], abs=0.02)


def test_cross_validation_of_a_smooth_function_is_accurate_and_of_noise_is_not():
    rng = np.random.default_rng(0)
    x = qmc.LatinHypercube(2, seed=2).random(20) * [2.0, 10.0] + [1.0, 0.0]
    smooth = se.cross_validate(x, x[:, 0] ** 2 + 0.3 * x[:, 1], [1, 0], [3, 10])
    assert smooth.folds == 20 and smooth.rmse_of_range < 0.02 and smooth.q2 > 0.99
    noise = se.cross_validate(x, rng.standard_normal(20), [1, 0], [3, 10], restarts=0)
    assert noise.rmse_of_range > 0.1 and noise.q2 < 0.5


def test_log_inputs_are_emulated_in_log_space():
    x = np.exp(np.linspace(np.log(0.01), np.log(100.0), 12))[:, None]
    emulator = se.fit_emulator(x, np.log10(x[:, 0]), [0.01], [100.0], log=[True])
    assert emulator.to_unit(np.array([[1.0]]))[0, 0] == pytest.approx(0.5)
    assert emulator.predict(np.array([[10.0]]))[0] == pytest.approx(1.0, abs=0.01)


def test_analysis_of_a_study_table_ranks_inputs_and_writes_plots(tmp_path):
    u = qmc.LatinHypercube(3, seed=4).random(24)
    x = u * [2.0, 50.0, 1.0] + [1.0, 100.0, 0.0]
    columns = {"case": [f"case_{i:04d}" for i in range(24)], "status": ["done"] * 24,
               "error": [""] * 24, "wall_time": [1.0] * 24,
               "a": list(x[:, 0]), "b": list(x[:, 1]), "c": list(x[:, 2])}
    # EF depends on b strongly, a weakly and c not at all; a failed run is left out.
    ef = 40 + 0.4 * (x[:, 1] - 100) + 2.0 * x[:, 0]
    columns["lv_EF"] = list(ef)
    columns["status"][3] = "failed"
    columns["lv_EF"][3] = float("nan")
    table = Table(columns, {"lv_EF": "%"}, {"a": "M / a", "b": "M / b", "c": "M / c"},
                  ["lv_EF"], {"a": (1.0, 3.0), "b": (100.0, 150.0), "c": (0.0, 1.0)})
    (result,) = se.analyse_table(table, ["lv_EF"], samples=1024, draws=16)
    assert result.n_runs == 23
    assert result.ranking() == ["b", "a", "c"]
    assert result.cv.rmse_of_range < 0.05
    # Exact for the linear law: var(0.4 b) = 0.16 * 50^2 / 12, var(2 a) = 4 * 4 / 12.
    va, vb = 16 / 12, 0.16 * 2500 / 12
    assert result.indices.first == pytest.approx([va / (va + vb), vb / (va + vb), 0], abs=0.03)
    lines = se.report_lines([result])
    assert max(len(line) for line in lines) <= 100
    assert lines[-1] == "  ranking (total index): b > a > c"

    se.write_results([result], tmp_path)
    data = json.loads((tmp_path / "sensitivity.json").read_text())
    assert data["lv_EF"]["ranking"] == ["b", "a", "c"]
    assert (tmp_path / "indices.csv").read_text().count("\n") == 4
    paths = se.plot_results([result], tmp_path)
    assert [p.name for p in paths] == ["main_effects_lv_EF.png", "indices.png",
                                       "emulator_cv.png"]
    assert all(p.stat().st_size > 10_000 for p in paths)
