#!/usr/bin/env python3
"""Write a synthetic diffusion-tensor image (.vti) of the truncated-ellipsoid LV.

The fibre frame is the analytic helix rule of Land et al. 2015, problem 3, as implemented by
``Fibres::AnalyticHelix`` (src/fibres/fibre_field.cc) on the ventricle of
``Geometry::LVShape`` (src/geometry/ellipsoid.h): a point with transmural coordinate t
(0 endocardium, 1 epicardium; the radii vary linearly, r(t) = r_endo + t (r_epi - r_endo))
and ellipsoidal coordinates (u, v) has

    f = sin(alpha) e_u + cos(alpha) e_v,   alpha(t) = alpha_endo + (alpha_epi - alpha_endo) t,

e_u (meridional, apex to base) and e_v (circumferential) the unit tangents of its spheroid;
the sheet s is the outward wall normal e_v x e_u rotated by the sheet angle beta about f,
and n = f x s. Every voxel gets D = l1 f f^T + l2 s s^T + l3 n n^T, with eigenvalues in the
geometric ratio 1 : q : q^2 (equally spaced logarithms, so all three are distinct) and q
chosen so that the fractional anisotropy equals --fa; their mean is --mean-diffusivity.

Voxels outside the wall (t < 0, t > 1 or above the base plane) get, by --outside:
  nearest-wall  the frame of the nearest wall surface: t clamped to [0, 1] (default);
  extrapolate   the rule continued beyond the wall: the voxel's own t, not clamped, so
                alpha keeps varying linearly. Interpolation at points on the endo- and
                epicardium then sees the linear profile on both sides (with nearest-wall the
                voxels beyond the surface hold the surface angle, and interpolation there is
                biased by a fraction of the helix change over one voxel: 3-5 degrees at
                0.5 mm on the Land ventricle). For checking an importer at the surfaces;
  isotropic     D = mean diffusivity * I (FA 0: the importer rejects points there);
  background    D = 0 (no data: the importer treats such voxels as outside).

--noise sigma adds sigma * (Z + Z^T) / 2 to log D (Z with independent standard normal
entries, drawn from numpy's default_rng(--seed)), so every tensor stays symmetric positive
definite and the same seed gives the same file.

Output: a VTK XML image file (<VTKFile type="ImageData">, read by VTK's
vtkXMLImageDataReader) with one point-data array of 6 components in VTK's symmetric order
xx, yy, zz, xy, yz, xz, marked as the tensor attribute; inline base64 binary (default) or
ASCII. Lengths in mm; the tensor unit is that of --mean-diffusivity (mm^2/s by default).

Example:
    scripts/make_synthetic_dti.py --fa 0.4 --noise 0.05 --spacing 0.5 --output lv_dti.vti
"""

import argparse
import base64
import sys
from pathlib import Path

import numpy as np

#: The Land et al. 2015 ventricle (Geometry::LVShape defaults), mm.
LAND_SHAPE = {"endo_short": 7.0, "endo_long": 17.0, "epi_short": 10.0, "epi_long": 20.0,
              "base_height": 5.0}


