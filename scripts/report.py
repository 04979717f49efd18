#!/usr/bin/env python3
"""One self-contained HTML report of a run: results/<run>/report.html.

    report.py RESULTS.h5 [-o REPORT.html]

The page holds every picture as an embedded base64 PNG and needs no network: provenance
(code version, ranks, wall time, peak memory), the pressure-volume loop(s) and traces of a
heartbeat or circulation run, the global indices of the "ventricle function" postprocessor,
the "clinical kinematics" (strains, twist and displacements referred to end-diastole) with
each beat's peaks against normal adult ranges, the activation map, the 12-lead pseudo-ECG
on the usual 3 x 4 grid, the AHA bull's-eye plots of peak strain and activation time, the
beat table, the cost statistics and the parameters used. Sections whose data the run lacks are left out. Prints the report's path.
"""

from __future__ import annotations

import argparse
import base64
import html
import io
import sys
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from pv_loop import (blood_volume_note, format_summary, make_loop_figure,
                     make_traces_figure)
from systole_post.bullseye import has_aha, make_bullseye_figure
from systole_post.results import Results, read_results

INDICES = [("long_axis_shortening", "long-axis shortening [-]"),
           ("wall_thickening", "wall thickening [-]"),
           ("torsion", "torsion (apex to base) [deg]"),
           ("ejection_fraction", "ejection fraction so far [-]")]

#: The peaks per beat of the "clinical kinematics" postprocessor (/summary) against normal
#: adult ranges (echo and MRI, referred to end-diastole; shared/reference/physiology.md,
#: docs/architecture.md "Clinical kinematics"): column, label, factor to the unit shown, unit,
#: lower and upper bound of the range (None: open), what is normal.
CLINICAL = [
    ("peak_global_longitudinal_strain", "global longitudinal strain (GLS)", 100, "%",
     -24, -16,
     "about -20 %, abnormal below 16 % in magnitude (Yingchoncharoen 2013: -19.7 %)"),
    ("peak_global_circumferential_strain", "global circumferential strain (GCS)", 100, "%",
     -30, -16, "Yingchoncharoen 2013: -23.3 %"),
    ("peak_global_radial_strain", "global radial strain (GRS)", 100, "%",
     25, 60, "Yingchoncharoen 2013: +47.3 %"),
    ("peak_endocardial_longitudinal_strain", "endocardial longitudinal strain", 100, "%",
     None, None, ""),
    ("peak_endocardial_circumferential_strain", "endocardial circumferential strain", 100,
     "%", None, None, ""),
    ("peak_endocardial_radial_strain", "endocardial radial strain", 100, "%",
     None, None, ""),
    ("peak_twist", "twist (apex minus base)", 1, "deg", 5, 25, "about 10-20 deg"),
    ("peak_torsion_per_length", "torsion (twist per ED length)", 1, "deg/mm", None, None, ""),
    ("peak_av_plane_displacement", "AV-plane displacement", 1, "mm", 8, 18,
     "about 12-16 mm, abnormal below about 10 mm"),
    ("peak_apex_displacement", "apex displacement", 1, "mm", None, 5, "a few mm"),
    ("peak_wall_thickening_ed", "wall thickening", 100, "%", 25, 60, "about 30-60 %"),
]

#: The /timeseries of "clinical kinematics" drawn per panel: (columns, factor, title).
CLINICAL_TRACES = [
    (("global_longitudinal_strain", "global_circumferential_strain", "global_radial_strain"),
     100, "global strains from ED [%]"),
    (("twist",), 1, "twist [deg]"),
    (("av_plane_displacement", "apex_displacement"), 1, "AV-plane and apex displacement [mm]"),
    (("wall_thickening_ed",), 100, "wall thickening from ED [%]"),
]

