#pragma once

#include <deal.II/base/point.h>
#include <deal.II/grid/manifold.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>

#include "geometry/boundary_names.h"

#include <limits>
#include <memory>

namespace systole::Geometry
{
  /// Shape of the idealized left ventricle: a thick-walled truncated prolate
  /// ellipsoid (Land et al. 2015, Proc. R. Soc. A 471:20150641, problem 2). A
  /// point of the wall with transmural coordinate t in [0, 1] and polar angle
  /// theta (from the apex) and azimuth v is
  ///   x = r_s(t) sin(theta) cos(v),  y = r_s(t) sin(theta) sin(v),  z =
  ///   -r_l(t) cos(theta),
  /// with radii varying linearly through the wall, r(t) = r_endo + t (r_epi -
  /// r_endo). The base is the plane z = base_height. Lengths in mm.
  ///
  /// Two generalisations, both off by default:
  /// - each surface cut at its own height (epi_base_height): the endocardium
  ///   at z = base_height, the epicardium at z = epi_base_height, and the
  ///   base the ruled (conical) surface of the straight segments between the
  ///   two cut rings in every meridional plane (Aróstica et al. 2025);
  /// - the long axis along x (long_axis_x): the whole wall turned by the
  ///   rotation (x, y, z) -> (z, x, y), so the apex points to -x and the
  ///   formulas above hold for the generator's frame (to_generator_frame).
  struct LVShape
  {
    double endo_short_radius = 7.0;  ///< r_s at the endocardium [mm]
    double endo_long_radius  = 17.0; ///< r_l at the endocardium [mm]
    double epi_short_radius  = 10.0; ///< r_s at the epicardium [mm]
    double epi_long_radius   = 20.0; ///< r_l at the epicardium [mm]
    /// Height of the (endocardial) cut along the long axis [mm].
    double base_height = 5.0;
    /// Height of the epicardial cut [mm]; NaN: base_height (a flat base).
    double epi_base_height = std::numeric_limits<double>::quiet_NaN();
    /// false: long axis z (apex at -z); true: long axis x (apex at -x).
    bool long_axis_x = false;

    /// The monoventricular geometry of Aróstica et al. 2025 (CMAME
    /// 435:117485) in its own frame: endocardium r_s = 25, r_l = 90 mm cut
    /// at mu_b = -arccos(5/17) (x = 90 * 5/17 = 26.47 mm), epicardium
    /// r_s = 35, r_l = 97 mm cut at mu_b = -arccos(5/20) (x = 24.25 mm),
    /// long axis x.
    static LVShape
    arostica();

    double
    short_radius(const double t) const;
    double
    long_radius(const double t) const;
    /// Polar angle (from the apex) of the base on the surface t: where the
    /// base plane, or the ruled base's segment, meets the spheroid t.
    double
    base_angle(const double t) const;
    /// Each surface cut at its own height (the base is not a plane).
    bool
    ruled_base() const;
    /// Height of the epicardial cut [mm] (base_height for a flat base).
    double
    epicardial_base_height() const;

    /// A point of the wall's frame in the generator's (long axis z) and back.
    dealii::Point<3>
    to_generator_frame(const dealii::Point<3> &wall) const;
    dealii::Point<3>
    from_generator_frame(const dealii::Point<3> &generator) const;
    /// A vector of the generator's frame in the wall's frame.
    dealii::Tensor<1, 3>
    from_generator_frame(const dealii::Tensor<1, 3> &generator) const;

    /// Throws a message naming the offending Geometry / Ellipsoid entry if the
    /// shape is invalid.
    void
    validate() const;
  };

  /// The curved geometry of the LV wall, exact under refinement. It is the
  /// spherical manifold of a reference half shell (radii 1..2, z <= 0) carried
  /// over by a smooth bijection onto the wall: reference radius 1 + t gives the
  /// transmural coordinate t, the reference polar angle [0, pi/2] is stretched
  /// to [0, base_angle(t)], so the reference equator plane becomes the base
  /// plane. The bijection is smooth at the apex (no coordinate singularity on
  /// the mesh).
  class EllipsoidalWallManifold : public dealii::Manifold<3, 3>
  {
  public:
    explicit EllipsoidalWallManifold(const LVShape &shape);

    std::unique_ptr<dealii::Manifold<3, 3>>
    clone() const override;

    dealii::Point<3>
    get_new_point(
      const dealii::ArrayView<const dealii::Point<3>> &surrounding_points,
      const dealii::ArrayView<const double>           &weights) const override;

    /// Reference half-shell point -> wall point.
    dealii::Point<3>
    push_forward(const dealii::Point<3> &reference) const;

    /// Wall point -> reference half-shell point.
    dealii::Point<3>
    pull_back(const dealii::Point<3> &wall) const;

    /// Transmural coordinate t of a wall point (0 endocardium, 1 epicardium).
    double
    transmural_coordinate(const dealii::Point<3> &wall) const;

  private:
    LVShape                      shape;
    dealii::SphericalManifold<3> reference_manifold;
  };

  /// Cell counts of the generated LV mesh.
  struct LVMeshCells
  {
    unsigned int circumferential = 8; ///< around the long axis; a multiple of 8
    unsigned int longitudinal    = 3; ///< apex to base; > circumferential / 8
    unsigned int transmural      = 1; ///< through the wall
  };

  /// Fill @p tria (empty, serial or distributed) with the coarse all-hexahedral
  /// mesh of the LV wall and attach EllipsoidalWallManifold (manifold id 0) to
  /// all cells, faces and edges. The apex cap is the bottom face of a cubed
  /// sphere (four regular cells meet at the apex), the rest are the lower
  /// halves of the four side faces. Boundary ids are returned in @p names
  /// ("endocardium", "epicardium", "base").
  void
  create_lv_mesh(dealii::Triangulation<3, 3> &tria,
                 const LVShape               &shape,
                 const LVMeshCells           &cells,
                 BoundaryNames               &names);
} // namespace systole::Geometry
