"""Reading gmsh 4.1 ASCII meshes of linear tetrahedra (scripts/make_tet_meshes.py writes them),
with numpy only: the nodes, the tetrahedra, the triangles of each physical surface, and the
cavity volume a surface encloses with a lid plane (an independent check of Systole's)."""

from collections import Counter

import numpy as np


def read_msh41(path):
    """Nodes {tag: xyz}, elements {dim: [(entity, type, rows of node tags)]}, physical names
    {name: (dim, tag)} and entity physical tags {(dim, entity): [tags]} of an ASCII msh 4.1."""
    lines = iter(path.read_text().splitlines())
    nodes, elements, names, physical = {}, {}, {}, {}
    for line in lines:
        if line == "$MeshFormat":
            assert next(lines).split() == ["4.1", "0", "8"]
        elif line == "$PhysicalNames":
            for _ in range(int(next(lines))):
                dim, tag, name = next(lines).split(maxsplit=2)
                names[name.strip('"')] = (int(dim), int(tag))
        elif line == "$Entities":
            counts = [int(v) for v in next(lines).split()]
            for dim, count in enumerate(counts):
                for _ in range(count):
                    values = next(lines).split()
                    at = 4 if dim == 0 else 7  # tag, x y z or the bounding box
                    n_physical = int(values[at])
                    physical[(dim, int(values[0]))] = [int(v) for v in
                                                       values[at + 1:at + 1 + n_physical]]
        elif line == "$Nodes":
            n_blocks = int(next(lines).split()[0])
            for _ in range(n_blocks):
                _, _, parametric, n = (int(v) for v in next(lines).split())
                assert parametric == 0
                tags = [int(next(lines)) for _ in range(n)]
                for node in tags:
                    nodes[node] = np.array([float(v) for v in next(lines).split()])
        elif line == "$Elements":
            n_blocks = int(next(lines).split()[0])
            for _ in range(n_blocks):
                dim, entity, element_type, n = (int(v) for v in next(lines).split())
                rows = np.array([[int(v) for v in next(lines).split()[1:]] for _ in range(n)])
                elements.setdefault(dim, []).append((entity, element_type, rows))
    return nodes, elements, names, physical



def closed_surface_volume(points, triangles, tetrahedra, lid_point):
    """Volume enclosed by the boundary @p triangles of a tetrahedral mesh (@p points,
    @p tetrahedra) and the lid plane through @p lid_point that holds their rim: the divergence
    theorem with the origin on the lid, so the lid adds nothing. Each triangle is oriented
    towards its tetrahedron (out of the cavity), whatever gmsh wrote."""
    opposite = {}
    for tet_nodes in tetrahedra:
        for k in range(4):
            opposite[tuple(sorted(np.delete(tet_nodes, k)))] = tet_nodes[k]
    volume = 0.0
    for triangle in triangles:
        a, b, c = points[triangle] - lid_point
        d = points[opposite[tuple(sorted(triangle))]] - lid_point
        six_v = np.dot(a, np.cross(b, c))
        if np.dot(np.cross(b - a, c - a), d - a) < 0:  # normal away from the wall
            six_v = -six_v
        volume += six_v / 6.0
    return volume

class Mesh:
    """The tetrahedra and the triangles of each physical surface of a msh 4.1 file."""

    def __init__(self, path):
        nodes, elements, self.names, physical = read_msh41(path)
        index = {tag: i for i, tag in enumerate(nodes)}
        self.points = np.array(list(nodes.values()))
        self.types_3d = {element_type for _, element_type, _ in elements[3]}
        self.tets = np.vstack([np.vectorize(index.get)(rows) for _, element_type, rows
                               in elements[3] if element_type == 4])
        self.surfaces = {}
        for name, (dim, tag) in self.names.items():
            if dim == 2:
                self.surfaces[name] = np.vstack([
                    np.vectorize(index.get)(rows) for entity, element_type, rows
                    in elements[2] if element_type == 2 and tag in physical[(2, entity)]])

    def tet_volumes(self):
        p = self.points[self.tets]
        return np.einsum("ij,ij->i", p[:, 1] - p[:, 0],
                         np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0

    def boundary_faces(self):
        """{sorted face: the vertex of its tetrahedron opposite it} for the faces of one tet."""
        opposite, count = {}, Counter()
        for tet_nodes in self.tets:
            for k in range(4):
                face = tuple(sorted(np.delete(tet_nodes, k)))
                count[face] += 1
                opposite[face] = tet_nodes[k]
        return {face: opposite[face] for face, n in count.items() if n == 1}

    def cavity_volume(self, name, lid_point):
        """Volume enclosed by the surface @p name and the lid plane through @p lid_point
        (closed_surface_volume())."""
        return closed_surface_volume(self.points, self.surfaces[name], self.tets, lid_point)

    def open_edges(self, name):
        """Points of the edges used by one triangle of the surface @p name (its rim)."""
        edges = Counter(tuple(sorted((t[i], t[(i + 1) % 3]))) for t in self.surfaces[name]
                        for i in range(3))
        return self.points[sorted({n for edge, k in edges.items() if k == 1 for n in edge})]
