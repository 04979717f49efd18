#!/usr/bin/env python3
"""Draw the Purkinje tree and the 12-lead ECG of a results file into two PNGs.

    plot_purkinje_ecg.py RESULTS.h5 [-o PREFIX] [--title TEXT] [--end MS]

PREFIX_tree.png: the tree (/purkinje/nodes, /purkinje/edges) seen along three axes
(front: x-z, side: y-z, from the base: x-y), its segments coloured by activation time,
the Purkinje-muscle junctions as dots. PREFIX_ecg.png: the 12 leads (/timeseries/ecg_*)
on the usual 3 x 4 grid (I, aVR, V1, V4 / II, aVL, V2, V5 / III, aVF, V3, V6), one
scale for all, the QRS (/summary ecg_QRS_onset, ecg_QRS_duration) shaded. Either
picture is skipped (with a message) when its data are missing. Default PREFIX: the
results file's folder / purkinje. Prints the paths written.
"""

import argparse
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

GRID = [["I", "aVR", "V1", "V4"], ["II", "aVL", "V2", "V5"], ["III", "aVF", "V3", "V6"]]
VIEWS = [("front (x-z)", 0, 2), ("side (y-z)", 1, 2), ("from the base (x-y)", 0, 1)]


def read_tree(f):
    """Nodes (n x 3), activation times, junction flags and edges, or None."""
    if "purkinje" not in f:
        return None
    nodes = f["purkinje/nodes"]
    xyz = np.column_stack([nodes[c][:] for c in ("x", "y", "z")])
    edges = np.column_stack([f["purkinje/edges/parent"][:], f["purkinje/edges/child"][:]])
    return xyz, nodes["activation_time"][:], nodes["junction"][:] > 0.5, edges.astype(int)


def plot_tree(f, path: Path, title: str) -> bool:
    """Write the tree picture; False if the file has no tree."""
    tree = read_tree(f)
    if tree is None:
        return False
    xyz, time, junction, edges = tree
    norm = plt.Normalize(time.min(), time.max())
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.6), constrained_layout=True)
    for ax, (name, i, j) in zip(axes, VIEWS):
        segments = np.stack([xyz[edges[:, 0]][:, [i, j]], xyz[edges[:, 1]][:, [i, j]]], axis=1)
        lines = LineCollection(segments, cmap="viridis", norm=norm, linewidths=0.7)
        lines.set_array(0.5 * (time[edges[:, 0]] + time[edges[:, 1]]))
        ax.add_collection(lines)
        ax.scatter(xyz[junction, i], xyz[junction, j], s=3, c=time[junction], cmap="viridis",
                   norm=norm, edgecolors="none")
        ax.scatter(xyz[0, i], xyz[0, j], s=40, marker="*", c="red", zorder=3)
        ax.set_aspect("equal")
        ax.autoscale_view()
        ax.set_title(name)
        ax.set_xlabel("xyz"[i] + " [mm]")
        ax.set_ylabel("xyz"[j] + " [mm]")
    bar = fig.colorbar(lines, ax=axes, shrink=0.8)
    bar.set_label("activation time [ms]")
    fig.suptitle(f"{title}: {len(xyz)} nodes, {int(junction.sum())} junctions (dots), "
                 "His entry (star)")
    fig.savefig(path, dpi=72)  # about 150 kB for 5000 segments
    plt.close(fig)
    return True


def plot_ecg(f, path: Path, title: str, end: float | None) -> bool:
    """Write the 12-lead picture; False if the file has no ECG columns."""
    ts = f.get("timeseries")
    if ts is None or "ecg_I" not in ts:
        return False
    t = ts["time"][:]
    keep = t <= end if end is not None else np.ones_like(t, dtype=bool)
    leads = {name: ts[f"ecg_{name}"][:][keep] for row in GRID for name in row}
    t = t[keep]
    scale = max(np.max(np.abs(v)) for v in leads.values()) * 1.1 or 1.0
    summary = f.get("summary")
    qrs = None
    if summary is not None and "ecg_QRS_onset" in summary:
        onset, duration = summary["ecg_QRS_onset"][0], summary["ecg_QRS_duration"][0]
        if np.isfinite(onset) and np.isfinite(duration):
            qrs = (onset, onset + duration)
    fig, axes = plt.subplots(3, 4, figsize=(12, 6.4), sharex=True, sharey=True,
                             constrained_layout=True)
    for r, row in enumerate(GRID):
        for c, name in enumerate(row):
            ax = axes[r, c]
            if qrs:
                ax.axvspan(*qrs, color="0.9")
            ax.axhline(0, color="0.6", linewidth=0.5)
            ax.plot(t, leads[name], color="k", linewidth=0.9)
            ax.text(0.03, 0.9, name, transform=ax.transAxes, fontweight="bold")
            ax.set_ylim(-scale, scale)
            if r == 2:
                ax.set_xlabel("time [ms]")
            if c == 0:
                ax.set_ylabel("[mV]")
    label = f", QRS {qrs[1] - qrs[0]:.0f} ms (shaded)" if qrs else ""
    fig.suptitle(f"{title}: 12-lead pseudo-ECG{label}")
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return True


def main(argv=None) -> int:
    """Parse the command line, write the pictures, return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="results file (HDF5)")
    parser.add_argument("-o", "--output", help="prefix of the PNGs (default: "
                        "RESULTS' folder/purkinje)")
    parser.add_argument("--title", default=None, help="title (default: the results' folder)")
    parser.add_argument("--end", type=float, help="last time of the ECG picture [ms]")
    args = parser.parse_args(argv)
    if not args.results.is_file():
        print(f"error: no results file {args.results}", file=sys.stderr)
        return 1
    prefix = args.output or str(args.results.parent / "purkinje")
    title = args.title or args.results.parent.name
    written = 0
    with h5py.File(args.results, "r") as f:
        for kind, draw in (("tree", lambda p: plot_tree(f, p, title)),
                           ("ecg", lambda p: plot_ecg(f, p, title, args.end))):
            path = Path(f"{prefix}_{kind}.png")
            if draw(path):
                print(path)
                written += 1
            else:
                print(f"{args.results}: no {'Purkinje tree' if kind == 'tree' else 'ECG'}; "
                      f"{path.name} not written", file=sys.stderr)
    return 0 if written else 1


if __name__ == "__main__":
    sys.exit(main())
