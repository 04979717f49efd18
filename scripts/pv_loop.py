#!/usr/bin/env python3
"""Draw the pressure-volume loop and the cardiac-cycle traces of a Systole results file.

    pv_loop.py RESULTS.h5 [-o OUT_PREFIX]

Writes OUT_PREFIX_loop.png (cavity pressure against volume, one curve per beat, segments
coloured by phase) and OUT_PREFIX_traces.png (pressures, volume and flow against time,
phases shaded), prints the paths written, then the per-beat /summary table as aligned
text. Default OUT_PREFIX: "pv" next to the results file (pv_loop.png, pv_traces.png).

Time-series columns used: time [ms], pressure_mmHg, volume_mL (required); beat, phase,
flow [mL/s], aortic_pressure_mmHg (optional). The value of ``phase`` at a row is the
phase during the step that ends there, so the segment from row i-1 to row i takes the
colour of phase[i].
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

sys.path.insert(0, str(Path(__file__).resolve().parent))

from systole_post.results import Results, ResultsError, read_results  # noqa: E402

#: Phase codes of the time-series column ``phase`` (src/circulation/phase.h).
PHASES = {
    0: ("filling", "tab:blue"),
    1: ("isovolumetric contraction", "tab:orange"),
    2: ("ejection", "tab:red"),
    3: ("isovolumetric relaxation", "tab:green"),
}
#: Colour of rows whose phase code is unknown (or missing).
OTHER_COLOUR = "0.4"

REQUIRED = ("time", "pressure_mmHg", "volume_mL")


def _column(results: Results, name: str, default: float | None = None) -> np.ndarray:
    """A time-series column as float array, or ``default`` repeated if it is absent."""
    if name in results.timeseries:
        return np.asarray(results.timeseries[name], dtype=float)
    if default is None:
        raise ValueError(f"{results.path}: no time-series column '{name}'")
    return np.full(results.n_rows, default)


def check_columns(results: Results) -> None:
    """Raise ValueError naming the missing required columns, or when there are no rows."""
    missing = [name for name in REQUIRED if name not in results.timeseries]
    if missing:
        raise ValueError(
            f"{results.path}: no time-series column {missing}; "
            f"available: {sorted(results.timeseries)}"
        )
    if results.n_rows == 0:
        raise ValueError(f"{results.path}: the time series is empty")


def beat_rows(beat: np.ndarray) -> dict[int, np.ndarray]:
    """Row indices of each beat, each preceded by the last row of the previous beat.

    Steps never straddle a beat boundary, so the previous beat's last row is the state at
    the start of the beat: prepending it closes the curves at the boundaries.
    """
    rows: dict[int, np.ndarray] = {}
    for number in np.unique(beat.astype(int)):
        index = np.flatnonzero(beat.astype(int) == number)
        if index[0] > 0:
            index = np.concatenate(([index[0] - 1], index))
        rows[int(number)] = index
    return rows


def phase_colours(phase: np.ndarray) -> list[str]:
    """Colour of each row's phase code."""
    return [PHASES.get(int(code), (None, OTHER_COLOUR))[1] for code in phase]


def make_loop_figure(results: Results) -> Figure:
    """The PV loop: one curve per beat, segments coloured by phase, later beats darker."""
    check_columns(results)
    volume = _column(results, "volume_mL")
    pressure = _column(results, "pressure_mmHg")
    beat = _column(results, "beat", 0.0)
    colours = phase_colours(_column(results, "phase", -1.0))

    figure = Figure(figsize=(6.5, 5.5), layout="constrained")
    FigureCanvasAgg(figure)
    ax = figure.subplots()
    rows = beat_rows(beat)
    for n, (number, index) in enumerate(rows.items()):
        # Older beats fade out; the last one is drawn fully opaque.
        alpha = 1.0 if n == len(rows) - 1 else 0.3 + 0.5 * n / max(len(rows) - 1, 1)
        points = np.column_stack((volume[index], pressure[index]))
        segments = np.stack((points[:-1], points[1:]), axis=1)
        ax.add_collection(LineCollection(segments, colors=[colours[i] for i in index[1:]],
                                         linewidths=1.8, alpha=alpha, label=f"beat {number}"))
    ax.autoscale()
    ax.set_xlabel("volume [mL]")
    ax.set_ylabel("cavity pressure [mmHg]")
    numbers = list(rows)
    beats = (f"beat {numbers[0]}" if len(numbers) == 1 else
             f"beats {numbers[0]}-{numbers[-1]}, earlier beats lighter")
    ax.set_title(f"pressure-volume loop ({beats})")
    ax.grid(True, alpha=0.3)
    ax.legend(handles=[Line2D([], [], color=colour, label=name)
                       for name, colour in PHASES.values()], loc="best", fontsize=8)
    return figure


