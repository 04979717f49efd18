#!/usr/bin/env python3
"""Draw the pressure-volume loops and the cardiac-cycle traces of a Systole results file.

    pv_loop.py RESULTS.h5 [-o OUT_PREFIX] [--full] [--report REPORT.html]

Writes OUT_PREFIX_loop.png (one panel per cavity: its pressure against its volume, one
curve per beat, segments coloured by the cavity's phase) and OUT_PREFIX_traces.png (the
cavity and vessel pressures of the left and the right heart, the cavity volumes and the
valve flows against time, the first ventricle's phases shaded), prints the paths written,
then the per-beat /summary in at most 100 columns: a table per ventricle (split into column
groups), the pressures of the last beat, what the blood-volume drift means, and where the
other columns are (--full prints them all, wide). Default OUT_PREFIX: "pv" next to the
results file (pv_loop.png, pv_traces.png).

Reads the files of Problem = heartbeat and Problem = circulation: a cavity is every prefix
c with time-series columns c_pressure_mmHg and c_volume_mL (optional c_phase,
c_mechanics_volume_mL), see systole_post.cavities. An old-style heartbeat file with only
pressure_mmHg, volume_mL (optional phase, flow, aortic_pressure_mmHg) is one cavity. A
phase column holds the phase at the end of each row's step, so the segment from row i-1 to
row i takes the colour of phase[i].
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

from systole_post.cavities import (PRESSURE_STATISTICS, Cavity, find_cavities,
                                   flow_traces, pressure_traces, summary_groups)
from systole_post.results import Results, ResultsError, read_results

#: Phase codes of the phase columns (src/circulation/phase.h).
PHASES = {
    0: ("filling", "tab:blue"),
    1: ("isovolumetric contraction", "tab:orange"),
    2: ("ejection", "tab:red"),
    3: ("isovolumetric relaxation", "tab:green"),
}
#: Colour of rows whose phase code is unknown (or missing).
OTHER_COLOUR = "0.4"
#: Colour of the loop of a cavity without a phase column (the atria of the closed loop).
NO_PHASE_COLOUR = "tab:purple"


def _column(results: Results, name: str, default: float | None = None) -> np.ndarray:
    """A time-series column as float array, or ``default`` repeated if it is absent."""
    if name in results.timeseries:
        return np.asarray(results.timeseries[name], dtype=float)
    if default is None:
        raise ValueError(f"{results.path}: no time-series column '{name}'")
    return np.full(results.n_rows, default)


def cavities_of(results: Results) -> list[Cavity]:
    """The cavities of the file; raise ValueError when there is none, no time column or no
    rows."""
    cavities = find_cavities(results.timeseries)
    if not cavities or "time" not in results.timeseries:
        raise ValueError(
            f"{results.path}: no time-series column 'time' and no cavity (columns "
            "c_pressure_mmHg and c_volume_mL, or pressure_mmHg and volume_mL); "
            f"available: {sorted(results.timeseries)}"
        )
    if results.n_rows == 0:
        raise ValueError(f"{results.path}: the time series is empty")
    return cavities


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


def _draw_loop(ax, results: Results, cavity: Cavity, rows: dict[int, np.ndarray]) -> None:
    """The loop of one cavity: one curve per beat, later beats darker."""
    volume = _column(results, cavity.volume)
    pressure = _column(results, cavity.pressure)
    if cavity.phase:
        colours = phase_colours(_column(results, cavity.phase))
    else:
        colours = [NO_PHASE_COLOUR] * results.n_rows
    for n, (number, index) in enumerate(rows.items()):
        # Older beats fade out; the last one is drawn fully opaque.
        alpha = 1.0 if n == len(rows) - 1 else 0.3 + 0.5 * n / max(len(rows) - 1, 1)
        points = np.column_stack((volume[index], pressure[index]))
        segments = np.stack((points[:-1], points[1:]), axis=1)
        ax.add_collection(LineCollection(segments, colors=[colours[i] for i in index[1:]],
                                         linewidths=1.8, alpha=alpha, label=f"beat {number}"))
    ax.autoscale()
    ax.set_xlabel(f"{cavity.label} volume [mL]")
    ax.set_ylabel(f"{cavity.label} pressure [mmHg]")
    numbers = list(rows)
    beats = (f"beat {numbers[0]}" if len(numbers) == 1 else
             f"beats {numbers[0]}-{numbers[-1]}, earlier beats lighter")
    ax.set_title(f"{cavity.label} pressure-volume loop ({beats})", fontsize=10)
    ax.grid(True, alpha=0.3)
    if cavity.phase:
        ax.legend(handles=[Line2D([], [], color=colour, label=name)
                           for name, colour in PHASES.values()], loc="best", fontsize=8)


def make_loop_figure(results: Results) -> Figure:
    """The PV loops: one panel per cavity (ventricles first), two panels a row."""
    cavities = cavities_of(results)
    rows = beat_rows(_column(results, "beat", 0.0))
    n_columns = min(len(cavities), 2)
    n_rows = math.ceil(len(cavities) / n_columns)
    figure = Figure(figsize=(6.0 * n_columns, 5.0 * n_rows), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(n_rows, n_columns, squeeze=False).ravel()
    for ax, cavity in zip(axes, cavities):
        _draw_loop(ax, results, cavity, rows)
    for ax in axes[len(cavities):]:
        ax.remove()
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


def trace_panels(results: Results, cavities: list[Cavity]
                 ) -> list[tuple[str, list[tuple[str, str, str]]]]:
    """The panels of the traces figure: (y label, [(column, legend, line style)]), empty
    panels left out. Pressures of the left and the right heart apart when the file has
    both (closed loop), one pressure panel otherwise."""
    columns = results.timeseries
    left, right = pressure_traces(columns, cavities)
    volumes = []
    for cavity in cavities:
        volumes.append((cavity.volume, cavity.label, "-"))
        if cavity.mechanics_volume:
            volumes.append((cavity.mechanics_volume, f"{cavity.label} (3D mesh)", "--"))
    flows = [(column, legend, "-") for column, legend in flow_traces(columns)]
    panels = [("left heart pressure [mmHg]" if right else "pressure [mmHg]",
               [(column, legend, "-") for column, legend in left]),
              ("right heart pressure [mmHg]", [(column, legend, "-") for column, legend in right]),
              ("volume [mL]", volumes),
              ("flow [mL/s]", flows)]
    return [(label, curves) for label, curves in panels if curves]


def make_traces_figure(results: Results) -> Figure:
    """Pressures, volumes and flows against time, the first ventricle's phases shaded."""
    cavities = cavities_of(results)
    time = _column(results, "time")
    shading = cavities[0] if cavities[0].phase else None
    phase = _column(results, shading.phase) if shading else np.full(results.n_rows, -1.0)
    panels = trace_panels(results, cavities)

    figure = Figure(figsize=(8.0, 2.4 * len(panels) + 0.6), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    # One colour per cavity or vessel in every panel; a 3D-mesh volume takes the colour of
    # its cavity.
    colours: dict[str, str] = {}
    for ax, (label, curves) in zip(axes, panels):
        _shade_phases(ax, time, phase)
        for column, legend, style in curves:
            colour = colours.setdefault(legend.removesuffix(" (3D mesh)"), f"C{len(colours) % 10}")
            ax.plot(time, _column(results, column), style, label=legend, lw=1.2, color=colour)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        if len(curves) > 1:
            ax.legend(loc="upper right", fontsize=8)
    whose = f"{shading.label} " if shading and shading.name else ""
    axes[0].set_title(f"cardiac cycle (shading: {whose}" +
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


def _aligned(headers: list[str], rows: list[list[str]], left_first: bool = False
             ) -> list[str]:
    """Lines of a table with right-aligned columns (the first one left-aligned if
    ``left_first``)."""
    widths = [max([len(header)] + [len(row[j]) for row in rows])
              for j, header in enumerate(headers)]

    def cell(text: str, j: int) -> str:
        return text.ljust(widths[j]) if left_first and j == 0 else text.rjust(widths[j])

    return ["  ".join(cell(text, j) for j, text in enumerate(line)) for line in [headers] + rows]



def _beats_and_groups(summary: dict):
    """The beat numbers of the /summary rows and the columns grouped per ventricle."""
    n_rows = len(next(iter(summary.values())))
    return summary.get("beat", np.arange(n_rows)), summary_groups(summary)

def format_summary(results: Results) -> str:
    """The /summary as aligned text.

    One table per ventricle (rows: beats; columns: EDV, ESV, SV, EF, EDP, peak pressure,
    stroke work, dp/dt, the phase durations, headed "name [unit]"), then the max/min/mean
    of every pressure in the last beat (one row per pressure), then the other columns (one
    row per beat, file order). ``beat`` heads every per-beat table. Returns a one-line
    note if the file has no summary.
    """
    summary = results.summary
    if not summary:
        return f"{results.path}: no /summary table"
    beats, groups = _beats_and_groups(summary)
    n_rows = len(beats)

    def per_beat(title: str, columns: list[tuple[str, str, str | None]]) -> list[str]:
        headers = ["beat [-]"] + [f"{heading} [{unit or summary_units.get(column) or '-'}]"
                                  for column, heading, unit in columns]
        cells = [[_format_value(beats[row])] +
                 [_format_value(summary[column][row]) for column, _, _ in columns]
                 for row in range(n_rows)]
        return [title] + _aligned(headers, cells)

    summary_units = results.summary_units
    lines = []
    for name, columns in groups.ventricles.items():
        label = name.upper() if name else "cavity"
        lines += per_beat(f"{label}, per beat:", columns)
    if groups.pressures:
        cells = [[name] + [_format_value(summary[f"{name}_{s}_mmHg"][-1])
                           for s in PRESSURE_STATISTICS] for name in groups.pressures]
        lines += [f"pressures [mmHg] in beat {_format_value(beats[-1])}:"]
        lines += _aligned(["pressure"] + list(PRESSURE_STATISTICS), cells, left_first=True)
    if groups.others:
        lines += per_beat("per beat:", [(column, column, None) for column in groups.others])
    return "\n".join(lines)


#: Width of the terminal summary (scripts/run's last screen), in characters.
TERMINAL_WIDTH = 100


def _split_table(title: str, headers: list[str], cells: list[list[str]], width: int
                 ) -> list[str]:
    """An aligned table split into column groups that fit ``width`` characters, the first
    column (the beat) repeated in each; titles after the first say "(continued)"."""
    widths = [max([len(h)] + [len(row[j]) for row in cells]) for j, h in enumerate(headers)]
    groups, current, used = [], [], widths[0]
    for j in range(1, len(headers)):
        if current and used + 2 + widths[j] > width:
            groups.append(current)
            current, used = [], widths[0]
        current.append(j)
        used += 2 + widths[j]
    groups.append(current)
    lines = []
    for k, group in enumerate(groups):
        columns = [0] + group
        lines.append(title if k == 0 else title.rstrip(":") + " (continued):")
        lines += _aligned([headers[j] for j in columns],
                          [[row[j] for j in columns] for row in cells])
    return lines


def _wrap(text: str, width: int, indent: str = "  ") -> list[str]:
    import textwrap

    return textwrap.wrap(text, width, subsequent_indent=indent, break_on_hyphens=False)


def blood_volume_note(results: Results) -> str | None:
    """What total_blood_volume_drift means for this run: a conservation check of the closed
    loop, or the change of the blood in an open (Windkessel) model, not an error."""
    summary = results.summary
    if "total_blood_volume_drift" not in summary:
        return None
    drift = float(np.nanmax(summary["total_blood_volume_drift"]))
    closed = len(find_cavities(results.timeseries)) > 1
    if closed:
        return (f"total blood volume: largest relative change within a beat {drift:.2g} "
                "(the closed loop conserves it: this is a conservation check)")
    return (f"total blood volume (ventricle + arteries) changes by up to {100 * drift:.3g} % "
            "within a beat: the Windkessel is an open system (blood comes in from the "
            "atrium, leaves through the peripheral resistance), not a conservation error")


def format_terminal_summary(results: Results, width: int = TERMINAL_WIDTH,
                            report: str | Path | None = None) -> str:
    """The short summary for the terminal, no line longer than ``width``: the table per
    ventricle (split into column groups), the pressures of the last beat, the meaning of the
    blood-volume drift, and where the other per-beat columns are (the report and /summary)."""
    summary = results.summary
    if not summary:
        return f"{results.path}: no /summary table"
    beats, groups = _beats_and_groups(summary)
    n_rows = len(beats)
    units = results.summary_units
    lines = []
    for name, columns in groups.ventricles.items():
        label = name.upper() if name else "cavity"
        headers = ["beat [-]"] + [f"{heading} [{unit or units.get(column) or '-'}]"
                                  for column, heading, unit in columns]
        cells = [[_format_value(beats[row])] +
                 [_format_value(summary[column][row]) for column, _, _ in columns]
                 for row in range(n_rows)]
        lines += _split_table(f"{label}, per beat:", headers, cells, width)
    if groups.pressures:
        cells = [[name] + [_format_value(summary[f"{name}_{s}_mmHg"][-1])
                           for s in PRESSURE_STATISTICS] for name in groups.pressures]
        lines += [f"pressures [mmHg] in beat {_format_value(beats[-1])}:"]
        lines += _aligned(["pressure"] + list(PRESSURE_STATISTICS), cells, left_first=True)
    note = blood_volume_note(results)
    if note:
        lines += _wrap(note, width)
    if groups.others:
        n = len(groups.others)
        aha = sum(1 for c in groups.others if c.startswith("aha_"))
        kinds = (f"{aha} of the AHA segments, " if aha else "") + \
            "periodicity, cost, postprocessors"
        where = f"the report ({report})" if report else "the report (scripts/report.py)"
        lines += _wrap(f"{n} more per-beat column{'s' if n > 1 else ''} ({kinds}): in "
                       f"{where} and in /summary of {results.path}", width)
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
    parser.add_argument("--full", action="store_true",
                        help="print every /summary column (wide tables) instead of the "
                        f"summary that fits {TERMINAL_WIDTH} columns")
    parser.add_argument("--report", help="where the report is (named in the summary)")
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
    if args.full:
        print(format_summary(results))
    else:
        print(format_terminal_summary(results, report=args.report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
