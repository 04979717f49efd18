#!/usr/bin/env python3
"""Convert a legacy-dolfin HDF5 tetrahedral mesh with facet markers into a gmsh 2.2 file.

Legacy FEniCS writes a mesh as `/Mesh/mesh/geometry` (vertex coordinates), `/Mesh/mesh/topology`
(4 vertices per tetrahedron) and the facet markers as a MeshFunction: `/MeshFunction/0/mesh/
topology` (3 vertices per triangle) and `/MeshFunction/0/values` (one tag per triangle; the
largest unsigned integer marks an unmarked, interior facet). This script writes the marked
triangles as gmsh physical surfaces named by --names, the tetrahedra (positively oriented) as
the physical volume `myocardium`, and the coordinates times --scale (gmsh 2.2 ASCII, 12
significant digits).

The mesh of the Aróstica et al. 2025 benchmark (the participants' shared mesh, element size
5 mm, lengths in m; markers 1 endocardium, 2 epicardium, 3 base): the file
`data/monoventricle_mesh/ellipsoid_0.005.h5` of github.com/Reidmen/cardiac_benchmark_toolkit
(MIT licence, commit e8d4755), converted by

  python3 scripts/convert_dolfin_mesh.py ellipsoid_0.005.h5 meshes/arostica_benchmark_tet.msh \
      --scale 1000 --names 1=endocardium,2=epicardium,3=base
"""

from __future__ import annotations

import argparse
import sys

import h5py
import numpy as np


def parse_names(text: str) -> dict[int, str]:
    """'1=endocardium,2=epicardium' -> {1: 'endocardium', 2: 'epicardium'}."""
    names = {}
    for item in text.split(","):
        tag, _, name = item.partition("=")
        if not name or not tag.strip().isdigit():
            sys.exit(f"--names: '{item}' is not TAG=NAME (e.g. 1=endocardium)")
        names[int(tag)] = name.strip()
    return names


def read(path: str, scale: float):
    """Coordinates [scaled], tetrahedra, marked triangles and their tags."""
    with h5py.File(path, "r") as f:
        try:
            x = f["Mesh/mesh/geometry"][:] * scale
            tets = f["Mesh/mesh/topology"][:].astype(np.int64)
            faces = f["MeshFunction/0/mesh/topology"][:].astype(np.int64)
            tags = f["MeshFunction/0/values"][:].ravel()
        except KeyError as e:
            sys.exit(f"{path}: no legacy-dolfin mesh with facet markers ({e})")
    if tets.shape[1] != 4 or faces.shape[1] != 3:
        sys.exit(f"{path}: not a tetrahedral mesh with triangle markers")
    marked = tags < np.iinfo(np.uint32).max
    return x, tets, faces[marked], tags[marked].astype(np.int64)


def orient(x: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The tetrahedra with their vertices ordered to a positive volume."""
    a, b, c, d = (x[tets[:, i]] for i in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    out = tets.copy()
    out[negative, 2], out[negative, 3] = tets[negative, 3], tets[negative, 2]
    return out


def write(path: str, x, tets, faces, tags, names: dict[int, str]) -> None:
    """gmsh 2.2 ASCII: physical surfaces by tag and name, the volume tag 1000."""
    missing = sorted(set(np.unique(tags)) - set(names))
    if missing:
        sys.exit(f"tags {missing} have no name: add them to --names")
    volume = 1000
    with open(path, "w") as o:
        o.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n")
        o.write(f"{len(names) + 1}\n")
        for tag, name in sorted(names.items()):
            o.write(f'2 {tag} "{name}"\n')
        o.write(f'3 {volume} "myocardium"\n$EndPhysicalNames\n$Nodes\n{len(x)}\n')
        for i, p in enumerate(x, 1):
            o.write(f"{i} {p[0]:.12g} {p[1]:.12g} {p[2]:.12g}\n")
        o.write(f"$EndNodes\n$Elements\n{len(faces) + len(tets)}\n")
        k = 1
        for face, tag in zip(faces + 1, tags):
            o.write(f"{k} 2 2 {tag} {tag} {face[0]} {face[1]} {face[2]}\n")
            k += 1
        for t in tets + 1:
            o.write(f"{k} 4 2 {volume} {volume} {t[0]} {t[1]} {t[2]} {t[3]}\n")
            k += 1
        o.write("$EndElements\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("input", help="legacy-dolfin HDF5 mesh (.h5)")
    parser.add_argument("output", help="gmsh file to write (.msh)")
    parser.add_argument("--scale", type=float, default=1.0,
                        help="factor to mm (1000 for a mesh in m)")
    parser.add_argument("--names", required=True, help="TAG=NAME,... for the facet markers")
    args = parser.parse_args()
    x, tets, faces, tags = read(args.input, args.scale)
    names = parse_names(args.names)
    write(args.output, x, orient(x, tets), faces, tags, names)
    counts = ", ".join(f"{names[t]} {n}" for t, n in zip(*np.unique(tags, return_counts=True)))
    print(f"{args.output}: {len(x)} vertices, {len(tets)} tetrahedra; triangles: {counts}")


if __name__ == "__main__":
    main()
