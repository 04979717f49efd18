#!/usr/bin/env python3
"""Tetrahedral gmsh meshes of the LV and BiV ellipsoids, written by cardiac-geometries-core.

The PyPI package cardiac-geometries-core (the gmsh half of cardiac-geometries, the geometry
package of fenicsx-pulse; no FEniCS) builds the shapes and meshes them with the gmsh wheel.
This script calls it with lengths in mm, pins gmsh's threads and random seed, and writes
gmsh format 4.1 ASCII with linear tetrahedra, plus a JSON of the physical groups beside each
mesh. The physical names are the package's own; Systole maps them to its part names with
the name table printed for each mesh (a `set Boundary names = ...` line for a .prm file).

lv_ellipsoid_tet.msh: the Land et al. 2015 ventricle (cardiac-geometries' lv_ellipsoid with
the defaults of its command line): endocardium r_short 7, r_long 17 mm; epicardium 10, 20 mm;
truncated 5 mm above the centre. The long axis is x: base plane x = 5 mm, endocardial apex
(-17, 0, 0), epicardial apex (-20, 0, 0). Physical groups: surfaces BASE (5), ENDO (6),
EPI (7); curves EPIRING (3), ENDORING (4); points ENDOPT (1), EPIPT (2); volume
MYOCARDIUM (8). The size at the base points is --lv-psize, at the apexes half of it.

biv_ellipsoid_tet.msh: cardiac-geometries' biv_ellipsoid with the defaults of its Python
function (given in cm there, here x 10 in mm). Long axis z, base plane z = 10 mm:

  LV outer   ellipsoid centred at 0, semi-axes (22, 22, 45); the LV wall 5 mm -> (17, 17, 40)
  RV outer   ellipsoid centred at (10, 0, 0), semi-axes (32, 23, 43); RV wall 4 mm ->
             cavity (28, 19, 39), minus the LV outer ellipsoid

myocardium = (LV outer u RV outer) - LV cavity - RV cavity, cut by z = 10 mm; the RV lies on
the +x side. Physical groups: surfaces EPI (1), BASE (2), LV (3: the LV endocardium),
RV (4: the RV endocardium, free wall and septal side); volume Myocardium (1). One uniform
element size, --biv-psize.

  python3 scripts/make_tet_meshes.py --out meshes

--order 2 writes second-order meshes (10-node tetrahedra, 6-node triangles; the mid-edge nodes
of the curved surfaces on them) as lv_ellipsoid_tet_p2.msh and biv_ellipsoid_tet_p2.msh.

Needs cardiac-geometries-core and the gmsh wheel (scripts/requirements.txt, in the venv).
"""

import argparse
import json
import math
import sys
from pathlib import Path

LV_FILE = "lv_ellipsoid_tet.msh"
BIV_FILE = "biv_ellipsoid_tet.msh"

#: The Land et al. 2015 ventricle [mm]: lv_ellipsoid's command-line defaults.
LV_SHAPE = {"r_short_endo": 7.0, "r_short_epi": 10.0, "r_long_endo": 17.0, "r_long_epi": 20.0}
LV_BASE_X = 5.0
#: biv_ellipsoid's Python defaults [cm] (its command line has others, e.g. a 3 mm RV wall).
BIV_SHAPE_CM = {"base_cut_z": 1.0, "box_size": 20.0, "rv_wall_thickness": 0.4,
                "lv_wall_thickness": 0.5, "rv_offset_x": 1.0, "lv_radius_x": 2.2,
                "lv_radius_y": 2.2, "lv_radius_z": 4.5, "rv_radius_x": 3.2, "rv_radius_y": 2.3,
                "rv_radius_z": 4.3}
BIV_SHAPE = {key: 10.0 * value for key, value in BIV_SHAPE_CM.items()}

#: Systole's part -> the package's physical surface name.
LV_PARTS = {"base": "BASE", "endocardium": "ENDO", "epicardium": "EPI"}
BIV_PARTS = {"base": "BASE", "lv_endocardium": "LV", "rv_endocardium": "RV", "epicardium": "EPI"}

DEFAULT_LV_PSIZE = 3.0
DEFAULT_BIV_PSIZE = 2.1


def boundary_names_line(parts):
    """The .prm line that maps Systole's part names to the mesh's physical names."""
    return "set Boundary names = " + "; ".join(f"{part}: {name}" for part, name in parts.items())


#: Element order, set by main(); _run_package raises the package's mesh to it before writing.
ELEMENT_ORDER = [1]


