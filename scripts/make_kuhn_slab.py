#!/usr/bin/env python3
"""The Niederer slab as fenicsx-beat meshes it: a structured tetrahedral gmsh mesh (format 2.2).

dolfinx's create_box with tetrahedra (cpp/dolfinx/mesh/generation.h, build_tet) splits every
cube of an nx x ny x nz grid into six tetrahedra that all share the cube's diagonal v0-v7 (the
Kuhn, or Freudenthal, split): every body and face diagonal of the mesh points along (+, +, +),
from the stimulated corner of the Niederer et al. 2011 slab towards its far corner P8. This
script writes that mesh for Systole (Geometry / Type = gmsh, P1), so that the mesh-orientation
effect on the activation times can be measured with Systole's own solver
(docs/verification.md, "fenicsx-beat's far corners"). --mirror-y flips y: the shared
diagonals then point along (1, -1, 1).

  python3 scripts/make_kuhn_slab.py 0.5 niederer_kuhn_h05.msh [--mirror-y]
"""

import argparse

import numpy as np

#: The slab [mm].
LENGTHS = (20.0, 7.0, 3.0)

#: The six tetrahedra of the cube with local vertices v0 ... v7 (bit 0: +x, bit 1: +y,
#: bit 2: +z), each holding v0 and v7, in dolfinx's order.
CUBE_TETS = ((0, 1, 3, 7), (0, 1, 7, 5), (0, 5, 7, 4), (0, 3, 2, 7), (0, 6, 4, 7), (0, 2, 6, 7))


def kuhn_slab(h: float, mirror_y: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 3) [mm] and positively oriented tetrahedra (m, 4) of the slab of cell size
    h, vertices numbered lexicographically (x fastest) as dolfinx does."""
    n = [int(round(length / h)) for length in LENGTHS]
    ix, iy, iz = np.meshgrid(*(np.arange(k + 1) for k in n), indexing="ij")
    index = (iz * (n[1] + 1) + iy) * (n[0] + 1) + ix
    points = np.zeros(((n[0] + 1) * (n[1] + 1) * (n[2] + 1), 3))
    for axis, grid in enumerate((ix, iy, iz)):
        points[index.ravel(), axis] = grid.ravel() * LENGTHS[axis] / n[axis]
    if mirror_y:
        points[:, 1] = LENGTHS[1] - points[:, 1]
    # The cubes' eight vertices, cubes numbered with x fastest; each cube's six tetrahedra
    # in turn, as dolfinx numbers them.
    corners = np.stack([index[dx:dx + n[0], dy:dy + n[1], dz:dz + n[2]].ravel(order="F")
                        for dz in (0, 1) for dy in (0, 1) for dx in (0, 1)], axis=1)
    cells = np.stack([corners[:, list(tet)] for tet in CUBE_TETS], axis=1).reshape(-1, 4)
    a, b, c, d = (points[cells[:, q]] for q in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    cells[negative, 2], cells[negative, 3] = cells[negative, 3], cells[negative, 2]
    return points, cells


def write_msh(path: str, points: np.ndarray, cells: np.ndarray) -> None:
    """gmsh format 2.2 ASCII: the nodes, and the tetrahedra in physical and elementary
    entity 1."""
    with open(path, "w", encoding="ascii") as out:
        out.write(f"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{len(points)}\n")
        out.writelines(f"{i + 1} {x:.10g} {y:.10g} {z:.10g}\n"
                       for i, (x, y, z) in enumerate(points))
        out.write(f"$EndNodes\n$Elements\n{len(cells)}\n")
        out.writelines(f"{e + 1} 4 2 1 1 {' '.join(str(v + 1) for v in tet)}\n"
                       for e, tet in enumerate(cells))
        out.write("$EndElements\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("h", type=float, help="cell size [mm] (20, 7 and 3 mm its multiples)")
    parser.add_argument("out", help="the .msh file to write")
    parser.add_argument("--mirror-y", action="store_true",
                        help="flip y: the shared diagonals along (1, -1, 1)")
    args = parser.parse_args()
    points, cells = kuhn_slab(args.h, args.mirror_y)
    write_msh(args.out, points, cells)
    print(f"{args.out}: {len(points)} nodes, {len(cells)} tetrahedra")


if __name__ == "__main__":
    main()
