#!/usr/bin/env python3
"""The idealized biventricular (BiV) mesh: two truncated ellipsoids joined by a septum.

The shape is the cardiac-geometries `biv_ellipsoid` family (fenicsx-pulse, ldrb demos), in mm:

  LV cavity       ellipsoid centred at 0, semi-axes (20, 18, 32.5)
  LV wall         the same ellipsoid grown by 5 mm in every semi-axis: (25, 23, 37.5)
  RV cavity       ellipsoid centred at (25, 0, 0), semi-axes (19, 25, 30), minus the LV wall
  RV wall         the RV cavity grown by 4 mm: (23, 29, 34)
  base            the plane z = 25 (everything above is cut away)

myocardium = (LV wall u RV wall) - LV cavity - RV cavity. The septum is the LV wall between
the two cavities (5 mm); the RV cavity is closed towards the LV by the LV epicardial
ellipsoid. Boundary parts (physical surfaces, the tags Systole reads as boundary ids):

  1 lv_endocardium   the LV cavity ellipsoid
  2 rv_endocardium   the RV cavity ellipsoid and the septal part of the LV wall ellipsoid
  3 epicardium       the outer surface (LV and RV wall ellipsoids outside the RV cavity)
  4 base             the plane z = 25

The tetrahedral mesh is turned into an all-hexahedral one by gmsh's subdivision
(Mesh.SubdivisionAlgorithm = 2: each tetrahedron split into four hexahedra), written as
ASCII msh 2.2; with --tetrahedra the linear tetrahedra themselves are written (ASCII msh 4.1,
one meshing thread and gmsh's default seed, so the same command writes the same mesh). Needs the gmsh Python module (Debian python3-gmsh or the PyPI wheel);
the shape constants are those of scripts/systole_post/biv_geometry.py.

  python3 scripts/make_biv_mesh.py --size 4.5 -o meshes/biv_coarse.msh
  python3 scripts/make_biv_mesh.py --size 5 --tetrahedra -o meshes/biv_tet_coarse.msh
"""

import argparse
import sys

from systole_post.biv_geometry import BASE_Z, LV_ENDO, LV_WALL, RV_ENDO, RV_WALL, grown


def level(ellipsoid, x):
    """The implicit function of an ellipsoid: < 0 inside, 0 on it, > 0 outside."""
    centre, radii = ellipsoid
    return sum(((x[i] - centre[i]) / radii[i]) ** 2 for i in range(3)) - 1.0


def add_ellipsoid(ellipsoid):
    import gmsh

    centre, radii = ellipsoid
    tag = gmsh.model.occ.addSphere(centre[0], centre[1], centre[2], 1.0)
    gmsh.model.occ.dilate([(3, tag)], centre[0], centre[1], centre[2], *radii)
    return tag


def surface_point(tag):
    """A point on the surface (its parametric centre, pulled onto the surface)."""
    import gmsh

    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    uv = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]
    x = gmsh.model.getValue(2, tag, uv)
    return gmsh.model.getClosestPoint(2, tag, x)[0]


def classify(tag):
    x = surface_point(tag)
    lv_epi = grown(LV_ENDO, LV_WALL)
    rv_epi = grown(RV_ENDO, RV_WALL)
    if abs(x[2] - BASE_Z) < 1e-6:
        return "base"
    if abs(level(LV_ENDO, x)) < 1e-4:
        return "lv_endocardium"
    if abs(level(RV_ENDO, x)) < 1e-4:
        return "rv_endocardium"
    if abs(level(lv_epi, x)) < 1e-4:
        # The LV wall ellipsoid bounds the RV cavity where it lies inside it.
        return "rv_endocardium" if level(RV_ENDO, x) < 0 else "epicardium"
    if abs(level(rv_epi, x)) < 1e-4:
        return "epicardium"
    raise RuntimeError(f"surface {tag} at {x} lies on none of the ellipsoids")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=float, default=4.5, help="element size [mm]")
    parser.add_argument("-o", "--output", required=True, help="the .msh file to write")
    parser.add_argument("--tetrahedra", action="store_true",
                        help="write the linear tetrahedra (msh 4.1) instead of hexahedra")
    args = parser.parse_args()
    import gmsh  # only here: the constants above are imported without gmsh


    gmsh.initialize(readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.model.add("biv_ellipsoid")
    occ = gmsh.model.occ
    lv_wall = add_ellipsoid(grown(LV_ENDO, LV_WALL))
    rv_wall = add_ellipsoid(grown(RV_ENDO, RV_WALL))
    lv_cavity = add_ellipsoid(LV_ENDO)
    rv_cavity = add_ellipsoid(RV_ENDO)
    septum = add_ellipsoid(grown(LV_ENDO, LV_WALL))
    rv_cavity, _ = occ.cut([(3, rv_cavity)], [(3, septum)])
    outer, _ = occ.fuse([(3, lv_wall)], [(3, rv_wall)])
    wall, _ = occ.cut(outer, [(3, lv_cavity)] + rv_cavity)
    box = occ.addBox(-100, -100, BASE_Z, 200, 200, 100)
    wall, _ = occ.cut(wall, [(3, box)])
    occ.synchronize()
    volumes = gmsh.model.getEntities(3)
    if len(volumes) != 1:
        raise RuntimeError(f"expected one myocardial volume, got {volumes}")

    parts = {"lv_endocardium": [], "rv_endocardium": [], "epicardium": [], "base": []}
    for _, tag in gmsh.model.getBoundary(volumes, oriented=False):
        parts[classify(tag)].append(tag)
    for i, name in enumerate(["lv_endocardium", "rv_endocardium", "epicardium", "base"]):
        if not parts[name]:
            raise RuntimeError(f"no surface for {name}")
        gmsh.model.addPhysicalGroup(2, parts[name], i + 1)
        gmsh.model.setPhysicalName(2, i + 1, name)
    gmsh.model.addPhysicalGroup(3, [volumes[0][1]], 1)
    gmsh.model.setPhysicalName(3, 1, "myocardium")

    gmsh.option.setNumber("Mesh.MeshSizeMin", args.size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", args.size)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)
    gmsh.option.setNumber("Mesh.Optimize", 1)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 0 if args.tetrahedra else 2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1 if args.tetrahedra else 2.2)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.model.mesh.generate(3)
    cell_type, cell_name = (4, "tetrahedra") if args.tetrahedra else (5, "hexahedra")
    types = gmsh.model.mesh.getElementTypes(3)
    if list(types) != [cell_type]:
        raise RuntimeError(f"not all {cell_name}: element types {types}")
    gmsh.write(args.output)
    n_cells = len(gmsh.model.mesh.getElementsByType(cell_type)[0])
    n_nodes = len(gmsh.model.mesh.getNodes()[0])
    print(f"wrote {args.output}: {n_cells} {cell_name}, {n_nodes} nodes, parts "
          + ", ".join(f"{k} = surfaces {v}" for k, v in parts.items()))
    gmsh.finalize()
    return 0


if __name__ == "__main__":
    sys.exit(main())
