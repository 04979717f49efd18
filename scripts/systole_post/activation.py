"""Plot the activation map that the ``electrophysiology`` problem writes.

The activation time of every node is the field ``activation_time`` [ms] of the
/fields/step_NNNNNN groups (-1 in the file, NaN here, where a node has not activated), on the
nodes of /mesh/nodes;
the /summary row holds first, last, total and 90 % activation times. The figure has two
panels: a histogram of the activation times and a picture of a plane slice of the map
(filled isochrones). Uses matplotlib's Agg canvas directly (no pyplot, no display).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.tri import Triangulation

from systole_post.results import read_results

AXES = "xyz"


def activation_field(path: str | Path, step: int | None = None):
    """Nodes [mm] and activation times [ms] of a field step (default: the last one).

    Returns:
        (nodes (n, 3), times (n,), step, time of the step [ms]).

    Raises:
        ValueError: no field step carries ``activation_time`` (or not the one asked for).
    """
    path = Path(path)
    results = read_results(path)
    with h5py.File(path, "r") as h5file:
        steps = [s for s in results.field_steps
                 if "activation_time" in h5file[f"fields/step_{s:06d}"]]
        if not steps:
            raise ValueError(f"{path}: no activation_time field (run the electrophysiology "
                             "problem with Output / Field output interval > 0)")
        if step is None:
            step = steps[-1]
        elif step not in steps:
            raise ValueError(f"{path}: no activation_time field at step {step} "
                             f"(steps with one: {steps})")
        group = h5file[f"fields/step_{step:06d}"]
        times = np.asarray(group["activation_time"][()], dtype=float).reshape(-1)
        times[times < 0] = np.nan  # the file's -1: not activated
        nodes = np.asarray(h5file["mesh/nodes"][()], dtype=float)
        return nodes, times, step, float(group.attrs["time"])


def slice_mask(nodes: np.ndarray, axis: int, value: float) -> np.ndarray:
    """The nodes of the node layer nearest to the plane x_axis = value (exactly one layer
    on a structured mesh); on unstructured meshes, if that layer has fewer than 20 nodes,
    the nodes within 2 % of the mesh's extent along the axis."""
    distance = np.abs(nodes[:, axis] - value)
    extent = np.ptp(nodes[:, axis]) or 1.0
    mask = distance <= distance.min() + 1e-9 * extent
    if mask.sum() < 20:
        mask = distance <= max(distance.min(), 0.02 * extent)
    return mask


def mesh_cells(path: str | Path) -> np.ndarray:
    """The hexahedra of /mesh/cells (node indices, (n, 8)); empty if the file has none."""
    with h5py.File(path, "r") as h5file:
        if "mesh/cells" not in h5file:
            return np.zeros((0, 8), dtype=int)
        return np.asarray(h5file["mesh/cells"][()], dtype=int).reshape(-1, 8)


def slice_faces(mask: np.ndarray, cells: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Triangles (indices into the masked nodes) of the cell faces that lie in the slice:
    every cell with exactly 4 of its nodes in `mask` contributes that face, split in two
    along a diagonal (its nodes ordered around their centre in the plane `points`). Empty
    when the slice is not a node layer of the mesh."""
    local = np.full(mask.size, -1)
    local[mask] = np.arange(mask.sum())
    inside = mask[cells] if len(cells) else np.zeros((0, 8), dtype=bool)
    triangles = set()
    for cell, flags in zip(cells, inside):
        if flags.sum() != 4:
            continue
        face = local[cell[flags]]
        centre = points[face].mean(axis=0)
        angle = np.arctan2(*(points[face] - centre).T[::-1])
        a, b, c, d = face[np.argsort(angle)]
        triangles.add(tuple(sorted((a, b, c))))
        triangles.add(tuple(sorted((a, c, d))))
    return np.array(sorted(triangles), dtype=int).reshape(-1, 3)


def make_activation_figure(path: str | Path, slice_axis: str = "z",
                           slice_value: float | None = None, step: int | None = None) -> Figure:
    """Histogram of the activation times and the isochrones on a plane slice (default: the
    plane through the middle of the mesh along the slice axis)."""
    nodes, times, step, _ = activation_field(path, step)
    summary = read_results(path).summary
    axis = AXES.index(slice_axis)
    if slice_value is None:
        slice_value = 0.5 * (nodes[:, axis].min() + nodes[:, axis].max())
    active = np.isfinite(times)

    figure = Figure(figsize=(11.0, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    histogram, picture = figure.subplots(1, 2, width_ratios=[1, 1.4])
    histogram.hist(times[active], bins=30, color="tab:red", alpha=0.8)
    histogram.set_xlabel("activation time [ms]")
    histogram.set_ylabel("nodes")
    title = f"{active.sum()} of {times.size} nodes activated"
    for name, label in (("activation_time_90", "90 %"), ("total_activation_time", "total")):
        if name in summary and np.isfinite(summary[name][-1]):
            title += f"; {label} {summary[name][-1]:.1f} ms"
            if name == "activation_time_90":
                histogram.axvline(summary[name][-1], color="black", linestyle="--",
                                  label="90 % of the volume active")
                histogram.legend()
    histogram.set_title(title, fontsize=9)
    histogram.grid(True, alpha=0.3)

    mask = slice_mask(nodes, axis, slice_value) & active
    u, v = [a for a in range(3) if a != axis]
    points = nodes[mask]
    if len(points) >= 3:
        triangulation = Triangulation(points[:, u], points[:, v])
        faces = slice_faces(mask, mesh_cells(path), points[:, [u, v]])
        if len(faces):
            # The slice is a layer of mesh nodes: triangulate its cell faces.
            triangulation = Triangulation(points[:, u], points[:, v], faces)
        else:
            # Drop the long triangles that bridge concave parts (a ventricle's cavity).
            tri = triangulation.triangles
            edges = np.max([np.hypot(*(points[tri[:, i]][:, [u, v]] -
                                       points[tri[:, (i + 1) % 3]][:, [u, v]]).T)
                            for i in range(3)], axis=0)
            triangulation.set_mask(edges > 3 * np.median(edges))
        filled = picture.tricontourf(triangulation, times[mask], levels=20, cmap="viridis")
        picture.tricontour(triangulation, times[mask], levels=10, colors="white",
                           linewidths=0.5)
        figure.colorbar(filled, ax=picture, label="activation time [ms]")
    picture.set_aspect("equal")
    picture.set_xlabel(f"{AXES[u]} [mm]")
    picture.set_ylabel(f"{AXES[v]} [mm]")
    picture.set_title(f"slice {slice_axis} = {slice_value:.3g} mm (field step {step})",
                      fontsize=9)
    return figure


def plot_activation(path: str | Path, png_path: str | Path, slice_axis: str = "z",
                    slice_value: float | None = None, step: int | None = None) -> Path:
    """Write the activation figure of a results file as a PNG; returns its path."""
    png_path = Path(png_path)
    make_activation_figure(path, slice_axis, slice_value, step).savefig(png_path, format="png",
                                                                        dpi=100)
    return png_path
