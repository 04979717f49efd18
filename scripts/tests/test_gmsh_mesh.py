"""systole_post.gmsh_mesh on tiny hand-made meshes with known answers."""

import itertools

import numpy as np
import pytest

from systole_post.gmsh_mesh import (cavity_volume, read_msh, scaled_jacobians,
                                    triangle_cavity_volume)


def write_block_with_cavity(path, shear=0.0, flip=False):
    """A 3 x 3 x 2 block of unit cubes (z in [0, 2]) without its top centre cube: a cavity of
    volume 1 open to the lid plane z = 2. Its 5 walls are the physical surface "endo" (tag 1),
    written with mixed orientations as gmsh does; the top faces are "base" (tag 2). With
    @p shear, x += shear * z (volumes unchanged). With @p flip, one cell is written inverted."""
    index = {}
    nodes = []
    for k, j, i in itertools.product(range(3), range(4), range(4)):
        index[(i, j, k)] = len(nodes) + 1
        nodes.append((i + shear * k, j, k))
    hexes, quads = [], []
    for i, j, k in itertools.product(range(3), range(3), range(2)):
        if (i, j, k) == (1, 1, 1):
            continue
        corners = [(i, j, k), (i + 1, j, k), (i + 1, j + 1, k), (i, j + 1, k)]
        cell = [index[c] for c in corners] + [index[(a, b, c + 1)] for a, b, c in corners]
        if flip and (i, j, k) == (0, 0, 0):
            cell = cell[4:] + cell[:4]
        hexes.append(cell)
    cavity = {"x-": [(1, 1, 1), (1, 2, 1), (1, 2, 2), (1, 1, 2)],
              "x+": [(2, 1, 1), (2, 1, 2), (2, 2, 2), (2, 2, 1)],
              "y-": [(1, 1, 1), (1, 1, 2), (2, 1, 2), (2, 1, 1)],
              "y+": [(1, 2, 1), (2, 2, 1), (2, 2, 2), (1, 2, 2)],
              "z-": [(1, 1, 1), (2, 1, 1), (2, 2, 1), (1, 2, 1)]}
    for n, face in enumerate(cavity.values()):
        ids = [index[c] for c in face]
        quads.append((1, ids[::-1] if n % 2 else ids))
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "2",
             '2 1 "endo"', '2 2 "base"', "$EndPhysicalNames", "$Nodes", str(len(nodes))]
    lines += [f"{n + 1} {x} {y} {z}" for n, (x, y, z) in enumerate(nodes)]
    lines += ["$EndNodes", "$Elements", str(len(hexes) + len(quads))]
    element = 1
    for tag, q in quads:
        lines.append(f"{element} 3 2 {tag} {tag} " + " ".join(map(str, q)))
        element += 1
    for h in hexes:
        lines.append(f"{element} 5 2 1 1 " + " ".join(map(str, h)))
        element += 1
    lines += ["$EndElements", ""]
    path.write_text("\n".join(lines))
    return path


def test_reader_and_cube_quality(tmp_path):
    mesh = read_msh(write_block_with_cavity(tmp_path / "block.msh"))
    assert mesh.nodes.shape == (48, 3)
    assert mesh.hexahedra.shape == (17, 8)
    assert mesh.names == {"endo": 1, "base": 2}
    assert mesh.quads[1].shape == (5, 4)
    np.testing.assert_allclose(scaled_jacobians(mesh), 1.0, rtol=0, atol=1e-14)


def test_sheared_and_inverted_cells(tmp_path):
    sheared = read_msh(write_block_with_cavity(tmp_path / "s.msh", shear=1.0))
    # A unit cube sheared by x += z: the corner angle between e_x and (1, 0, 1)/sqrt 2.
    np.testing.assert_allclose(scaled_jacobians(sheared), 1 / np.sqrt(2), atol=1e-14)
    flipped = read_msh(write_block_with_cavity(tmp_path / "f.msh", flip=True))
    sj = scaled_jacobians(flipped)
    assert sj.min() == pytest.approx(-1.0) and np.sum(sj < 0) == 1


@pytest.mark.parametrize("shear", [0.0, 0.3])
def test_cavity_volume_of_the_open_cube(tmp_path, shear):
    mesh = read_msh(write_block_with_cavity(tmp_path / "b.msh", shear=shear))
    assert cavity_volume(mesh, "endo", lid_z=2.0) == pytest.approx(1.0, rel=1e-12)


