"""Tests of scripts/make_synthetic_dti.py: the .vti it writes and the tensors in it."""

import base64
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import make_synthetic_dti as dti


def read_vti(path):
    """(root element, origin, spacing, dims (nx, ny, nz), tensors (nz, ny, nx, 3, 3))."""
    root = ET.parse(path).getroot()  # raises on malformed XML
    image = root.find("ImageData")
    extent = [int(value) for value in image.get("WholeExtent").split()]
    dims = [extent[1] - extent[0] + 1, extent[3] - extent[2] + 1, extent[5] - extent[4] + 1]
    origin = np.array([float(value) for value in image.get("Origin").split()])
    spacing = np.array([float(value) for value in image.get("Spacing").split()])
    array = image.find("Piece/PointData/DataArray")
    assert array.get("NumberOfComponents") == "6"
    assert image.find("Piece/PointData").get("Tensors") == array.get("Name")
    text = array.text.strip()
    if array.get("format") == "binary":
        header = base64.b64decode(text[:12])  # one UInt64: 8 bytes -> 12 characters
        n_bytes = int(np.frombuffer(header, dtype="<u8")[0])
        values = np.frombuffer(base64.b64decode(text[12:]), dtype="<f8")
        assert values.nbytes == n_bytes
    else:
        values = np.array(text.split(), dtype=float)
    c = values.reshape(dims[2], dims[1], dims[0], 6)
    tensors = np.empty(c.shape[:3] + (3, 3))
    for (i, j), k in {(0, 0): 0, (1, 1): 1, (2, 2): 2, (0, 1): 3, (1, 2): 4, (0, 2): 5}.items():
        tensors[..., i, j] = c[..., k]
        tensors[..., j, i] = c[..., k]
    return root, origin, spacing, dims, tensors


@pytest.fixture
def write(tmp_path):
    """``write(*options)`` runs the script into tmp_path and returns read_vti of the file."""

    def run(*options, name="dti.vti"):
        path = tmp_path / name
        assert dti.main(["--output", str(path), "--spacing", "1.0", *options]) == 0
        return read_vti(path)

    return run


@pytest.mark.parametrize("data_format", ["binary", "ascii"])
def test_writes_well_formed_vti_with_spd_tensors_of_the_requested_fa(write, data_format):
    root, origin, spacing, dims, tensors = write("--fa", "0.35", "--format", data_format)
    assert root.tag == "VTKFile" and root.get("type") == "ImageData"
    assert root.get("byte_order") == "LittleEndian"
    np.testing.assert_allclose(spacing, 1.0)
    # The box covers the epicardium (r_s = 10, r_l = 20) and the base (z = 5) with a margin.
    assert origin[0] <= -10 and origin[2] <= -20
    assert origin[2] + spacing[2] * (dims[2] - 1) >= 5
    np.testing.assert_array_equal(tensors, np.swapaxes(tensors, -1, -2))
    eigenvalues = np.linalg.eigvalsh(tensors)
    assert np.all(eigenvalues > 0)
    np.testing.assert_allclose(dti.fractional_anisotropy(eigenvalues), 0.35, atol=1e-12)
    np.testing.assert_allclose(eigenvalues.mean(axis=-1), 1e-3, rtol=1e-12)


def test_principal_direction_is_the_analytic_helix_fibre(write):
    _, origin, spacing, dims, tensors = write("--helix-endo", "90", "--helix-epi", "-90")
    nx, ny, nz = dims
    zz, yy, xx = np.meshgrid(*(origin[d] + spacing[d] * np.arange(dims[d]) for d in (2, 1, 0)),
                             indexing="ij")
    points = np.stack([xx, yy, zz], axis=-1)
    f, s, n = dti.helix_frames(points, dti.LAND_SHAPE, np.pi / 2, -np.pi / 2, 0.0)
    t = dti.transmural_coordinate(points, dti.LAND_SHAPE)
    wall = (t > 0) & (t < 1) & (points[..., 2] < 5)
    assert wall.sum() > 100
    _, vectors = np.linalg.eigh(tensors[wall])
    assert np.all(np.abs(np.einsum("ij,ij->i", vectors[..., 2], f[wall])) > 1 - 1e-10)
    assert np.all(np.abs(np.einsum("ij,ij->i", vectors[..., 1], s[wall])) > 1 - 1e-10)
    # Frames are orthonormal and right-handed; the endocardial fibre is meridional (90 deg).
    np.testing.assert_allclose(np.einsum("...i,...i", f, s), 0, atol=1e-12)
    np.testing.assert_allclose(np.cross(f, s), n, atol=1e-12)


