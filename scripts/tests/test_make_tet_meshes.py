"""Tests of scripts/make_tet_meshes.py on coarse meshes, read back with an independent parser
of gmsh's format 4.1 (not gmsh): element types, names, orientation, the parts on their exact
surfaces, and cavity volumes by the divergence theorem against the smooth shapes."""

import json
import math
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("cardiac_geometries_core")

import make_tet_meshes as tet  # noqa: E402  (after the skip: it needs the package)
from systole_post.msh41 import Mesh, read_msh41  # noqa: E402,F401

LV_PSIZE = 3.0  # the shipped mesh's size (compared below)
BIV_PSIZE = 4.0

#: The smooth shapes in mm, from the package's documented defaults (not from the script).
LV_ENDO = ((0.0, 0.0, 0.0), (17.0, 7.0, 7.0))
LV_EPI = ((0.0, 0.0, 0.0), (20.0, 10.0, 10.0))
BIV_LV_ENDO = ((0.0, 0.0, 0.0), (17.0, 17.0, 40.0))
BIV_LV_EPI = ((0.0, 0.0, 0.0), (22.0, 22.0, 45.0))
BIV_RV_ENDO = ((10.0, 0.0, 0.0), (28.0, 19.0, 39.0))
BIV_RV_EPI = ((10.0, 0.0, 0.0), (32.0, 23.0, 43.0))


def level(ellipsoid, x):
    """The implicit function of an ellipsoid at the points @p x: 0 on it."""
    centre, radii = ellipsoid
    return (((x - np.array(centre)) / np.array(radii)) ** 2).sum(axis=1) - 1.0


def cap_volume(a, b, c, h):
    """Volume of the ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 <= 1 below the plane x = h."""
    return math.pi * b * c * ((h + a) - (h ** 3 + a ** 3) / (3.0 * a ** 2))


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    out = tmp_path_factory.mktemp("tet")
    assert tet.main(["--out", str(out), "--lv-psize", str(LV_PSIZE),
                     "--biv-psize", str(BIV_PSIZE)]) == 0
    return out


def test_same_bytes_when_rerun(meshes, tmp_path):
    assert tet.main(["--out", str(tmp_path), "--only", "lv", "--lv-psize", str(LV_PSIZE)]) == 0
    assert (tmp_path / tet.LV_FILE).read_bytes() == (meshes / tet.LV_FILE).read_bytes()
    assert not (tmp_path / tet.BIV_FILE).exists()


def test_shipped_lv_mesh_is_the_scripts(meshes):
    """meshes/lv_ellipsoid_tet.msh is what the script writes at its size, with the package
    versions recorded in its JSON (other versions may mesh differently)."""
    shipped = Path(__file__).resolve().parents[2] / "meshes" / tet.LV_FILE
    info = json.loads(shipped.with_suffix(".json").read_text())
    if info["written_by"] != tet.package_versions():
        pytest.skip(f"shipped with {info['written_by']}, installed {tet.package_versions()}")
    assert info["psize_mm"] == LV_PSIZE
    assert shipped.read_bytes() == (meshes / tet.LV_FILE).read_bytes()


@pytest.mark.parametrize("name, parts", [(tet.LV_FILE, {"base": "BASE", "endocardium": "ENDO",
                                                        "epicardium": "EPI"}),
                                         (tet.BIV_FILE, {"base": "BASE", "lv_endocardium": "LV",
                                                         "rv_endocardium": "RV",
                                                         "epicardium": "EPI"})])
def test_tetrahedra_names_and_json(meshes, name, parts):
    mesh = Mesh(meshes / name)
    assert mesh.types_3d == {4}  # linear tetrahedra only
    assert {n for n, (dim, _) in mesh.names.items() if dim == 2} == set(parts.values())
    volumes = mesh.tet_volumes()
    assert volumes.min() > 0.0
    # Every boundary face of the tetrahedra is in exactly one physical surface.
    tagged = Counter(tuple(sorted(t)) for triangles in mesh.surfaces.values() for t in triangles)
    assert max(tagged.values()) == 1
    assert set(tagged) == set(mesh.boundary_faces())
    info = json.loads((meshes / name).with_suffix(".json").read_text())
    assert info["tetrahedra"] == len(mesh.tets)
    assert info["systole_parts"] == parts
    assert {n: tuple(v[::-1]) for n, v in info["markers"].items()} == mesh.names
    assert info["boundary_names"] == "set Boundary names = " + "; ".join(
        f"{part}: {surface}" for part, surface in parts.items())


