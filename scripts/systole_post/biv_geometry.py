"""The idealized biventricular shape (scripts/make_biv_mesh.py's docstring describes it), in mm:
the ellipsoids (centre, semi-axes) of the LV and RV cavities, the wall thicknesses that grow
them into the epicardial ellipsoids, and the base plane. Shared by the mesh generators and
systole_post.biv_shape (the exact cavity volumes)."""

LV_ENDO = ((0.0, 0.0, 0.0), (20.0, 18.0, 32.5))
LV_WALL = 5.0
RV_ENDO = ((25.0, 0.0, 0.0), (19.0, 25.0, 30.0))
RV_WALL = 4.0
BASE_Z = 25.0


def grown(ellipsoid, thickness):
    centre, radii = ellipsoid
    return centre, tuple(r + thickness for r in radii)