STYLE = """
body { font-family: sans-serif; margin: 2em; max-width: 1400px; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; font-size: 0.85em; }
td, th { border: 1px solid #ccc; padding: 2px 8px; text-align: right; }
th { background: #f0f0f0; } td:first-child, th:first-child { text-align: left; }
td.out { background: #f8d0d0; } td.in { background: #d8f0d8; }
img { max-width: 100%; display: block; margin: 0.5em 0; }
pre { background: #f7f7f7; padding: 0.8em; font-size: 0.8em; overflow-x: auto; }
"""

#: Marks every picture that decoded (a headless browser's --dump-dom shows it).
SCRIPT = """
window.addEventListener('load', function () {
  var images = document.getElementsByTagName('img'), ok = 0;
  for (var i = 0; i < images.length; ++i)
    if (images[i].complete && images[i].naturalWidth > 0) {
      images[i].setAttribute('data-decoded', images[i].naturalWidth + 'x' +
                             images[i].naturalHeight);
      ++ok;
    }
  document.body.setAttribute('data-pictures', ok + '/' + images.length);
});
"""


def png(figure: Figure) -> str:
    """The figure as an <img> with an embedded base64 PNG."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=90)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return f'<img alt="figure" src="data:image/png;base64,{data}">'


def indices_figure(results: Results) -> Figure | None:
    ts = results.timeseries
    present = [(k, label) for k, label in INDICES if k in ts]
    if not present:
        return None
    figure = Figure(figsize=(12.0, 2.8), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(1, len(present))
    for ax, (key, label) in zip(np.atleast_1d(axes), present):
        ax.plot(ts["time"], ts[key], color="tab:blue")
        ax.set_xlabel("time [ms]")
        ax.set_title(label, fontsize=9)
        ax.grid(True, alpha=0.3)
    return figure


def normal_range(low: float | None, high: float | None, unit: str) -> str:
    if low is None and high is None:
        return ""
    if low is None:
        return f"< {high:g} {unit}"
    if high is None:
        return f"> {low:g} {unit}"
    return f"{low:+g} … {high:+g} {unit}" if low < 0 else f"{low:g} … {high:g} {unit}"


def in_range(value: float, low: float | None, high: float | None) -> bool | None:
    """Whether value lies in [low, high] (None: no range, or not a number)."""
    if (low is None and high is None) or not np.isfinite(value):
        return None
    return (low is None or value >= low) and (high is None or value <= high)


def clinical_rows(results: Results) -> list[tuple[str, list[float], str, list, str]]:
    """(label with unit, the values per beat in that unit, the normal range, whether each
    value is in it (None: no range), what is normal) of the CLINICAL columns the run has."""
    rows = []
    for column, label, factor, unit, low, high, normal in CLINICAL:
        if column not in results.summary:
            continue
        values = [factor * float(v) for v in results.summary[column]]
        rows.append((f"{label} [{unit}]", values, normal_range(low, high, unit),
                     [in_range(v, low, high) for v in values], normal))
    return rows


def clinical_table(results: Results) -> str:
    """The peaks per beat against the normal ranges; empty without the columns."""
    rows = clinical_rows(results)
    if not rows:
        return ""
    beats = len(rows[0][1])
    head = ("<tr><th>peak from end-diastole</th>" +
            "".join(f"<th>beat {b}</th>" for b in range(beats)) +
            "<th>normal range</th><th>normal</th></tr>")
    body = ""
    for label, values, band, inside, normal in rows:
        cells = "".join(
            f'<td class="{"" if ok is None else ("in" if ok else "out")}">{v:.3g}</td>'
            for v, ok in zip(values, inside))
        body += (f"<tr><td>{html.escape(label)}</td>{cells}<td>{html.escape(band)}</td>"
                 f"<td>{html.escape(normal)}</td></tr>")
    return "<table>" + head + body + "</table>"


def clinical_figure(results: Results) -> Figure | None:
    ts = results.timeseries
    panels = [([k for k in keys if k in ts], factor, title)
              for keys, factor, title in CLINICAL_TRACES if any(k in ts for k in keys)]
    if not panels:
        return None
    figure = Figure(figsize=(12.0, 2.8), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(1, len(panels))
    for ax, (keys, factor, title) in zip(np.atleast_1d(axes), panels):
        for key in keys:
            ax.plot(ts["time"], factor * np.asarray(ts[key]), label=key.replace("_", " "))
        if len(keys) > 1:
            ax.legend(fontsize=7)
        ax.set_xlabel("time [ms]")
        ax.set_title(title, fontsize=9)
        ax.grid(True, alpha=0.3)
    return figure


#: The 12 leads as printed on an ECG sheet: rows of (limb, augmented, precordial,
#: precordial) leads.
ECG_GRID = [["I", "aVR", "V1", "V4"],
            ["II", "aVL", "V2", "V5"],
            ["III", "aVF", "V3", "V6"]]


def ecg_figure(results: Results) -> Figure | None:
    """The 12 leads /timeseries/ecg_<lead> [mV] on the usual 3 x 4 grid (one scale for
    all), or None when the run has no ECG."""
    ts = results.timeseries
    if any(f"ecg_{lead}" not in ts for row in ECG_GRID for lead in row):
        return None
    figure = Figure(figsize=(12.0, 6.0), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(3, 4, sharex=True, sharey=True)
    for row, names in zip(axes, ECG_GRID):
        for ax, lead in zip(row, names):
            ax.plot(ts["time"], ts[f"ecg_{lead}"], color="black", linewidth=1.0)
            ax.axhline(0.0, color="tab:red", linewidth=0.5, alpha=0.5)
            ax.set_title(lead, fontsize=10, loc="left")
            ax.grid(True, alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time [ms]")
    for ax in axes[:, 0]:
        ax.set_ylabel("mV")
    return figure


def has_activation_field(results: Results) -> bool:
    if not results.field_steps:
        return False
    import h5py

    with h5py.File(results.path, "r") as f:
        last = f"fields/step_{results.field_steps[-1]:06d}"
        return "activation_time" in f[last]


def provenance_table(results: Results) -> str:
    stats = results.statistics
    rows = [("results file", str(results.path)),
            ("code version", results.code_version or "?"),
            ("MPI ranks", str(results.n_ranks))]
    if "wall_time" in stats:
        rows.append(("wall time", f"{stats['wall_time']:.1f} s"))
    if "peak_memory_per_rank" in stats:
        rows.append(("peak memory", f"{stats['peak_memory_per_rank']:.0f} MiB per rank"))
    for key in ("discretization", "linear_solver"):
        if key in results.statistics_text:
            rows.append((key.replace("_", " "), results.statistics_text[key]))
    for key in ("n_cells", "n_dofs"):
        if key in stats:
            rows.append((key.replace("n_", "").replace("dofs", "DOFs"), f"{stats[key]:.0f}"))
    return "<table>" + "".join(f"<tr><td>{html.escape(a)}</td><td>{html.escape(b)}</td></tr>"
                               for a, b in rows) + "</table>"


def statistics_table(results: Results) -> str:
    stats = results.statistics
    if not stats:
        return ""
    body = "".join(f"<tr><td>{html.escape(k)}</td><td>{v:.6g}</td></tr>"
                   for k, v in stats.items())
    return "<table><tr><th>statistic</th><th>value</th></tr>" + body + "</table>"


def beat_table(results: Results) -> str:
    summary = results.summary
    if not summary:
        return ""
    names = [k for k in summary if not k.startswith("aha_")]
    beats = len(next(iter(summary.values())))
    head = "<tr><th>column</th>" + "".join(f"<th>beat {b}</th>" for b in range(beats))
    rows = "".join(
        f"<tr><td>{html.escape(k)}</td>" +
        "".join(f"<td>{summary[k][b]:.4g}</td>" for b in range(beats)) + "</tr>"
        for k in names)
    return "<table>" + head + "</tr>" + rows + "</table>"


#: The picture scripts/run renders with ParaView (scripts/paraview_load.py) beside results.h5.
PARAVIEW_PICTURE = "paraview.png"


def paraview_section(path: str | Path) -> list[str]:
    """The ParaView picture beside the results file, embedded, if there is one."""
    picture = Path(path).resolve().parent / PARAVIEW_PICTURE
    if not picture.is_file():
        return []
    data = base64.b64encode(picture.read_bytes()).decode("ascii")
    return ["<h2>ParaView</h2>",
            "<p>The last field step in ParaView (scripts/paraview_load.py: warped by the "
            "displacement; open fields.xdmf with that script for every step and field).</p>",
            f'<img alt="ParaView" src="data:image/png;base64,{data}">']


def build_report(path: str | Path) -> str:
    """The HTML text of the report of one results file."""
    results = read_results(path)
    run = Path(path).resolve().parent.name
    parts = [f"<h1>Systole run {html.escape(run)}</h1>", "<h2>Provenance</h2>",
             provenance_table(results)]
    ts = results.timeseries
    if any(k.endswith("volume_mL") for k in ts) and any("pressure" in k for k in ts):
        try:
            parts += ["<h2>Pressure-volume loop</h2>", png(make_loop_figure(results)),
                      "<h2>Traces</h2>", png(make_traces_figure(results))]
        except (KeyError, ValueError):
            pass
    figure = indices_figure(results)
    if figure is not None:
        parts += ["<h2>Global indices</h2>", png(figure)]
    table = clinical_table(results)
    if table:
        parts += ["<h2>Clinical kinematics</h2>",
                  "<p>Peaks of each beat referred to its end-diastole (Lagrangian strains "
                  "in the end-diastolic cardiac frame; docs/architecture.md, \"Clinical "
                  "kinematics\"), against normal adult ranges: green inside, red outside.</p>",
                  table]
        figure = clinical_figure(results)
        if figure is not None:
            parts.append(png(figure))
    if has_activation_field(results):
        from systole_post.activation import make_activation_figure

        parts += ["<h2>Activation map</h2>", png(make_activation_figure(path, "x", 0.0))]
    figure = ecg_figure(results)
    if figure is not None:
        parts += ["<h2>ECG</h2>",
                  "<p>The pseudo-ECG (infinite homogeneous volume conductor) at the "
                  "electrodes of Electrophysiology / ECG electrodes: limb leads, augmented "
                  "limb leads and V1-V6 against Wilson's central terminal; QRS, QT and R "
                  "amplitudes per beat in the beat table (docs/architecture.md, ECG).</p>",
                  png(figure)]
    if has_aha(results):
        parts += ["<h2>AHA segments</h2>", png(make_bullseye_figure(results))]
    parts += paraview_section(path)
    if results.summary:
        parts += ["<h2>Beats</h2>", beat_table(results)]
        note = blood_volume_note(results)
        if note:
            parts.append(f"<p>{html.escape(note[0].upper() + note[1:])}.</p>")
        try:
            parts.append("<pre>" + html.escape(format_summary(results)) + "</pre>")
        except (KeyError, ValueError):
            pass
    if results.statistics:
        parts += ["<h2>Cost</h2>", statistics_table(results)]
    parts += ["<h2>Parameters</h2>", "<pre>" + html.escape(results.parameters) + "</pre>"]
    return ("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">"
            f"<title>Systole: {html.escape(run)}</title><style>{STYLE}</style>"
            f"<script>{SCRIPT}</script></head><body>\n" + "\n".join(parts) +
            "\n</body></html>\n")


def write_report(path: str | Path, output: str | Path | None = None) -> Path:
    output = Path(output) if output else Path(path).resolve().parent / "report.html"
    output.write_text(build_report(path), encoding="utf-8")
    return output


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="results.h5 of a run")
    parser.add_argument("-o", "--output", help="report path (default: report.html beside it)")
    args = parser.parse_args(argv)
    print(write_report(args.results, args.output))
    return 0


if __name__ == "__main__":
    sys.exit(main())
