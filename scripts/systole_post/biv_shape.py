"""The exact cavity volumes of the idealized biventricular shape (systole_post.biv_geometry).

LV: the truncated ellipsoid, in closed form. RV: the RV cavity ellipsoid minus the LV wall
ellipsoid, below the base plane, by nested adaptive quadrature (scipy) of the closed-form
length of the cavity along x at each (y, z).
"""

import math

import numpy as np
import warnings

from scipy import integrate

from systole_post.biv_geometry import BASE_Z, LV_ENDO, LV_WALL, RV_ENDO, grown

# The kinks of the integrand where the chords meet: quad warns, the value holds (a 0.2 mm
# voxel count agrees to 3e-5).
warnings.filterwarnings("ignore", category=integrate.IntegrationWarning)



def lv_cavity_volume(base_z=BASE_Z) -> float:
    """pi a b (z_b + c - (z_b^3 + c^3) / (3 c^2)): the ellipsoid below z = z_b [mm^3]."""
    (_, (a, b, c)) = LV_ENDO
    z = base_z
    return math.pi * a * b * (z + c - (z**3 + c**3) / (3 * c * c))


def _half_width(ellipsoid, y, z):
    """Half the chord of the ellipsoid along x at (y, z) (0 outside) and its centre x."""
    (centre, radii) = ellipsoid
    s = 1.0 - ((y - centre[1]) / radii[1]) ** 2 - ((z - centre[2]) / radii[2]) ** 2
    return (radii[0] * math.sqrt(s) if s > 0 else 0.0), centre[0]


def rv_cavity_volume(tolerance=1e-8, base_z=BASE_Z, lv_thickness=LV_WALL) -> float:
    """The RV cavity: inside the RV cavity ellipsoid, outside the LV wall ellipsoid, z < z_b
    (the base plane @p base_z and the LV wall's thickness @p lv_thickness in mm, as the mesh
    generator's --base-z and --lv-wall)."""
    lv_wall = grown(LV_ENDO, lv_thickness)
    (centre, radii) = RV_ENDO

    def length(y, z):
        h_rv, x_rv = _half_width(RV_ENDO, y, z)
        h_lv, x_lv = _half_width(lv_wall, y, z)
        overlap = max(0.0, min(x_rv + h_rv, x_lv + h_lv) - max(x_rv - h_rv, x_lv - h_lv))
        return 2 * h_rv - (overlap if h_lv > 0 else 0.0)

    def slice_area(z):
        s = 1.0 - ((z - centre[2]) / radii[2]) ** 2
        if s <= 0:
            return 0.0
        y_max = radii[1] * math.sqrt(s)
        # The LV wall's edge in y at this z: a kink of the integrand.
        lv = lv_wall[1]
        s_lv = 1.0 - (z / lv[2]) ** 2
        points = [lv[1] * math.sqrt(s_lv)] if s_lv > 0 else None
        return integrate.quad(lambda y: length(y, z), -y_max, y_max, points=points and
                              [-points[0], points[0]], epsabs=0, epsrel=tolerance, limit=200)[0]

    z_min = centre[2] - radii[2]
    lv_apex = -lv_wall[1][2]
    breaks = [lv_apex] if z_min < lv_apex < base_z else None
    return integrate.quad(slice_area, z_min, base_z, points=breaks, epsabs=0, epsrel=tolerance,
                          limit=200)[0]


if __name__ == "__main__":
    print(f"LV cavity {lv_cavity_volume():.6f} mm^3, RV cavity {rv_cavity_volume():.6f} mm^3")
