"""Tests of scripts/activation_dipole.py (files in tmp_path)."""

import subprocess
import sys

import h5py
import numpy as np

from conftest import SCRIPTS_DIR


def write_front(path, speed=0.5, shuffle=True, unreached=False):
    """A 4 x 2 x 2 block of 1 mm hexahedra (16 mm^3) activated by a plane front along +x
    (tau = 10 + x / speed), the cells' nodes in a scrambled order."""
    xs, ys, zs = np.arange(5.0), np.arange(3.0), np.arange(3.0)
    nodes = np.array([[x, y, z] for z in zs for y in ys for x in xs])
    index = {tuple(p): i for i, p in enumerate(nodes)}
    rng = np.random.default_rng(3)
    cells = []
    for z in zs[:-1]:
        for y in ys[:-1]:
            for x in xs[:-1]:
                corners = [index[(x + a, y + b, z + c)] for c in (0, 1) for b in (0, 1)
                           for a in (0, 1)]
                cells.append(rng.permutation(corners) if shuffle else corners)
    tau = 10 + nodes[:, 0] / speed
    if unreached:
        tau[-1] = -1  # the file's "not activated"
    with h5py.File(path, "w") as f:
        f.create_dataset("mesh/nodes", data=nodes)
        f.create_dataset("mesh/cells", data=np.array(cells, dtype=np.uint32))
        f.create_dataset("fields/step_000000/activation_time", data=np.full((len(nodes), 1), -1.0))
        f.create_dataset("fields/step_000010/activation_time", data=tau[:, None])
    return path


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPTS_DIR / "activation_dipole.py"), *args],
                          capture_output=True, text=True)


def test_plane_front_gives_volume_over_speed_along_it(tmp_path):
    import activation_dipole

    # Exact for a linear tau on any node order: 16 mm^3 x 2 ms/mm along x.
    nodes, cells, tau = activation_dipole.read_map(write_front(tmp_path / "r.h5"))
    centres, times, volume, gradient = activation_dipole.cell_dipoles(nodes, cells, tau)
    assert np.allclose(volume, 1.0)
    assert np.allclose(gradient, [2.0, 0.0, 0.0])
    assert np.allclose(times, 10 + 2 * centres[:, 0])
    out = run(str(tmp_path / "r.h5"), "--bands", "2", "--bin", "2")
    assert out.returncode == 0, out.stderr
    whole = out.stdout.splitlines()[0]
    model = [float(v) for v in whole.split("model (")[1].split(")")[0].split()]
    assert np.allclose(model, [32, 0, 0])
    # The model's +x (the septum, forwards at angle 0) in the body: 32 times the frame's
    # first row (-0.354, 0.866, 0.354): right, anterior, superior, frontal -135 deg.
    assert "body left       -11 anterior        28 superior        11" in whole
    assert whole.endswith("frontal  -135 deg")
    # 2 height bands and 4 time bins (one per column of cells: 11, 13, 15, 17 ms).
    assert len(out.stdout.splitlines()) == 1 + 2 + 4


def test_frontal_angle_convention():
    import activation_dipole

    assert activation_dipole.frontal_angle(np.array([1.0, 0, 0])) == 0  # left
    assert np.isclose(activation_dipole.frontal_angle(np.array([0, 0, -1.0])), 90)  # inferior
    assert np.isclose(activation_dipole.frontal_angle(np.array([-1.0, 0, 1.0])), -135)


def test_unreached_cells_are_left_out_and_no_map_fails(tmp_path):
    out = run(str(write_front(tmp_path / "u.h5", unreached=True)))
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("whole:     15 cells")
    with h5py.File(tmp_path / "empty.h5", "w") as f:
        f.create_dataset("timeseries/time", data=[0.0])
    out = run(str(tmp_path / "empty.h5"))
    assert out.returncode == 1
    assert "no activation map" in out.stderr
