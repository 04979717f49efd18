"""Plot the helix-angle profile that ``systole-fibres`` writes as the /summary table.

One row per bin of the transmural coordinate (0 endocardium, 1 epicardium), with the
columns ``depth_lower``, ``depth_upper``, ``depth`` (bin centre), ``helix_mean``,
``helix_min``, ``helix_max`` [degree] and ``n_points``; an empty bin has NaN angles.
Uses matplotlib's Agg canvas directly (no pyplot, no display).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from systole_post.results import Results, read_results

#: The /summary columns of a helix-angle profile.
PROFILE_COLUMNS = ("depth", "helix_mean", "helix_min", "helix_max", "n_points")


def helix_profile(results: Results) -> dict[str, np.ndarray]:
    """The profile's columns, without the empty bins.

    Raises:
        ValueError: the file has no helix-angle profile (not written by systole-fibres,
            or the mesh had no endocardium, epicardium and base).
    """
    missing = [name for name in PROFILE_COLUMNS if name not in results.summary]
    if missing:
        raise ValueError(
            f"{results.path}: no helix-angle profile in /summary (missing {missing}); "
            "write one with systole-fibres on an LV mesh"
        )
    filled = results.summary["n_points"] > 0
    return {name: results.summary[name][filled] for name in PROFILE_COLUMNS}


def make_helix_profile_figure(results: Results) -> Figure:
    """Mean helix angle against transmural depth, with the band from min to max."""
    profile = helix_profile(results)
    figure = Figure(figsize=(6.0, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    ax = figure.subplots()
    ax.fill_between(profile["depth"], profile["helix_min"], profile["helix_max"],
                    alpha=0.3, label="min to max")
    ax.plot(profile["depth"], profile["helix_mean"], marker="o", label="mean")
    ax.axhline(0.0, color="grey", linewidth=0.8)
    ax.set_xlim(0.0, 1.0)
    ax.set_xlabel("transmural depth [-] (0 endocardium, 1 epicardium)")
    ax.set_ylabel("helix angle [degree]")
    ax.set_title("Helix angle through the wall")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return figure


def plot_helix_profile(results: Results | str | Path, png_path: str | Path) -> Path:
    """Write the helix-angle profile of a results file as a PNG; returns its path."""
    if not isinstance(results, Results):
        results = read_results(results)
    png_path = Path(png_path)
    make_helix_profile_figure(results).savefig(png_path, format="png", dpi=100)
    return png_path