def _shade_phases(ax, time: np.ndarray, phase: np.ndarray) -> None:
    """Shade the time axis by phase: the interval (t[i-1], t[i]] takes phase[i]."""
    i = 1
    while i < len(time):
        code = int(phase[i])
        j = i
        while j + 1 < len(time) and int(phase[j + 1]) == code:
            j += 1
        if code in PHASES:
            ax.axvspan(time[i - 1], time[j], color=PHASES[code][1], alpha=0.08, lw=0)
        i = j + 1


def make_traces_figure(results: Results) -> Figure:
    """Pressures, volume and flow against time, with the phases shaded."""
    check_columns(results)
    time = _column(results, "time")
    phase = _column(results, "phase", -1.0)
    panels = [("pressure [mmHg]", [("pressure_mmHg", "cavity"),
                                   ("aortic_pressure_mmHg", "aortic root")]),
              ("volume [mL]", [("volume_mL", "cavity")]),
              ("flow [mL/s]", [("flow", "outflow - inflow")])]
    panels = [(label, [(name, text) for name, text in curves if name in results.timeseries])
              for label, curves in panels]
    panels = [(label, curves) for label, curves in panels if curves]

    figure = Figure(figsize=(8.0, 2.4 * len(panels) + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (label, curves) in zip(axes, panels):
        _shade_phases(ax, time, phase)
        for name, text in curves:
            ax.plot(time, _column(results, name), label=text, lw=1.2)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        if len(curves) > 1:
            ax.legend(loc="upper right", fontsize=8)
    axes[0].set_title("cardiac cycle (shading: " +
                      ", ".join(f"{name}" for name, _ in PHASES.values()) + ")", fontsize=9)
    axes[-1].set_xlabel(f"time [{results.units.get('time') or 'ms'}]")
    return figure


def _format_value(value: float) -> str:
    """Integers without decimals, NaN as "-", others with 5 significant digits."""
    if isinstance(value, (float, np.floating)) and math.isnan(value):
        return "-"
    if float(value).is_integer() and abs(value) < 1e9:
        return str(int(value))
    return f"{value:.5g}"


def format_summary(results: Results) -> str:
    """The /summary table as aligned text, one row per beat, headed "name [unit]".

    Columns in file order, except that ``beat`` comes first. Returns a one-line note if
    the file has no summary.
    """
    if not results.summary:
        return f"{results.path}: no /summary table"
    names = sorted(results.summary, key=lambda name: name != "beat")  # stable
    headers = [f"{name} [{results.summary_units.get(name) or '-'}]" for name in names]
    n_rows = len(next(iter(results.summary.values())))
    cells = [[_format_value(results.summary[name][row]) for name in names]
             for row in range(n_rows)]
    widths = [max([len(header)] + [len(row[j]) for row in cells])
              for j, header in enumerate(headers)]
    lines = ["  ".join(header.rjust(width) for header, width in zip(headers, widths))]
    lines += ["  ".join(cell.rjust(width) for cell, width in zip(row, widths)) for row in cells]
    return "\n".join(lines)


def write_pv_plots(results: Results | str | Path, prefix: str | Path) -> list[Path]:
    """Write PREFIX_loop.png and PREFIX_traces.png; returns the paths written."""
    if not isinstance(results, Results):
        results = read_results(results)
    prefix = Path(prefix)
    written = []
    for suffix, make in (("loop", make_loop_figure), ("traces", make_traces_figure)):
        path = prefix.with_name(f"{prefix.name}_{suffix}.png")
        make(results).savefig(path, format="png", dpi=100)
        written.append(path)
    return written


def main(argv=None) -> int:
    """Parse the command line, write the plots, print the summary; return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="results file (HDF5)")
    parser.add_argument("-o", "--output", type=Path, metavar="OUT_PREFIX",
                        help="prefix of the PNGs (default: 'pv' next to RESULTS)")
    args = parser.parse_args(argv)
    prefix = args.output or args.results.parent / "pv"
    try:
        results = read_results(args.results)
        written = write_pv_plots(results, prefix)
    except (ResultsError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    for path in written:
        print(path)
    print(format_summary(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