def test_lv_shape_and_cavity(meshes):
    mesh = Mesh(meshes / tet.LV_FILE)
    x = mesh.points
    assert x[:, 0].min() == pytest.approx(-20.0, abs=1e-9)  # the epicardial apex
    assert x[:, 0].max() == pytest.approx(5.0, abs=1e-9)    # the base plane
    radius = np.hypot(x[:, 1], x[:, 2])
    assert radius.max() <= 10.0 + 1e-9
    assert radius.max() > 10.0 - 0.5  # faceted: within the chord error
    for surface, on in (("ENDO", lambda p: level(LV_ENDO, p)),
                        ("EPI", lambda p: level(LV_EPI, p)), ("BASE", lambda p: p[:, 0] - 5.0)):
        points = x[np.unique(mesh.surfaces[surface])]
        np.testing.assert_allclose(on(points), 0.0, atol=1e-6, err_msg=surface)
    np.testing.assert_allclose(mesh.open_edges("ENDO")[:, 0], 5.0, atol=1e-9)
    exact = cap_volume(17.0, 7.0, 7.0, 5.0)
    assert exact == pytest.approx(2492.13, abs=0.01)
    volume = mesh.cavity_volume("ENDO", np.array([5.0, 0.0, 0.0]))
    assert volume == pytest.approx(exact, rel=0.03)
    assert volume < exact  # the facets are chords of the convex surface


def test_biv_parts_and_lv_cavity(meshes):
    mesh = Mesh(meshes / tet.BIV_FILE)
    x = mesh.points
    assert x[:, 2].min() == pytest.approx(-45.0, abs=1e-6)  # the LV epicardial apex
    assert x[:, 2].max() == pytest.approx(10.0, abs=1e-9)   # the base plane
    tol = 1e-6
    points = {name: x[np.unique(triangles)] for name, triangles in mesh.surfaces.items()}
    np.testing.assert_allclose(points["BASE"][:, 2], 10.0, atol=1e-9)
    np.testing.assert_allclose(level(BIV_LV_ENDO, points["LV"]), 0.0, atol=tol)
    # RV: the RV cavity ellipsoid, and the septum on the LV outer ellipsoid inside it.
    rv = points["RV"]
    on_rv, on_septum = (abs(level(BIV_RV_ENDO, rv)) < tol, abs(level(BIV_LV_EPI, rv)) < tol)
    assert np.all(on_rv | on_septum)
    assert np.all(level(BIV_RV_ENDO, rv[on_septum]) < tol)
    assert on_rv.sum() > 0 and on_septum.sum() > 0
    # EPI: the two outer ellipsoids, each outside the other.
    epi = points["EPI"]
    on_lv, on_rv = abs(level(BIV_LV_EPI, epi)) < tol, abs(level(BIV_RV_EPI, epi)) < tol
    assert np.all(on_lv | on_rv)
    assert np.all(level(BIV_RV_EPI, epi[on_lv]) > -tol)
    assert np.all(level(BIV_LV_EPI, epi[on_rv]) > -tol)
    exact = cap_volume(40.0, 17.0, 17.0, 10.0)  # the LV cavity, long axis z
    volume = mesh.cavity_volume("LV", np.array([0.0, 0.0, 10.0]))
    assert volume == pytest.approx(exact, rel=0.03)
    assert volume < exact
    # The RV cavity (inside the RV cavity ellipsoid, outside the LV outer one, below the
    # base) by the midpoint rule on a 0.5 mm grid: 18 340 mm^3 (18 344 on a 0.25 mm grid).
    h = 0.5
    grid = np.stack(np.meshgrid(np.arange(-18 + h / 2, 38, h), np.arange(-19 + h / 2, 19, h),
                                np.arange(-39 + h / 2, 10, h), indexing="ij"), axis=-1)
    grid = grid.reshape(-1, 3)
    in_rv = (level(BIV_RV_ENDO, grid) < 0) & (level(BIV_LV_EPI, grid) > 0)
    assert mesh.cavity_volume("RV", np.array([0.0, 0.0, 10.0])) == pytest.approx(
        in_rv.sum() * h ** 3, rel=0.03)
