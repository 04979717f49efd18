"""systole_post.biv_shape's exact cavity volumes for another cut and LV wall (the mesh
generator's --base-z and --lv-wall): the closed-form LV against a quadrature of its slices, the
defaults unchanged, and the RV's growing with the cut and shrinking with a thicker LV wall."""

import math
import warnings

import pytest
from scipy import integrate

from systole_post import biv_shape
from systole_post.biv_geometry import BASE_Z, LV_ENDO, LV_WALL


@pytest.mark.parametrize("base_z", [25.0, 12.0, 5.0])
def test_lv_cavity_volume_against_slices(base_z):
    (_, (a, b, c)) = LV_ENDO
    slices = integrate.quad(lambda z: math.pi * a * b * (1 - (z / c) ** 2), -c, base_z)[0]
    assert biv_shape.lv_cavity_volume(base_z) == pytest.approx(slices, rel=1e-12)


def test_rv_cavity_volume_defaults_and_trends():
    # quad warns at the kinks of the integrand; the value holds (biv_shape's docstring).
    warnings.simplefilter("ignore", integrate.IntegrationWarning)
    default = biv_shape.rv_cavity_volume(tolerance=1e-6)
    assert biv_shape.rv_cavity_volume(tolerance=1e-6, base_z=BASE_Z,
                                      lv_thickness=LV_WALL) == default
    lower = biv_shape.rv_cavity_volume(tolerance=1e-6, base_z=5.0)
    thicker = biv_shape.rv_cavity_volume(tolerance=1e-6, base_z=5.0, lv_thickness=7.0)
    assert lower < default
    assert thicker < lower
    # A 2 mm thicker LV wall takes at most the RV cavity's share of a 2 mm shell: well
    # under half of it.
    assert thicker > 0.5 * lower
