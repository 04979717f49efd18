"""Global sensitivity of a study's outputs: a Gaussian-process emulator and its Sobol indices.

The emulator (scikit-learn's GaussianProcessRegressor) is trained on the study's inputs
mapped to the unit cube (uniformly, or in log for a log range) with a constant times an
anisotropic squared-exponential kernel plus a white-noise term, on standardized outputs. Its
accuracy is measured by cross-validation (leave-one-out up to 40 runs, else 10 folds): the
root-mean-square and largest errors of the held-out predictions, in % of the output's range
over the study, and Q^2 = 1 - SSE / SST.

The Sobol indices assume independent inputs uniform over the study's ranges. They are
estimated on the emulator's mean with Saltelli's sampling (matrices A, B and A_B^i from one
scrambled Sobol sequence): first order after Saltelli et al. 2010 (Comput. Phys. Commun.
181:259, table 2 (b)), total after Jansen 1999 (table 2 (f)). Their confidence intervals
combine, as independent errors, the estimator's sampling error (bootstrap over the base
samples) and the emulator's uncertainty (the spread of the indices over draws of the
Gaussian-process posterior, jointly at every Saltelli point).

Command line: ``systole-study sensitivity STUDY_DIR --output lv_EF [--output ...]`` writes
``STUDY_DIR/sensitivity/``: ``indices.csv``, ``sensitivity.json`` and the plots
``main_effects_<output>.png``, ``indices.png``, ``emulator_cv.png``.
"""

from __future__ import annotations

import csv
import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.stats import norm, qmc

#: Cross-validation is leave-one-out up to this many runs, else 10-fold.
LOO_MAX = 40


@dataclass
class Emulator:
    """A Gaussian process on inputs scaled to [0, 1]^d.

    Attributes:
        low, high: the input ranges (in log when ``log`` is set for that input).
        log: per input, whether the unit coordinate is linear in log(value).
        gp: the fitted sklearn GaussianProcessRegressor (inputs in the unit cube).
    """

    low: np.ndarray
    high: np.ndarray
    log: np.ndarray
    gp: object
    y_mean: float = 0.0
    y_std: float = 1.0
    warnings: list[str] = field(default_factory=list)

    def to_unit(self, x: np.ndarray) -> np.ndarray:
        x = np.where(self.log, np.log(np.where(self.log, x, 1.0)), x)
        return (x - self.low) / (self.high - self.low)

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        x = self.low + u * (self.high - self.low)
        return np.where(self.log, np.exp(x), x)

    def predict_unit(self, u: np.ndarray, return_std=False):
        """The emulator's mean (and standard deviation) at unit-cube points."""
        if return_std:
            mean, std = self.gp.predict(np.atleast_2d(u), return_std=True)
            return mean * self.y_std + self.y_mean, std * self.y_std
        return self.gp.predict(np.atleast_2d(u)) * self.y_std + self.y_mean

    def predict(self, x: np.ndarray, return_std=False):
        return self.predict_unit(self.to_unit(np.atleast_2d(x)), return_std)


def _ranges(low, high, log):
    log = np.asarray(log if log is not None else np.zeros(len(low)), dtype=bool)
    low, high = np.asarray(low, float), np.asarray(high, float)
    return np.where(log, np.log(np.where(log, low, 1.0)), low), \
        np.where(log, np.log(np.where(log, high, 1.0)), high), log


def fit_emulator(x: np.ndarray, y: np.ndarray, low, high, log=None, seed: int = 0,
                 restarts: int = 4) -> Emulator:
    """Fit the emulator to runs ``x`` (n x d, in the inputs' units) and outputs ``y`` (n)."""
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

    low, high, log = _ranges(low, high, log)
    d = x.shape[1]
    emulator = Emulator(low, high, log, None)
    u = emulator.to_unit(np.asarray(x, float))
    kernel = (ConstantKernel(1.0, (1e-3, 1e3))
              * RBF(length_scale=np.full(d, 0.5), length_scale_bounds=(0.05, 1e3))
              + WhiteKernel(1e-4, (1e-8, 1e-1)))
    # The outputs are standardized here rather than by normalize_y, so that
    # latent_posterior can undo it without sklearn's private attributes.
    y = np.asarray(y, float)
    emulator.y_mean = float(y.mean())
    emulator.y_std = float(y.std()) or 1.0
    gp = GaussianProcessRegressor(kernel=kernel, normalize_y=False,
                                  n_restarts_optimizer=restarts, random_state=seed)
    with warnings.catch_warnings(record=True) as caught:
        # Hyperparameters at a bound (noise-free data: the smallest noise level) and
        # line-search stops of L-BFGS are expected; the cross-validation judges the fit.
        warnings.simplefilter("always", ConvergenceWarning)
        gp.fit(u, (y - emulator.y_mean) / emulator.y_std)
    emulator.gp = gp
    emulator.warnings = [str(w.message).splitlines()[0] for w in caught
                         if issubclass(w.category, ConvergenceWarning)]
    return emulator


