"""AHA 17-segment bull's-eye plots of the /summary columns of the "AHA segments" postprocessor.

The segments follow the C++ Postprocess::AhaSegments: seen from the apex, anterior at the
top, the septum on the left (counter-clockwise from anterior): the basal ring (1-6) outside,
then mid (7-12), apical (13-16) and the apex (17) in the centre. Segment 1 (basal anterior)
spans -30 ... 30 degrees about the top, 13 (apical anterior) -45 ... 45.
"""

from __future__ import annotations

import matplotlib
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import Normalize
from matplotlib.figure import Figure

from .results import Results

#: Quantities of the AHA columns: column suffix -> (title, unit).
QUANTITIES = {
    "peak_strain_circumferential": ("peak circumferential strain", "-"),
    "peak_strain_longitudinal": ("peak longitudinal strain", "-"),
    "peak_strain_radial": ("peak radial strain", "-"),
    "activation_time": ("activation time", "ms"),
}


def has_aha(results: Results) -> bool:
    return all(f"aha_{n:02d}_activation_time" in results.summary for n in range(1, 18))


def aha_values(results: Results, quantity: str, beat: int = -1) -> np.ndarray:
    """The 17 values of one quantity (a key of QUANTITIES) in one beat (default: the last)."""
    return np.array([results.summary[f"aha_{n:02d}_{quantity}"][beat] for n in range(1, 18)],
                    dtype=float)


def segment_wedges() -> list[tuple[float, float, float, float]]:
    """(theta_start, theta_width [rad, polar axes: 0 to the right, counter-clockwise],
    inner radius, outer radius) of segments 1 ... 17."""
    wedges = []
    for inner in (3, 2):  # the basal ring (1-6), then the mid ring (7-12)
        for k in range(6):
            # Its k-th segment is centred 60 k degrees counter-clockwise from the top.
            centre = np.pi / 2 + np.radians(60 * k)
            wedges.append((centre - np.radians(30), np.radians(60), inner, inner + 1))
    for k in range(4):
        centre = np.pi / 2 + np.radians(90 * k)
        wedges.append((centre - np.radians(45), np.radians(90), 1, 2))
    wedges.append((0.0, 2 * np.pi, 0, 1))
    return wedges


def bullseye_axes(ax, values: np.ndarray, cmap: str = "RdBu_r", vmin=None, vmax=None,
                  label: str = "", fmt: str = "{:.3f}"):
    """Draw the bull's-eye of the 17 values on polar axes; NaN segments are grey."""
    finite = values[np.isfinite(values)]
    if vmin is None or vmax is None:
        if cmap == "RdBu_r" and finite.size:
            bound = max(np.abs(finite).max(), 1e-12)
            vmin, vmax = -bound, bound
        else:
            vmin = finite.min() if finite.size else 0.0
            vmax = finite.max() if finite.size and finite.max() > vmin else vmin + 1
    norm = Normalize(vmin=vmin, vmax=vmax)
    colour_map = matplotlib.colormaps[cmap]
    for n, (start, width, inner, outer) in enumerate(segment_wedges(), start=1):
        value = values[n - 1]
        colour = colour_map(norm(value)) if np.isfinite(value) else (0.8, 0.8, 0.8, 1.0)
        ax.bar(start + width / 2, outer - inner, width=width, bottom=inner, color=colour,
               edgecolor="black", linewidth=0.8)
        r = 0.0 if n == 17 else 0.5 * (inner + outer)
        ax.text(start + width / 2 if n != 17 else 0.0, r,
                f"{n}\n" + (fmt.format(value) if np.isfinite(value) else "–"),
                ha="center", va="center", fontsize=7)
    ax.set_ylim(0, 4)
    ax.set_axis_off()
    mappable = matplotlib.cm.ScalarMappable(norm=norm, cmap=colour_map)
    ax.figure.colorbar(mappable, ax=ax, shrink=0.7, label=label)


def make_bullseye_figure(results: Results, beat: int = -1) -> Figure:
    """The four bull's-eyes (peak circumferential, longitudinal, radial strain, activation
    time) of one beat."""
    figure = Figure(figsize=(14.0, 3.8), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(1, 4, subplot_kw={"projection": "polar"})
    beat_number = int(results.summary["beat"][beat]) if "beat" in results.summary else beat
    for ax, (quantity, (title, unit)) in zip(axes, QUANTITIES.items()):
        values = aha_values(results, quantity, beat)
        strain = quantity.startswith("peak")
        bullseye_axes(ax, values, cmap="RdBu_r" if strain else "viridis",
                      label=f"{title} [{unit}]", fmt="{:.3f}" if strain else "{:.1f}")
        ax.set_title(title, fontsize=10)
    figure.suptitle(f"AHA segments, beat {beat_number} (seen from the apex, anterior up, "
                    "septum left)", fontsize=10)
    return figure