def transmural_coordinate(points, shape):
    """t with rho^2 / r_s(t)^2 + z^2 / r_l(t)^2 = 1 for points (..., 3), by bisection."""
    rho2 = points[..., 0] ** 2 + points[..., 1] ** 2
    z2 = points[..., 2] ** 2
    d_short = shape["epi_short"] - shape["endo_short"]
    d_long = shape["epi_long"] - shape["endo_long"]

    def g(t):
        r_s = shape["endo_short"] + t * d_short
        r_l = shape["endo_long"] + t * d_long
        return rho2 / r_s ** 2 + z2 / r_l ** 2 - 1.0

    # g decreases in t while both radii are positive.
    lowest = -0.99 * min(shape["endo_short"] / d_short, shape["endo_long"] / d_long)
    lo = np.full(rho2.shape, lowest)
    hi = np.full(rho2.shape, 1.0)
    while np.any(g(hi) > 0.0):
        hi = np.where(g(hi) > 0.0, 2.0 * hi + 1.0, hi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        above = g(mid) > 0.0
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    return 0.5 * (lo + hi)


def helix_frames(points, shape, alpha_endo, alpha_epi, beta, t=None):
    """The analytic helix frame (f, s, n), each (..., 3), at points (..., 3).

    Angles in radians. t (default: the transmural coordinate of the points) selects the
    spheroid whose tangents are used; pass a clamped t for the nearest-wall frame.
    """
    if t is None:
        t = transmural_coordinate(points, shape)
    r_s = shape["endo_short"] + t * (shape["epi_short"] - shape["endo_short"])
    r_l = shape["endo_long"] + t * (shape["epi_long"] - shape["endo_long"])
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    # The axis has no circumferential direction: step off it (as AnalyticHelix does).
    x = np.where(np.hypot(x, y) < 1e-8 * r_s, 1e-8 * r_s, x)
    cos_u = np.clip(z / r_l, -1.0 + 1e-12, 1.0 - 1e-12)
    sin_u = -np.sqrt(1.0 - cos_u ** 2)  # u in (-pi, 0)
    v = np.arctan2(-y, -x)
    e_u = np.stack([r_s * cos_u * np.cos(v), r_s * cos_u * np.sin(v), -r_l * sin_u], axis=-1)
    e_u /= np.linalg.norm(e_u, axis=-1, keepdims=True)
    # r_s sin(u) (-sin v, cos v, 0), normalized (sin u < 0).
    e_v = np.stack([np.sin(v), -np.cos(v), np.zeros_like(v)], axis=-1)
    alpha = (alpha_endo + (alpha_epi - alpha_endo) * t)[..., None]
    f = np.sin(alpha) * e_u + np.cos(alpha) * e_v
    normal = np.cross(e_v, e_u)
    side = np.cross(f, normal)
    s = np.cos(beta) * normal + np.sin(beta) * side
    n = np.cross(f, s)
    return f, s, n


def fractional_anisotropy(eigenvalues):
    """FA of eigenvalues (..., 3)."""
    lam = np.asarray(eigenvalues, dtype=float)
    mean = lam.mean(axis=-1, keepdims=True)
    return np.sqrt(1.5) * np.linalg.norm(lam - mean, axis=-1) / np.linalg.norm(lam, axis=-1)


def eigenvalues_for_fa(fa, mean_diffusivity=1.0e-3):
    """Eigenvalues l1 > l2 > l3 in the ratio 1 : q : q^2 with FA fa and mean mean_diffusivity."""
    if not 0.0 < fa < 1.0:
        raise ValueError(f"the fractional anisotropy must lie in (0, 1), not {fa}")

    def fa_of(q):
        return fractional_anisotropy([1.0, q, q * q])

    lo, hi = 0.0, 1.0  # fa_of decreases from 1 (q = 0) to 0 (q = 1)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if fa_of(mid) > fa:
            lo = mid
        else:
            hi = mid
    q = 0.5 * (lo + hi)
    ratios = np.array([1.0, q, q * q])
    return 3.0 * mean_diffusivity * ratios / ratios.sum()


def tensors_from_frames(f, s, n, eigenvalues):
    """D = l1 f f^T + l2 s s^T + l3 n n^T, shape (..., 3, 3)."""
    l1, l2, l3 = eigenvalues
    outer = lambda a: a[..., :, None] * a[..., None, :]  # noqa: E731
    return l1 * outer(f) + l2 * outer(s) + l3 * outer(n)


def add_log_noise(tensors, sigma, seed):
    """exp(log D + sigma (Z + Z^T) / 2) for SPD tensors (..., 3, 3); deterministic in seed."""
    if sigma == 0.0:
        return tensors
    rng = np.random.default_rng(seed)
    z = rng.standard_normal(tensors.shape)
    lam, vec = np.linalg.eigh(tensors)
    log_d = (vec * np.log(lam)[..., None, :]) @ np.swapaxes(vec, -1, -2)
    log_d += 0.5 * sigma * (z + np.swapaxes(z, -1, -2))
    lam, vec = np.linalg.eigh(log_d)
    return (vec * np.exp(lam)[..., None, :]) @ np.swapaxes(vec, -1, -2)


def to_vtk_symmetric(tensors):
    """(..., 3, 3) -> (..., 6) in VTK's order xx, yy, zz, xy, yz, xz."""
    return np.stack([tensors[..., 0, 0], tensors[..., 1, 1], tensors[..., 2, 2],
                     tensors[..., 0, 1], tensors[..., 1, 2], tensors[..., 0, 2]], axis=-1)


def encode_binary(values):
    """Inline VTK binary: base64 of the UInt64 byte count, then base64 of the data."""
    data = np.ascontiguousarray(values, dtype="<f8").tobytes()
    header = np.array([len(data)], dtype="<u8").tobytes()
    return (base64.b64encode(header) + base64.b64encode(data)).decode("ascii")


def vti_text(origin, spacing, components, name="tensors", data_format="binary"):
    """The .vti text of a point-data tensor array components (nz, ny, nx, 6), x fastest."""
    nz, ny, nx, n_components = components.shape
    extent = f"0 {nx - 1} 0 {ny - 1} 0 {nz - 1}"
    if data_format == "binary":
        data = encode_binary(components.reshape(-1))
    elif data_format == "ascii":
        rows = components.reshape(-1, n_components)
        data = "\n".join(" ".join(f"{value:.17g}" for value in row) for row in rows)
    else:
        raise ValueError(f"unknown format {data_format!r} (binary or ascii)")
    origin_text = " ".join(f"{value:.17g}" for value in origin)
    spacing_text = " ".join(f"{value:.17g}" for value in spacing)
    return (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" '
        'header_type="UInt64">\n'
        f'  <ImageData WholeExtent="{extent}" Origin="{origin_text}" Spacing="{spacing_text}" '
        'Direction="1 0 0 0 1 0 0 0 1">\n'
        f'    <Piece Extent="{extent}">\n'
        f'      <PointData Tensors="{name}">\n'
        f'        <DataArray type="Float64" Name="{name}" NumberOfComponents="{n_components}" '
        f'format="{data_format}">\n'
        f"{data}\n"
        "        </DataArray>\n"
        "      </PointData>\n"
        "      <CellData>\n"
        "      </CellData>\n"
        "    </Piece>\n"
        "  </ImageData>\n"
        "</VTKFile>\n")


def synthetic_lv_tensors(shape, spacing, margin, fa, mean_diffusivity, alpha_endo, alpha_epi,
                         beta, noise, seed, outside):
    """Grid origin (3,), spacing (3,) and tensors (nz, ny, nx, 3, 3) over the box of the LV.

    Angles in degrees.
    """
    lower = np.array([-shape["epi_short"] - margin, -shape["epi_short"] - margin,
                      -shape["epi_long"] - margin])
    upper = np.array([shape["epi_short"] + margin, shape["epi_short"] + margin,
                      shape["base_height"] + margin])
    counts = np.ceil((upper - lower) / spacing - 1e-9).astype(int) + 1
    axes = [lower[d] + spacing * np.arange(counts[d]) for d in range(3)]
    zz, yy, xx = np.meshgrid(axes[2], axes[1], axes[0], indexing="ij")
    points = np.stack([xx, yy, zz], axis=-1)

    t = transmural_coordinate(points, shape)
    in_wall = (t >= 0.0) & (t <= 1.0) & (points[..., 2] <= shape["base_height"])
    degree = np.pi / 180.0
    f, s, n = helix_frames(points, shape, alpha_endo * degree, alpha_epi * degree,
                           beta * degree, t=t if outside == "extrapolate" else np.clip(t, 0.0, 1.0))
    tensors = tensors_from_frames(f, s, n, eigenvalues_for_fa(fa, mean_diffusivity))
    tensors = add_log_noise(tensors, noise, seed)
    if outside == "isotropic":
        tensors[~in_wall] = mean_diffusivity * np.eye(3)
    elif outside == "background":
        tensors[~in_wall] = 0.0
    elif outside not in ("nearest-wall", "extrapolate"):
        raise ValueError(f"unknown --outside {outside!r}")
    return lower, np.full(3, spacing), tensors


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("--output", "-o", required=True, type=Path, help="the .vti file to write")
    parser.add_argument("--fa", type=float, default=0.4, help="fractional anisotropy (0, 1)")
    parser.add_argument("--mean-diffusivity", type=float, default=1.0e-3,
                        help="mean eigenvalue (default 1e-3, mm^2/s)")
    parser.add_argument("--noise", type=float, default=0.0,
                        help="sigma of the symmetric perturbation of log D (default 0)")
    parser.add_argument("--seed", type=int, default=42, help="random seed of the noise")
    parser.add_argument("--spacing", type=float, default=0.5, help="voxel size, mm")
    parser.add_argument("--margin", type=float, default=1.0,
                        help="extra space around the epicardium and above the base, mm")
    parser.add_argument("--helix-endo", type=float, default=60.0,
                        help="helix angle at the endocardium, degrees")
    parser.add_argument("--helix-epi", type=float, default=-60.0,
                        help="helix angle at the epicardium, degrees")
    parser.add_argument("--sheet-angle", type=float, default=0.0, help="sheet angle, degrees")
    parser.add_argument("--outside",
                        choices=["nearest-wall", "extrapolate", "isotropic", "background"],
                        default="nearest-wall", help="tensors of voxels outside the wall")
    parser.add_argument("--format", choices=["binary", "ascii"], default="binary",
                        help="DataArray format (inline base64 binary or ASCII)")
    parser.add_argument("--array-name", default="tensors", help="name of the tensor array")
    for key, value in LAND_SHAPE.items():
        option = "--" + key.replace("_", "-") + ("-radius" if key != "base_height" else "")
        parser.add_argument(option, dest=key, type=float, default=value,
                            help=f"mm (default {value}: Land et al. 2015)")
    args = parser.parse_args(argv)
    if args.spacing <= 0.0:
        parser.error("--spacing must be positive")
    if not 0.0 < args.fa < 1.0:
        parser.error("--fa must lie in (0, 1)")
    if args.noise < 0.0:
        parser.error("--noise must not be negative")
    if not (0.0 < args.endo_short < args.epi_short and 0.0 < args.endo_long < args.epi_long
            and abs(args.base_height) < args.endo_long):
        parser.error("the radii must satisfy 0 < endo < epi and |base height| < endo long")
    return args


def main(argv=None):
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    shape = {key: getattr(args, key) for key in LAND_SHAPE}
    origin, spacing, tensors = synthetic_lv_tensors(
        shape, args.spacing, args.margin, args.fa, args.mean_diffusivity, args.helix_endo,
        args.helix_epi, args.sheet_angle, args.noise, args.seed, args.outside)
    text = vti_text(origin, spacing, to_vtk_symmetric(tensors), args.array_name, args.format)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(text, encoding="ascii")
    nz, ny, nx = tensors.shape[:3]
    print(f"{args.output}: {nx} x {ny} x {nz} voxels, spacing {args.spacing} mm, FA {args.fa}, "
          f"noise {args.noise}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