@dataclass
class CrossValidation:
    """Held-out predictions and the errors, as fractions of the output's range."""

    predicted: np.ndarray
    std: np.ndarray
    rmse: float
    max_error: float
    rmse_of_range: float
    max_error_of_range: float
    q2: float
    folds: int


def cross_validate(x, y, low, high, log=None, seed: int = 0, restarts: int = 2
                   ) -> CrossValidation:
    """Leave-one-out (n <= LOO_MAX) or 10-fold cross-validation of the emulator."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    n = len(y)
    folds = n if n <= LOO_MAX else 10
    order = np.random.default_rng(seed).permutation(n)
    predicted, std = np.empty(n), np.empty(n)
    for k in range(folds):
        test = order[k::folds]
        train = np.setdiff1d(np.arange(n), test)
        emulator = fit_emulator(x[train], y[train], low, high, log, seed, restarts)
        predicted[test], std[test] = emulator.predict(x[test], return_std=True)
    error = predicted - y
    spread = float(np.ptp(y)) or 1.0
    rmse = float(np.sqrt(np.mean(error**2)))
    max_error = float(np.max(np.abs(error)))
    q2 = 1.0 - float(np.sum(error**2) / max(np.sum((y - y.mean()) ** 2), 1e-300))
    return CrossValidation(predicted, std, rmse, max_error, rmse / spread, max_error / spread,
                           q2, folds)


@dataclass
class SobolIndices:
    """First-order and total Sobol indices with confidence intervals (low, high)."""

    first: np.ndarray
    total: np.ndarray
    first_ci: np.ndarray  # d x 2
    total_ci: np.ndarray  # d x 2
    variance: float
    samples: int
    confidence: float
    draws: int = 0
    extra: dict = field(default_factory=dict)


def saltelli_points(d: int, n: int, seed: int) -> np.ndarray:
    """The points of A, B and A_B^i (i = 1..d) stacked: ((d + 2) n) x d, in the unit cube."""
    base = qmc.Sobol(2 * d, scramble=True, seed=seed)
    m = int(math.ceil(math.log2(n)))
    ab = base.random_base2(m)[:n]
    a, b = ab[:, :d], ab[:, d:]
    blocks = [a, b]
    for i in range(d):
        abi = a.copy()
        abi[:, i] = b[:, i]
        blocks.append(abi)
    return np.vstack(blocks)


def _indices(f: np.ndarray, n: int, d: int, rows: np.ndarray | None = None):
    """First and total indices from the stacked values f (A, B, A_B^1..d); ``rows``
    resamples the base samples (bootstrap). f may be (..., (d+2) n)."""
    f = f.reshape(f.shape[:-1] + (d + 2, n))
    if rows is not None:
        f = f[..., rows]
    # Centre the values: the estimators are unbiased either way, but a large mean (EF
    # around 55 % that varies by a few %) would multiply the first-order one's variance.
    f = f - f[..., :2, :].mean(axis=(-2, -1), keepdims=True)
    fa, fb, fab = f[..., 0, :], f[..., 1, :], f[..., 2:, :]
    var = np.var(np.concatenate([fa, fb], axis=-1), axis=-1)
    first = np.mean(fb[..., None, :] * (fab - fa[..., None, :]), axis=-1) / var[..., None]
    total = 0.5 * np.mean((fa[..., None, :] - fab) ** 2, axis=-1) / var[..., None]
    return first, total, var


def sobol_indices(function, d: int, n: int = 4096, seed: int = 0, confidence: float = 0.95,
                  bootstrap: int = 500, posterior=None, draws: int = 64,
                  draw_samples: int = 256) -> SobolIndices:
    """Sobol indices of ``function`` (unit-cube points m x d -> m values).

    Args:
        function: the (emulator's mean) function on [0, 1]^d.
        n: base samples (rounded up to a power of 2); (d + 2) n evaluations.
        bootstrap: resamples of the base samples for the sampling error.
        posterior: optional ``f(points) -> (mean, covariance)`` of the emulator; the
            indices of ``draws`` joint posterior draws at ``draw_samples`` base samples
            give the emulator's share of the uncertainty.
    """
    n = 2 ** int(math.ceil(math.log2(n)))
    points = saltelli_points(d, n, seed)
    values = np.asarray(function(points), float)
    first, total, var = _indices(values, n, d)
    rng = np.random.default_rng(seed)
    rows = rng.integers(0, n, size=(bootstrap, n))
    boot_first = np.empty((bootstrap, d))
    boot_total = np.empty((bootstrap, d))
    for k in range(bootstrap):
        boot_first[k], boot_total[k], _ = _indices(values, n, d, rows[k])
    z = norm.ppf(0.5 + confidence / 2)
    half_first = z * boot_first.std(axis=0)
    half_total = z * boot_total.std(axis=0)
    extra = {"bootstrap_halfwidth_first": half_first.tolist(),
             "bootstrap_halfwidth_total": half_total.tolist()}
    if posterior is not None and draws > 0:
        m = 2 ** int(math.ceil(math.log2(draw_samples)))
        pts = saltelli_points(d, m, seed + 1)
        mean, cov = posterior(pts)
        cov = 0.5 * (cov + cov.T)
        jitter = 1e-10 * max(np.trace(cov) / len(cov), 1e-300)
        for _ in range(8):
            try:
                chol = np.linalg.cholesky(cov + jitter * np.eye(len(cov)))
                break
            except np.linalg.LinAlgError:
                jitter *= 100
        else:
            raise np.linalg.LinAlgError("posterior covariance is not positive definite")
        samples = mean + (chol @ rng.standard_normal((len(cov), draws))).T
        gp_first, gp_total, _ = _indices(samples, m, d)
        gp_half_first = z * gp_first.std(axis=0)
        gp_half_total = z * gp_total.std(axis=0)
        extra["emulator_halfwidth_first"] = gp_half_first.tolist()
        extra["emulator_halfwidth_total"] = gp_half_total.tolist()
        half_first = np.hypot(half_first, gp_half_first)
        half_total = np.hypot(half_total, gp_half_total)
    return SobolIndices(first, total, np.stack([first - half_first, first + half_first], 1),
                        np.stack([total - half_total, total + half_total], 1), float(var), n,
                        confidence, draws if posterior is not None else 0, extra)


def latent_posterior(emulator: Emulator, points: np.ndarray):
    """Mean and covariance of the emulated function at unit-cube ``points``, without the
    white-noise term (which would add independent noise to every draw of the function)."""
    from scipy.linalg import solve_triangular

    gp = emulator.gp
    signal_kernel = gp.kernel_.k1  # constant * RBF; k2 is the white noise
    k_star = signal_kernel(points, gp.X_train_)
    mean = k_star @ gp.alpha_
    v = solve_triangular(gp.L_, k_star.T, lower=True)
    cov = signal_kernel(points) - v.T @ v
    return mean * emulator.y_std + emulator.y_mean, cov * emulator.y_std**2


def emulator_sobol(emulator: Emulator, n: int = 4096, seed: int = 0, draws: int = 64,
                   **kwargs) -> SobolIndices:
    """Sobol indices of the emulator's mean, with its posterior uncertainty in the CIs."""

    def posterior(points):
        return latent_posterior(emulator, points)

    return sobol_indices(emulator.predict_unit, len(emulator.low), n, seed,
                         posterior=posterior if draws else None, draws=draws, **kwargs)


def main_effects(emulator: Emulator, levels: int = 41, samples: int = 512, seed: int = 0):
    """E[y | x_i] on a grid of each input, averaging the emulator over the others.

    Returns (grid values (d x levels, in the inputs' units), means (d x levels)).
    """
    d = len(emulator.low)
    others = qmc.Sobol(d, scramble=True, seed=seed).random(samples)
    grid = np.linspace(0.0, 1.0, levels)
    means = np.empty((d, levels))
    for i in range(d):
        points = np.repeat(others[None], levels, axis=0)
        points[:, :, i] = grid[:, None]
        means[i] = emulator.predict_unit(points.reshape(-1, d)).reshape(levels, samples) \
            .mean(axis=1)
    values = np.array([emulator.from_unit(np.tile(grid[:, None], (1, d)))[:, i]
                       for i in range(d)])
    return values, means


# ----------------------------------------------------------------------------- a study


@dataclass
class OutputSensitivity:
    """Everything computed for one output of a study."""

    output: str
    unit: str
    inputs: list[str]
    n_runs: int
    y_range: tuple[float, float]
    cv: CrossValidation
    indices: SobolIndices
    effects: tuple
    x: np.ndarray
    y: np.ndarray

    def ranking(self) -> list[str]:
        """Inputs by decreasing total index."""
        return [self.inputs[i] for i in np.argsort(-self.indices.total)]


def analyse_table(table, outputs, samples: int = 4096, seed: int = 0, draws: int = 64
                  ) -> list[OutputSensitivity]:
    """Emulator, cross-validation, Sobol indices and main effects of each output."""
    inputs = list(table.parameter_entries)
    done = np.array([s == "done" for s in table.columns["status"]])
    x_all = np.column_stack([table.array(name) for name in inputs])
    low = np.array([table.ranges.get(name, (np.nanmin(x_all[:, j]),))[0]
                    for j, name in enumerate(inputs)])
    high = np.array([table.ranges.get(name, (0, np.nanmax(x_all[:, j])))[1]
                     for j, name in enumerate(inputs)])
    log = np.array([table.logs.get(name, False) for name in inputs])
    results = []
    for output in outputs:
        if output not in table.columns:
            raise KeyError(f"the table has no output column '{output}'")
        y_all = table.array(output)
        keep = done & np.isfinite(y_all)
        x, y = x_all[keep], y_all[keep]
        if len(y) < len(inputs) + 2:
            raise ValueError(f"{output}: {len(y)} finished runs are too few for "
                             f"{len(inputs)} inputs")
        cv = cross_validate(x, y, low, high, log, seed)
        emulator = fit_emulator(x, y, low, high, log, seed)
        indices = emulator_sobol(emulator, samples, seed, draws)
        effects = main_effects(emulator, seed=seed)
        results.append(OutputSensitivity(output, table.units.get(output, ""), inputs, len(y),
                                         (float(y.min()), float(y.max())), cv, indices,
                                         effects, x, y))
    return results


def report_lines(results: list[OutputSensitivity]) -> list[str]:
    """A terminal summary (< 100 columns)."""
    lines = []
    for r in results:
        lines.append(f"{r.output} [{r.unit}]: {r.n_runs} runs, range {r.y_range[0]:.4g} .. "
                     f"{r.y_range[1]:.4g}")
        lines.append(f"  emulator, {r.cv.folds}-fold cross-validation: RMSE "
                     f"{100 * r.cv.rmse_of_range:.1f} % of the range, largest error "
                     f"{100 * r.cv.max_error_of_range:.1f} %, Q2 {r.cv.q2:.3f}")
        pct = int(round(100 * r.indices.confidence))
        lines.append(f"  {'input':<16} {'S1':>7} {pct:>3}% CI{'':<10} {'ST':>7} {pct:>3}% CI")
        for i in np.argsort(-r.indices.total):
            f, t = r.indices.first_ci[i], r.indices.total_ci[i]
            lines.append(f"  {r.inputs[i]:<16} {r.indices.first[i]:7.3f} "
                         f"[{f[0]:6.3f}, {f[1]:6.3f}] {r.indices.total[i]:7.3f} "
                         f"[{t[0]:6.3f}, {t[1]:6.3f}]")
        lines.append("  ranking (total index): " + " > ".join(r.ranking()))
    return lines


def write_results(results: list[OutputSensitivity], out_dir: Path) -> None:
    """indices.csv (one row per output and input) and sensitivity.json."""
    out_dir.mkdir(parents=True, exist_ok=True)
    with open(out_dir / "indices.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["output", "input", "S1", "S1_low", "S1_high", "ST", "ST_low",
                         "ST_high", "cv_rmse_percent_of_range",
                         "cv_max_error_percent_of_range", "cv_q2", "runs"])
        for r in results:
            for i, name in enumerate(r.inputs):
                writer.writerow([r.output, name, *(f"{v:.6g}" for v in (
                    r.indices.first[i], *r.indices.first_ci[i], r.indices.total[i],
                    *r.indices.total_ci[i], 100 * r.cv.rmse_of_range,
                    100 * r.cv.max_error_of_range, r.cv.q2)), r.n_runs])
    data = {r.output: {
        "unit": r.unit, "runs": r.n_runs, "range": r.y_range, "ranking": r.ranking(),
        "cv": {"folds": r.cv.folds, "rmse": r.cv.rmse, "max_error": r.cv.max_error,
               "rmse_percent_of_range": 100 * r.cv.rmse_of_range,
               "max_error_percent_of_range": 100 * r.cv.max_error_of_range, "q2": r.cv.q2},
        "sobol": {"confidence": r.indices.confidence, "samples": r.indices.samples,
                  "posterior_draws": r.indices.draws,
                  "inputs": {name: {"S1": r.indices.first[i],
                                    "S1_ci": r.indices.first_ci[i].tolist(),
                                    "ST": r.indices.total[i],
                                    "ST_ci": r.indices.total_ci[i].tolist()}
                             for i, name in enumerate(r.inputs)}}}
        for r in results}
    (out_dir / "sensitivity.json").write_text(json.dumps(data, indent=1, default=float) + "\n")


