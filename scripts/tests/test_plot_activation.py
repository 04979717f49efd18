"""Tests of systole_post.activation and scripts/plot_activation.py (outputs go to tmp_path)."""

import subprocess
import sys

import h5py
import numpy as np
import pytest

from conftest import SCRIPTS_DIR, write_results_file
from systole_post.activation import activation_field, make_activation_figure, plot_activation, \
    slice_faces, slice_mask

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture
def activation_results(tmp_path):
    """A 6 x 5 x 3 grid of nodes (1 mm apart); a plane wave along x at 0.5 mm/ms from 1 ms,
    one node never activated; fields at steps 0 (all NaN) and 40."""
    summary = {"activation_time_90": [9.0], "total_activation_time": [10.0]}
    path = write_results_file(tmp_path / "results.h5", {"time": [0, 20, 40], "step": [0, 1, 2]},
                              summary=summary)
    x, y, z = np.meshgrid(np.arange(6.0), np.arange(5.0), np.arange(3.0), indexing="ij")
    nodes = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    times = 1.0 + 2.0 * nodes[:, 0]
    times[-1] = np.nan
    with h5py.File(path, "a") as f:
        del f["mesh"]
        f.create_dataset("mesh/nodes", data=nodes)
        for step, values in ((0, np.full(len(nodes), np.nan)), (40, times)):
            group = f.create_group(f"fields/step_{step:06d}")
            group.attrs["time"] = float(step)
            group.attrs["step"] = step
            group.create_dataset("activation_time", data=values.reshape(-1, 1))
    return path


def test_field_of_the_last_step(activation_results):
    nodes, times, step, time = activation_field(activation_results)
    assert step == 40 and time == 40.0
    assert nodes.shape == (90, 3) and times.shape == (90,)
    assert np.isnan(times[-1])
    assert np.nanmax(times) == 11.0
    assert np.all(np.isnan(activation_field(activation_results, step=0)[1]))
    with pytest.raises(ValueError, match="no activation_time field at step 7"):
        activation_field(activation_results, step=7)


def test_slice_is_one_node_layer(activation_results):
    nodes, _, _, _ = activation_field(activation_results)
    assert slice_mask(nodes, 2, 1.2).sum() == 30          # the layer z = 1
    assert set(nodes[slice_mask(nodes, 0, 4.9), 0]) == {5.0}


def test_figure_histogram_and_slice(activation_results):
    figure = make_activation_figure(activation_results, "z", 1.0)
    histogram, picture = figure.axes[:2]
    counts = sum(patch.get_height() for patch in histogram.patches)
    assert counts == 89                                   # the NaN node is left out
    assert "89 of 90 nodes activated; 90 % 9.0 ms; total 10.0 ms" == histogram.get_title()
    assert picture.get_xlabel() == "x [mm]" and picture.get_ylabel() == "y [mm]"
    assert "z = 1 mm" in picture.get_title()
    assert len(figure.axes) == 3                          # with the colour bar


def test_plot_writes_png(activation_results, tmp_path):
    out = plot_activation(activation_results, tmp_path / "a.png", "y")
    assert out.read_bytes()[:8] == PNG_MAGIC


def test_script(activation_results, make_results, three_steps, tmp_path):
    script = str(SCRIPTS_DIR / "plot_activation.py")
    done = subprocess.run([sys.executable, script, str(activation_results), "--slice", "x=2"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    written = activation_results.parent / "activation.png"
    assert done.stdout.strip() == str(written)
    assert written.read_bytes()[:8] == PNG_MAGIC

    other = make_results(three_steps, name="mechanics.h5", fields={0: 0.0})
    done = subprocess.run([sys.executable, script, str(other)], capture_output=True, text=True)
    assert done.returncode == 1
    assert "no activation_time field" in done.stderr

    done = subprocess.run([sys.executable, script, str(activation_results), "--slice", "w=1"],
                          capture_output=True, text=True)
    assert done.returncode == 2
    assert "the axis must be x, y or z" in done.stderr


def u_shaped_mesh():
    """Unit hexahedra on the squares of a U in the (x, y) plane (3 x 3 squares without the
    middle and top-middle ones: 7 squares, area 7), one layer thick in z. Returns the nodes
    and the cells (8 node indices each, in an arbitrary order)."""
    squares = [(i, j) for i in range(3) for j in range(3) if not (i == 1 and j >= 1)]
    index, nodes, cells = {}, [], []
    for i, j in squares:
        cell = []
        for dz in (0, 1):
            for dx, dy in ((0, 0), (1, 0), (1, 1), (0, 1)):
                key = (i + dx, j + dy, dz)
                if key not in index:
                    index[key] = len(nodes)
                    nodes.append(key)
                cell.append(index[key])
        cells.append(cell)
    return np.array(nodes, dtype=float), np.array(cells)


def test_slice_faces_follow_the_mesh():
    # A slice through a node layer is triangulated along the cell faces: the triangles
    # cover the U (area 7) and not its notch, which a Delaunay triangulation would fill.
    nodes, cells = u_shaped_mesh()
    mask = nodes[:, 2] == 0
    points = nodes[mask][:, :2]
    triangles = slice_faces(mask, cells, points)
    assert len(triangles) == 2 * 7
    a, b, c = (points[triangles[:, k]] for k in range(3))
    area = 0.5 * np.abs(np.cross(b - a, c - a)).sum()
    assert area == pytest.approx(7.0)
    centres = (a + b + c) / 3
    assert not np.any((centres[:, 0] > 1) & (centres[:, 0] < 2) & (centres[:, 1] > 1))
    # A plane between node layers cuts no face: no triangles (the plot falls back).
    assert len(slice_faces(np.zeros(len(nodes), dtype=bool), cells, points[:0])) == 0