def _prepare_gmsh():
    """Initialise gmsh with pinned options before the package's own gmsh.initialize(), which
    is then a no-op (gmsh keeps these options until the package's gmsh.finalize()).

    No configuration files are read; one thread and the default random seed, so the same
    command writes the same bytes; format 4.1 ASCII (the defaults, pinned)."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    gmsh.option.setNumber("General.Verbosity", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)


def _run_package(build, path, **kwargs):
    import gmsh

    _prepare_gmsh()
    write = gmsh.write

    def write_at_order(file_name):
        # The package meshes at order 1 (it sets the option itself): raise the order on the
        # model it built, which puts the new nodes of the curved surfaces on them.
        if ELEMENT_ORDER[0] != 1:
            gmsh.model.mesh.setOrder(ELEMENT_ORDER[0])
        write(file_name)

    gmsh.write = write_at_order
    try:
        build(path, **kwargs)
    finally:
        gmsh.write = write
        if gmsh.isInitialized():
            gmsh.finalize()


def write_lv(path, psize):
    """Write the LV ellipsoid to @p path with point size @p psize [mm] at the base."""
    import cardiac_geometries_core as cgc

    _run_package(cgc.lv_ellipsoid, path, psize_ref=psize,
                 mu_apex_endo=-math.pi, mu_base_endo=-math.acos(LV_BASE_X / 17.0),
                 mu_apex_epi=-math.pi, mu_base_epi=-math.acos(LV_BASE_X / 20.0),
                 **LV_SHAPE)


def write_biv(path, psize):
    """Write the BiV ellipsoid to @p path with element size @p psize [mm]."""
    import cardiac_geometries_core as cgc

    _run_package(cgc.biv_ellipsoid, path, char_length=psize, **BIV_SHAPE)


def summarize(path):
    """Physical groups ({name: [tag, dim]}), number of tetrahedra and of their vertices, and
    the 3D element types found, read back with gmsh."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Verbosity", 0)
        gmsh.open(str(path))
        markers = {gmsh.model.getPhysicalName(dim, tag): [tag, dim]
                   for dim, tag in gmsh.model.getPhysicalGroups()}
        types, _, nodes = gmsh.model.mesh.getElements(3)
        n_tets, vertices = 0, set()
        for element_type, element_nodes in zip(types, nodes):
            if element_type in (4, 11):  # 4- or 10-node tetrahedron, corners first
                n_nodes = 4 if element_type == 4 else 10
                n_tets += len(element_nodes) // n_nodes
                corners = element_nodes.reshape(-1, n_nodes)[:, :4]
                vertices.update(corners.ravel().tolist())
        return markers, n_tets, len(vertices), [int(t) for t in types]
    finally:
        gmsh.finalize()


def package_versions():
    from importlib.metadata import version

    return {"cardiac-geometries-core": version("cardiac-geometries-core"),
            "gmsh": version("gmsh")}


def write_mesh(kind, out_dir, psize):
    """Write one mesh and its JSON, print its summary and .prm line; returns the .msh path."""
    writer, name, parts = {"lv": (write_lv, LV_FILE, LV_PARTS),
                           "biv": (write_biv, BIV_FILE, BIV_PARTS)}[kind]
    if ELEMENT_ORDER[0] == 2:
        name = name.replace(".msh", "_p2.msh")
    path = out_dir / name
    writer(path, psize)
    markers, n_tets, n_vertices, types = summarize(path)
    expected = [4] if ELEMENT_ORDER[0] == 1 else [11]
    if types != expected:
        raise RuntimeError(f"{path}: 3D element types {types}, expected {expected} only")
    missing = [name for name in parts.values() if markers.get(name, [0, 0])[1] != 2]
    if missing:
        raise RuntimeError(f"{path}: no physical surface {missing}; it has {sorted(markers)}")
    info = {"mesh": name, "psize_mm": psize, "element_order": ELEMENT_ORDER[0],
            "tetrahedra": n_tets, "vertices": n_vertices,
            "markers": markers, "systole_parts": parts,
            "boundary_names": boundary_names_line(parts), "written_by": package_versions()}
    path.with_suffix(".json").write_text(json.dumps(info, indent=1) + "\n")
    surfaces = ", ".join(f"{n} ({t})" for n, (t, d) in markers.items() if d == 2)
    print(f"{path}: {n_tets} tetrahedra, {n_vertices} vertices (psize {psize:g} mm)")
    print(f"  physical surfaces: {surfaces}")
    print(f"  {boundary_names_line(parts)}")
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog="\n\n".join(__doc__.split("\n\n")[1:]),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=Path("."), help="output folder")
    parser.add_argument("--lv-psize", type=float, default=DEFAULT_LV_PSIZE,
                        help="LV point size at the base [mm] (half of it at the apexes)")
    parser.add_argument("--biv-psize", type=float, default=DEFAULT_BIV_PSIZE,
                        help="BiV element size [mm]")
    parser.add_argument("--only", choices=["lv", "biv"], help="write one of the two meshes")
    parser.add_argument("--order", type=int, choices=[1, 2], default=1,
                        help="element order: 2 adds the mid-edge nodes (file name *_p2.msh)")
    args = parser.parse_args(argv)
    ELEMENT_ORDER[0] = args.order
    for size in (args.lv_psize, args.biv_psize):
        if not size > 0:
            parser.error(f"sizes must be positive, got {size}")
    args.out.mkdir(parents=True, exist_ok=True)
    for kind, psize in (("lv", args.lv_psize), ("biv", args.biv_psize)):
        if args.only in (None, kind):
            write_mesh(kind, args.out, psize)
    return 0


if __name__ == "__main__":
    sys.exit(main())
