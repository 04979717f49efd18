"""A small reader of ASCII gmsh .msh 2.2 meshes (hexahedra with quadrilateral faces, or
tetrahedra with triangular faces), the quality of hexahedral cells and the volume of a cavity
bounded by a tagged surface (quadrilaterals or triangles) and closed by a flat lid.

This is an independent path to the numbers Systole computes in C++ (deal.II's gmsh import and
Mechanics::CavityVolume): it reads the file itself and integrates another field over another
closed surface (the endocardium plus the polygon of its basal ring), see cavity_volume().
"""

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from systole_post.msh41 import closed_surface_volume

HEX = 5
QUAD = 3
TET = 4
TRIANGLE = 2

# For each corner of a gmsh (= VTK) hexahedron, its three edge neighbours in right-handed
# order: det(x_a - x_i, x_b - x_i, x_c - x_i) > 0 for a positively oriented cell.
_CORNER_NEIGHBOURS = np.array(
    [[1, 3, 4], [2, 0, 5], [3, 1, 6], [0, 2, 7], [7, 5, 0], [4, 6, 1], [5, 7, 2], [6, 4, 3]]
)


@dataclass
class MshMesh:
    nodes: np.ndarray  # (n, 3) coordinates, by node index (0-based)
    hexahedra: np.ndarray  # (n_hex, 8) node indices
    quads: dict = field(default_factory=dict)  # physical tag -> (n, 4) node indices
    names: dict = field(default_factory=dict)  # physical surface name -> tag
    tetrahedra: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), int))
    triangles: dict = field(default_factory=dict)  # physical tag -> (n, 3) node indices

    def faces(self, tag: int) -> np.ndarray:
        """The boundary faces (quadrangles or triangles) of physical surface @p tag."""
        return self.quads.get(tag, self.triangles.get(tag, np.zeros((0, 3), int)))


def read_msh(path) -> MshMesh:
    """Read an ASCII msh 2.2 file with hexahedral cells and quadrilateral boundary faces, or
    tetrahedral cells and triangular boundary faces."""
    lines = Path(path).read_text().split("\n")
    i = 0
    names, node_ids, coords, hexes, quads = {}, [], [], [], {}
    tets, triangles = [], {}
    if not lines[1].startswith("2."):
        raise ValueError(f"{path}: not an msh 2.x file (version {lines[1]})")
    while i < len(lines):
        line = lines[i].strip()
        if line == "$PhysicalNames":
            n = int(lines[i + 1])
            for entry in lines[i + 2 : i + 2 + n]:
                dim, tag, name = entry.split(maxsplit=2)
                if int(dim) == 2:
                    names[name.strip('"')] = int(tag)
            i += n + 2
        elif line == "$Nodes":
            n = int(lines[i + 1])
            table = np.array([lines[i + 2 + k].split() for k in range(n)], dtype=float)
            node_ids, coords = table[:, 0].astype(int), table[:, 1:4]
            i += n + 2
        elif line == "$Elements":
            n = int(lines[i + 1])
            for entry in lines[i + 2 : i + 2 + n]:
                values = [int(v) for v in entry.split()]
                kind, n_tags = values[1], values[2]
                physical, vertices = values[3], values[3 + n_tags :]
                if kind == HEX:
                    hexes.append(vertices)
                elif kind == QUAD:
                    quads.setdefault(physical, []).append(vertices)
                elif kind == TET:
                    tets.append(vertices)
                elif kind == TRIANGLE:
                    triangles.setdefault(physical, []).append(vertices)
            i += n + 2
        else:
            i += 1
    index = np.full(node_ids.max() + 1, -1)
    index[node_ids] = np.arange(len(node_ids))
    return MshMesh(
        nodes=coords,
        hexahedra=index[np.array(hexes, dtype=int).reshape(-1, 8)],
        quads={tag: index[np.array(q)] for tag, q in quads.items()},
        names=names,
        tetrahedra=index[np.array(tets, dtype=int).reshape(-1, 4)],
        triangles={tag: index[np.array(t)] for tag, t in triangles.items()},
    )