def test_cavity_volume_needs_its_ring_in_the_lid_plane(tmp_path):
    mesh = read_msh(write_block_with_cavity(tmp_path / "b.msh"))
    with pytest.raises(ValueError, match="off the lid plane"):
        cavity_volume(mesh, "endo", lid_z=1.5)


def test_reader_of_tetrahedra(tmp_path):
    """One unit tetrahedron, its face z = 0 tagged "base": the cells and faces by type."""
    path = tmp_path / "tet.msh"
    path.write_text("\n".join([
        "$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "2", '2 1 "base"',
        '3 2 "myocardium"', "$EndPhysicalNames", "$Nodes", "4", "1 0 0 0", "2 1 0 0",
        "3 0 1 0", "4 0 0 1", "$EndNodes", "$Elements", "2", "1 2 2 1 1 1 3 2",
        "2 4 2 2 2 1 2 3 4", "$EndElements", ""]))
    mesh = read_msh(path)
    assert mesh.hexahedra.shape == (0, 8) and mesh.quads == {}
    np.testing.assert_array_equal(mesh.tetrahedra, [[0, 1, 2, 3]])
    np.testing.assert_array_equal(mesh.faces(mesh.names["base"]), [[0, 2, 1]])


def write_tet_block_with_cavity(path, shear=0.0):
    """The block of write_block_with_cavity() with every cube split into the 6 tetrahedra
    around its diagonal from (i, j, k) to (i + 1, j + 1, k + 1) (a conforming split), the
    tetrahedra's faces on the 5 walls of the cavity the physical surface "endo" (tag 1),
    written with mixed orientations."""
    index, nodes = {}, []
    for k, j, i in itertools.product(range(3), range(4), range(4)):
        index[(i, j, k)] = len(nodes) + 1
        nodes.append((i + shear * k, j, k))
    tets = []
    for i, j, k in itertools.product(range(3), range(3), range(2)):
        if (i, j, k) == (1, 1, 1):
            continue
        for order in itertools.permutations(range(3)):
            corner, path_ = [i, j, k], [(i, j, k)]
            for axis in order:
                corner[axis] += 1
                path_.append(tuple(corner))
            tets.append([index[c] for c in path_])
    count = {}
    for tet in tets:
        for f in range(4):
            face = tuple(sorted(tet[:f] + tet[f + 1:]))
            count[face] = count.get(face, 0) + 1
    unsheared = {index[c]: c for c in index}
    walls = []
    for face, n in count.items():
        centre = np.mean([unsheared[v] for v in face], axis=0)
        if n == 1 and 1 <= centre[0] <= 2 and 1 <= centre[1] <= 2 and 1 <= centre[2] < 2:
            walls.append(list(face) if len(walls) % 2 else list(face)[::-1])
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "1",
             '2 1 "endo"', "$EndPhysicalNames", "$Nodes", str(len(nodes))]
    lines += [f"{n + 1} {x} {y} {z}" for n, (x, y, z) in enumerate(nodes)]
    lines += ["$EndNodes", "$Elements", str(len(walls) + len(tets))]
    element = 1
    for face in walls:
        lines.append(f"{element} 2 2 1 1 " + " ".join(map(str, face)))
        element += 1
    for tet in tets:
        lines.append(f"{element} 4 2 2 2 " + " ".join(map(str, tet)))
        element += 1
    lines += ["$EndElements", ""]
    path.write_text("\n".join(lines))
    return path


@pytest.mark.parametrize("shear", [0.0, 0.7])
def test_triangle_cavity_volume_of_a_tetrahedral_block(tmp_path, shear):
    """The unit cavity (a shear keeps its volume) from its 10 wall triangles."""
    mesh = read_msh(write_tet_block_with_cavity(tmp_path / "t.msh", shear=shear))
    assert mesh.tetrahedra.shape == (17 * 6, 4)
    assert mesh.triangles[1].shape == (10, 3)
    lid = np.array([1.0 + 2 * shear, 1.0, 2.0])  # a point of the plane z = 2
    assert triangle_cavity_volume(mesh, "endo", lid) == pytest.approx(1.0, abs=1e-14)