def test_helix_frame_matches_the_cpp_rule_at_known_points():
    # At v = 0 (x = r_s sin u < 0, y = 0) on the equator, AnalyticHelix has e_v = (0, -1, 0),
    # e_u = e_z and the outward normal -e_x: alpha = 0 gives f = e_v, alpha = 90 deg f = e_u.
    shape = dti.LAND_SHAPE
    u, t = -np.pi / 2, 0.5
    r_s = shape["endo_short"] + t * (shape["epi_short"] - shape["endo_short"])
    point = np.array([[r_s * np.sin(u), 0.0, 0.0]])
    np.testing.assert_allclose(dti.transmural_coordinate(point, shape), t, atol=1e-12)
    f, s, _ = dti.helix_frames(point, shape, 0.0, 0.0, 0.0)
    np.testing.assert_allclose(f[0], [0.0, -1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(s[0], [-1.0, 0.0, 0.0], atol=1e-12)  # outward normal
    f, _, _ = dti.helix_frames(point, shape, np.pi / 2, np.pi / 2, 0.0)
    np.testing.assert_allclose(f[0], [0.0, 0.0, 1.0], atol=1e-12)  # towards the base


def test_noise_is_deterministic_and_keeps_tensors_spd(write):
    _, _, _, _, a = write("--noise", "0.2", "--seed", "7", name="a.vti")
    _, _, _, _, b = write("--noise", "0.2", "--seed", "7", name="b.vti")
    _, _, _, _, c = write("--noise", "0.2", "--seed", "8", name="c.vti")
    _, _, _, _, clean = write(name="clean.vti")
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    assert np.all(np.linalg.eigvalsh(a) > 0)
    fa = dti.fractional_anisotropy(np.linalg.eigvalsh(a))
    assert abs(fa.mean() - 0.4) < 0.1 and fa.std() > 0.01  # noise adds some anisotropy
    assert not np.allclose(a, clean)


@pytest.mark.parametrize("outside, expected", [("isotropic", "identity"), ("background", "zero")])
def test_outside_voxels(write, outside, expected):
    _, origin, spacing, dims, tensors = write("--outside", outside)
    corner = tensors[0, 0, 0]  # far from the wall
    if expected == "identity":
        np.testing.assert_allclose(corner, 1e-3 * np.eye(3))
    else:
        np.testing.assert_array_equal(corner, 0.0)


def test_extrapolate_continues_the_helix_angle_beyond_the_wall(write):
    _, origin, spacing, dims, clamped = write("--helix-endo", "60", "--helix-epi", "-60",
                                              name="clamped.vti")
    _, _, _, _, extended = write("--helix-endo", "60", "--helix-epi", "-60",
                                 "--outside", "extrapolate", name="extended.vti")
    zz, yy, xx = np.meshgrid(*(origin[d] + spacing[d] * np.arange(dims[d]) for d in (2, 1, 0)),
                             indexing="ij")
    points = np.stack([xx, yy, zz], axis=-1)
    t = dti.transmural_coordinate(points, dti.LAND_SHAPE)
    wall = (t >= 0) & (t <= 1) & (points[..., 2] <= 5)
    np.testing.assert_array_equal(extended[wall], clamped[wall])
    # Just outside the epicardium (t = 1 + 1/3: 1 mm off on the equator) the fibre follows
    # alpha(t) = 60 - 120 t = -100 degrees, not the surface's -60.
    point = np.array([[-11.0, 0.0, 0.0]])
    t_out = dti.transmural_coordinate(point, dti.LAND_SHAPE)[0]
    degree = np.pi / 180
    f, _, _ = dti.helix_frames(point, dti.LAND_SHAPE, 60 * degree, -60 * degree, 0.0)
    i = np.argmin(np.linalg.norm(points - point[0], axis=-1))
    _, vectors = np.linalg.eigh(extended.reshape(-1, 3, 3)[i])
    assert t_out > 1 and abs(vectors[:, 2] @ f[0]) > 1 - 1e-10
    assert np.all(np.linalg.eigvalsh(extended) > 0)


def test_eigenvalues_for_fa_and_argument_checks(tmp_path):
    for fa in (0.05, 0.3, 0.9):
        eigenvalues = dti.eigenvalues_for_fa(fa, 2.0)
        assert dti.fractional_anisotropy(eigenvalues) == pytest.approx(fa, abs=1e-12)
        assert eigenvalues.mean() == pytest.approx(2.0)
        assert eigenvalues[0] > eigenvalues[1] > eigenvalues[2] > 0
    with pytest.raises(SystemExit):
        dti.main(["--output", str(tmp_path / "x.vti"), "--fa", "1.5"])
    with pytest.raises(SystemExit):
        dti.main(["--output", str(tmp_path / "x.vti"), "--spacing", "0"])
