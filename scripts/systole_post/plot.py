"""Plot time-series columns of a results file against time into a PNG.

Uses matplotlib's Agg canvas directly (no pyplot, no display, no global backend
switch), so it works on headless machines and inside tests.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from systole_post.cavities import alias_columns, find_cavities
from systole_post.results import Results, read_results

#: Columns never plotted by default (the x axis and the step counter).
NOT_PLOTTED = ("time", "step")

#: Default panels that gather the columns of one quantity (circulation and heartbeat
#: files, see systole_post.cavities): title, name suffix. The first matching suffix wins;
#: the legend shows the names without it.
QUANTITY_PANELS = (("flow [mL/s]", "_mL_per_s"), ("pressure [mmHg]", "_mmHg"),
                   ("volume [mL]", "_mL"), ("phase [-]", "_phase"))
#: Columns kept out of the quantity panels (another scale): one panel each.
OWN_PANEL = ("total_blood_volume_mL", "cumulative_outflow_mL", "cumulative_inflow_mL")


def default_columns(results: Results) -> list[str]:
    """All time-series columns except ``time``, ``step`` and the heartbeat's unprefixed
    aliases of its first cavity (when its prefixed columns are there), in file order."""
    aliases = alias_columns(find_cavities(results.timeseries))
    return [name for name in results.timeseries
            if name not in NOT_PLOTTED and name not in aliases]


def default_panels(results: Results) -> list[tuple[str, list[str]]]:
    """The default panels, (title, columns), in the order of their first column: the
    columns of each quantity of QUANTITY_PANELS together where there are two or more,
    every other column alone, titled "name [unit]"."""
    groups: dict[str, list[str]] = {}
    for name in default_columns(results):
        title = f"{name} [{results.units.get(name) or '-'}]"
        if name not in OWN_PANEL:
            title = next((t for t, suffix in QUANTITY_PANELS if name.endswith(suffix)), title)
        groups.setdefault(title, []).append(name)
    return [(title if len(names) > 1 else f"{names[0]} [{results.units.get(names[0]) or '-'}]",
             names) for title, names in groups.items()]


def _legend(name: str) -> str:
    """``name`` without its quantity suffix (``lv_pressure_mmHg`` -> ``lv_pressure``)."""
    suffix = next((s for _, s in QUANTITY_PANELS if name.endswith(s)), "")
    return name[: len(name) - len(suffix)]


def make_figure(results: Results, columns: list[str] | None = None) -> Figure:
    """Build a figure of time-series columns against time.

    By default the panels of :func:`default_panels` (pressures, volumes, flows and phases
    of a circulation or heartbeat file together, with a legend); with ``columns``, one
    panel per column, titled "name [unit]". Columns holding only integers (phase, beat,
    iteration counts) are drawn as steps.

    Raises:
        ValueError: no ``time`` column, an unknown column, or nothing to plot.
    """
    if "time" not in results.timeseries:
        raise ValueError(f"{results.path}: no 'time' column to plot against")
    if columns is None:
        panels = default_panels(results)
    else:
        unknown = [name for name in columns if name not in results.timeseries]
        if unknown:
            raise ValueError(
                f"{results.path}: no time-series column {unknown}; "
                f"available: {sorted(results.timeseries)}"
            )
        panels = [(f"{name} [{results.units.get(name) or '-'}]", [name]) for name in columns]
    if not panels:
        raise ValueError(f"{results.path}: no columns to plot")

    time = results.timeseries["time"]
    figure = Figure(figsize=(8.0, 2.2 * len(panels) + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (title, names) in zip(axes, panels):
        for name in names:
            values = results.timeseries[name]
            integer_valued = values.size > 0 and np.all(np.mod(values, 1.0) == 0.0)
            ax.plot(time, values, drawstyle="steps-post" if integer_valued else "default",
                    label=_legend(name) if len(names) > 1 else name)
        ax.set_title(title)
        ax.grid(True, alpha=0.3)
        if len(names) > 1:
            ax.legend(loc="upper right", fontsize=7)
    axes[-1].set_xlabel(f"time [{results.units.get('time') or 'ms'}]")
    return figure


def plot_timeseries(
    results: Results | str | Path, png_path: str | Path, columns: list[str] | None = None
) -> Path:
    """Write a PNG of the time series against time (see :func:`make_figure`).

    Args:
        results: a :class:`Results` object or the path of a results file.
        png_path: output file.
        columns: columns to plot, one panel each; default all except ``time`` and
            ``step``, grouped by quantity (:func:`default_panels`).

    Returns:
        The path written.
    """
    if not isinstance(results, Results):
        results = read_results(results)
    png_path = Path(png_path)
    make_figure(results, columns).savefig(png_path, format="png", dpi=100)
    return png_path