def plot_results(results: list[OutputSensitivity], out_dir: Path, units=None) -> list[Path]:
    """Main effects (one figure per output), index bars and emulator-vs-held-out plots."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = units or {}
    paths = []
    for r in results:
        d = len(r.inputs)
        fig, axes = plt.subplots(1, d, figsize=(3.2 * d, 3.0), sharey=True, squeeze=False)
        values, means = r.effects
        for i, ax in enumerate(axes[0]):
            ax.scatter(r.x[:, i], r.y, s=12, color="0.6", label="runs")
            ax.plot(values[i], means[i], color="C0", label="emulator E[y | x]")
            unit = units.get(r.inputs[i], "")
            ax.set_xlabel(r.inputs[i] + (f" [{unit}]" if unit and unit != "-" else ""))
        axes[0][0].set_ylabel(f"{r.output} [{r.unit}]")
        axes[0][0].legend(fontsize=7)
        fig.suptitle(f"Main effects on {r.output}")
        fig.tight_layout()
        paths.append(out_dir / f"main_effects_{r.output}.png")
        fig.savefig(paths[-1], dpi=110)
        plt.close(fig)

    fig, axes = plt.subplots(1, len(results), figsize=(4.0 * len(results), 3.2),
                             squeeze=False)
    for ax, r in zip(axes[0], results):
        pos = np.arange(len(r.inputs))
        for shift, value, ci, label in ((-0.18, r.indices.first, r.indices.first_ci, "first"),
                                        (0.18, r.indices.total, r.indices.total_ci, "total")):
            err = np.abs(ci - value[:, None]).T
            ax.bar(pos + shift, value, 0.36, yerr=err, capsize=3, label=label)
        ax.set_xticks(pos, r.inputs, rotation=30, ha="right", fontsize=8)
        ax.set_ylim(0, max(1.0, float(np.max(r.indices.total_ci)) + 0.05))
        ax.set_title(r.output, fontsize=9)
    axes[0][0].set_ylabel(f"Sobol index ({int(100 * results[0].indices.confidence)} % CI)")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    paths.append(out_dir / "indices.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, len(results), figsize=(3.6 * len(results), 3.4),
                             squeeze=False)
    for ax, r in zip(axes[0], results):
        ax.errorbar(r.y, r.cv.predicted, yerr=2 * r.cv.std, fmt="o", ms=3, capsize=2)
        lo, hi = r.y_range
        pad = 0.05 * (hi - lo or 1.0)
        ax.plot([lo - pad, hi + pad], [lo - pad, hi + pad], color="0.5", lw=0.8)
        ax.set_xlabel(f"run [{r.unit}]")
        ax.set_title(f"{r.output}: CV RMSE {100 * r.cv.rmse_of_range:.1f} % of range",
                     fontsize=8)
    axes[0][0].set_ylabel("emulator, held out (±2σ)")
    fig.tight_layout()
    paths.append(out_dir / "emulator_cv.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)
    return paths


def main_for_study(folder, outputs, samples=4096, seed=0, plots=True) -> int:
    """``systole-study sensitivity``: analyse, print, write and plot."""
    from systole_post.study import read_table

    folder = Path(folder)
    table = read_table(folder)
    results = analyse_table(table, outputs, samples, seed)
    out_dir = folder / "sensitivity"
    write_results(results, out_dir)
    for line in report_lines(results):
        print(line)
    if plots:
        for path in plot_results(results, out_dir, table.units):
            print(f"wrote {path}")
    print(f"wrote {out_dir / 'indices.csv'}")
    return 0
