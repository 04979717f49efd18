#!/usr/bin/env python3
"""The mean activation dipole of an electrophysiology run, whole, per height band and per time.

    activation_dipole.py RESULTS.h5 [--centre X Y Z] [--right-angle DEG] [--bands N] [--bin MS]

For an upstroke at the activation time tau(x) and a plateau through the QRS, the QRS integral
of the pseudo-ECG is the field of a dipole proportional to the integral of sigma grad(tau): the
mean direction of propagation. This script takes sigma isotropic (the fibres are not in the
results file) and sums, over the EP cells of /mesh/cells, the cell's volume (its nodes' convex
hull) times its gradient of tau (least squares over its nodes, so any node order works) from
the last /fields step with activation_time. It prints the sum [mm^2 ms] in the model's frame
and in the body frame of scripts/ecg_electrodes.py (x the patient's left, y anterior, z
superior; --centre and --right-angle as given there) with its frontal angle (0 deg left, +90
inferior, the QRS axis's convention); then the same for N bands of the cell centres' height
(model z) and for bins of the cells' mean activation time. Exit status 1 if the file has no
activation map.
"""

import argparse
import sys

import h5py
import numpy as np
from scipy.spatial import ConvexHull

from ecg_electrodes import model_frame


def cell_dipoles(nodes: np.ndarray, cells: np.ndarray, tau: np.ndarray):
    """Per cell: centre, mean activation time, volume and gradient of tau."""
    points = nodes[cells]
    times = tau[cells]
    centres = points.mean(axis=1)
    design = np.concatenate([np.ones(points.shape[:2] + (1,)), points - centres[:, None]], axis=2)
    gradient = np.array([np.linalg.lstsq(a, t, rcond=None)[0][1:]
                         for a, t in zip(design, times)])
    volume = np.array([ConvexHull(p).volume for p in points])
    return centres, times.mean(axis=1), volume, gradient


def frontal_angle(body: np.ndarray) -> float:
    """Frontal-plane angle [deg] of a body-frame vector: 0 left, +90 inferior."""
    return float(np.degrees(np.arctan2(-body[2], body[0])))


def read_map(path):
    """Nodes, cells and the last activation map (NaN where not activated), or None."""
    with h5py.File(path, "r") as f:
        if "fields" not in f or "mesh" not in f:
            return None
        steps = sorted(s for s in f["fields"] if "activation_time" in f["fields"][s])
        if not steps:
            return None
        tau = np.asarray(f["fields"][steps[-1]]["activation_time"][()], float).reshape(-1)
        tau[tau < 0] = np.nan
        return f["mesh/nodes"][()], np.asarray(f["mesh/cells"][()], int), tau


def main(argv=None) -> int:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("--centre", type=float, nargs=3, default=(0.0, 0.0, -40.0),
                        metavar=("X", "Y", "Z"))
    parser.add_argument("--right-angle", type=float, default=0.0)
    parser.add_argument("--bands", type=int, default=6)
    parser.add_argument("--bin", type=float, default=10.0, help="time bin [ms] (default 10)")
    args = parser.parse_args(argv)
    data = read_map(args.results)
    if data is None:
        print(f"{args.results}: no activation map", file=sys.stderr)
        return 1
    nodes, cells, tau = data
    keep = np.all(np.isfinite(tau[cells]), axis=1)
    centres, times, volume, gradient = cell_dipoles(nodes, cells[keep], tau)
    frame = model_frame(args.right_angle)  # rows: model axes in body coordinates

    def line(label: str, mask: np.ndarray) -> str:
        m = (volume[mask, None] * gradient[mask]).sum(axis=0)
        b = frame.T @ m
        return (f"{label}: {mask.sum():6d} cells, model ({m[0]:9.0f} {m[1]:9.0f} {m[2]:9.0f}), "
                f"body left {b[0]:9.0f} anterior {b[1]:9.0f} superior {b[2]:9.0f}, "
                f"|.| {np.linalg.norm(m):9.0f}, frontal {frontal_angle(b):5.0f} deg")

    print(line("whole", np.ones(len(volume), bool)))
    edges = np.linspace(centres[:, 2].min(), centres[:, 2].max(), args.bands + 1)
    for low, high in zip(edges[:-1], edges[1:]):
        mask = (centres[:, 2] >= low) & (centres[:, 2] <= high)
        print(line(f"z {low:6.1f} .. {high:6.1f} mm (mean time {times[mask].mean():5.1f} ms)",
                   mask))
    start = np.floor(times.min() / args.bin) * args.bin
    for low in np.arange(start, times.max() + 1e-9, args.bin):
        mask = (times >= low) & (times < low + args.bin)
        if mask.any():
            print(line(f"t {low:5.0f} .. {low + args.bin:5.0f} ms", mask))
    return 0


if __name__ == "__main__":
    sys.exit(main())
