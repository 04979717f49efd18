"""Tests of scripts/make_kuhn_slab.py: the dolfinx split of the Niederer slab, checked by
volume, orientation, the shared diagonal and the file read back."""

import numpy as np

import make_kuhn_slab as kuhn


def volumes(points, cells):
    a, b, c, d = (points[cells[:, q]] for q in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0


def test_six_positive_tetrahedra_per_cube_fill_the_slab():
    points, cells = kuhn.kuhn_slab(1.0)
    assert points.shape == (21 * 8 * 4, 3)
    assert cells.shape == (20 * 7 * 3 * 6, 4)
    v = volumes(points, cells)
    assert np.all(v > 0)
    np.testing.assert_allclose(v, 1.0 / 6.0, rtol=1e-12)
    assert abs(v.sum() - 420.0) < 1e-9
    assert np.array_equal(np.unique(cells), np.arange(len(points)))


def test_every_tetrahedron_holds_its_cubes_diagonal_along_plus_plus_plus():
    for mirror, direction in ((False, (1, 1, 1)), (True, (1, -1, 1))):
        points, cells = kuhn.kuhn_slab(1.0, mirror_y=mirror)
        for tet in cells.reshape(-1, 6, 4)[::37]:  # a sample of cubes
            shared = set.intersection(*(set(t) for t in tet))
            assert len(shared) == 2
            p, q = (points[i] for i in sorted(shared, key=lambda i: points[i] @ direction))
            np.testing.assert_allclose(q - p, direction, atol=1e-12)


def test_the_file_reads_back(tmp_path):
    points, cells = kuhn.kuhn_slab(1.0)
    path = tmp_path / "slab.msh"
    kuhn.write_msh(str(path), points, cells)
    lines = path.read_text().splitlines()
    n_nodes = int(lines[4])
    nodes = np.array([[float(x) for x in line.split()[1:]] for line in lines[5:5 + n_nodes]])
    start = 5 + n_nodes + 3
    elements = np.array([[int(x) for x in line.split()[5:]]
                         for line in lines[start:start + len(cells)]]) - 1
    np.testing.assert_array_equal(elements, cells)
    np.testing.assert_allclose(nodes, points, atol=1e-9)
    assert lines[-1] == "$EndElements"