def scaled_jacobians(mesh: MshMesh) -> np.ndarray:
    """The scaled Jacobian of every hexahedron: the smallest over its 8 corners of
    det(e_a, e_b, e_c) with the unit edge vectors from the corner (1 for a cube, <= 0 for an
    inverted or degenerate corner)."""
    x = mesh.nodes[mesh.hexahedra]  # (n, 8, 3)
    corner = x[:, :, None, :]
    edges = x[:, _CORNER_NEIGHBOURS, :] - corner  # (n, 8, 3, 3)
    edges /= np.linalg.norm(edges, axis=-1, keepdims=True)
    return np.linalg.det(edges).min(axis=1)


def _outward_quads(mesh: MshMesh, quads: np.ndarray) -> np.ndarray:
    """The boundary quads reordered so that their normal points out of the hexahedron they
    bound (gmsh does not orient boundary elements consistently)."""
    owner = {}
    for c, cell in enumerate(mesh.hexahedra):
        for face in ([0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]):
            owner.setdefault(tuple(sorted(cell[face])), c)
    result = quads.copy()
    for k, quad in enumerate(quads):
        cell = owner[tuple(sorted(quad))]
        centre = mesh.nodes[mesh.hexahedra[cell]].mean(axis=0)
        p = mesh.nodes[quad]
        normal = np.cross(p[2] - p[0], p[3] - p[1])
        if normal @ (p.mean(axis=0) - centre) < 0:
            result[k] = quad[::-1]
    return result


def cavity_volume(mesh: MshMesh, surface: str, lid_z: float) -> float:
    """Volume of the cavity bounded by the physical surface @p surface (the wall around it) and
    closed by the lid in the plane z = lid_z, by the divergence theorem with the field x / 3:

        V = 1/3 (integral over the surface of x . n  +  lid_z * area of the lid),

    n pointing out of the cavity (into the wall). Each bilinear quad is integrated exactly
    (2 x 2 Gauss points: x . (x_u x x_v) has degree 2 in u and v); the lid is the polygon
    of the surface's boundary edges in the plane z = lid_z, whose area is the shoelace sum
    over those edges, oriented by the surface."""
    quads = _outward_quads(mesh, mesh.quads[mesh.names[surface]])
    # Cavity-outward normal = minus the wall-outward one: reverse the quads.
    quads = quads[:, ::-1]
    g = 0.5 / np.sqrt(3.0)
    flux = 0.0
    for u in (0.5 - g, 0.5 + g):
        for v in (0.5 - g, 0.5 + g):
            p = mesh.nodes[quads]
            w = np.array([(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v])
            x = np.einsum("k,nkd->nd", w, p)
            x_u = (1 - v) * (p[:, 1] - p[:, 0]) + v * (p[:, 2] - p[:, 3])
            x_v = (1 - u) * (p[:, 3] - p[:, 0]) + u * (p[:, 2] - p[:, 1])
            flux += 0.25 * np.sum(np.einsum("nd,nd->n", x, np.cross(x_u, x_v)))
    # Boundary edges of the surface (used by one quad only), in the quads' orientation. The
    # cavity's boundary is surface + lid, so the lid's boundary runs against these edges.
    count = {}
    for quad in quads:
        for a, b in zip(quad, np.roll(quad, -1)):
            key = (min(a, b), max(a, b))
            count[key] = count.get(key, 0) + 1
    area = 0.0
    for quad in quads:
        for a, b in zip(quad, np.roll(quad, -1)):
            if count[(min(a, b), max(a, b))] == 1:
                pa, pb = mesh.nodes[a], mesh.nodes[b]
                if abs(pa[2] - lid_z) > 1e-6 or abs(pb[2] - lid_z) > 1e-6:
                    raise ValueError(f"{surface}: a boundary edge off the lid plane z = {lid_z}")
                # Lid traversed b -> a; its outward normal is +z, area = 1/2 sum (x_b y_a - x_a y_b).
                area += 0.5 * (pb[0] * pa[1] - pa[0] * pb[1])
    return (flux + lid_z * area) / 3.0


def triangle_cavity_volume(mesh: MshMesh, surface: str, lid_point) -> float:
    """Volume of the cavity bounded by the triangles of the physical surface @p surface of a
    tetrahedral mesh and closed by the plane through @p lid_point that holds its rim: the
    divergence theorem with the origin on the lid (the lid adds nothing), each triangle
    oriented out of the cavity, into the tetrahedron it bounds (gmsh does not orient boundary
    elements consistently)."""
    return closed_surface_volume(mesh.nodes, mesh.triangles[mesh.names[surface]],
                                 mesh.tetrahedra, lid_point)
