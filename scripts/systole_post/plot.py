"""Plot time-series columns of a results file against time into a PNG.

Uses matplotlib's Agg canvas directly (no pyplot, no display, no global backend
switch), so it works on headless machines and inside tests.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from systole_post.results import Results, read_results

#: Columns never plotted by default (the x axis and the step counter).
NOT_PLOTTED = ("time", "step")


def default_columns(results: Results) -> list[str]:
    """All time-series columns except ``time`` and ``step``, in file order."""
    return [name for name in results.timeseries if name not in NOT_PLOTTED]


def make_figure(results: Results, columns: list[str] | None = None) -> Figure:
    """Build a figure with one subplot per column against time, titled "name [unit]".

    Columns holding only integers (phase, beat, iteration counts) are drawn as steps.

    Raises:
        ValueError: no ``time`` column, an unknown column, or nothing to plot.
    """
    columns = default_columns(results) if columns is None else list(columns)
    if "time" not in results.timeseries:
        raise ValueError(f"{results.path}: no 'time' column to plot against")
    unknown = [name for name in columns if name not in results.timeseries]
    if unknown:
        raise ValueError(
            f"{results.path}: no time-series column {unknown}; "
            f"available: {sorted(results.timeseries)}"
        )
    if not columns:
        raise ValueError(f"{results.path}: no columns to plot")

    time = results.timeseries["time"]
    figure = Figure(figsize=(8.0, 2.2 * len(columns) + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(columns), 1, sharex=True, squeeze=False)[:, 0]
    for ax, name in zip(axes, columns):
        values = results.timeseries[name]
        integer_valued = values.size > 0 and np.all(np.mod(values, 1.0) == 0.0)
        ax.plot(time, values, drawstyle="steps-post" if integer_valued else "default")
        ax.set_title(f"{name} [{results.units.get(name) or '-'}]")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel(f"time [{results.units.get('time') or 'ms'}]")
    return figure


def plot_timeseries(
    results: Results | str | Path, png_path: str | Path, columns: list[str] | None = None
) -> Path:
    """Write a PNG with one subplot per time-series column against time.

    Args:
        results: a :class:`Results` object or the path of a results file.
        png_path: output file.
        columns: columns to plot; default all except ``time`` and ``step``.

    Returns:
        The path written.
    """
    if not isinstance(results, Results):
        results = read_results(results)
    png_path = Path(png_path)
    make_figure(results, columns).savefig(png_path, format="png", dpi=100)
    return png_path
