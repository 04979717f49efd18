#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "geometry/boundary_names.h"

#include "postprocess/lv_wall.h"

#include <string>

namespace systole::Postprocess
{
  /// The American Heart Association 17-segment model of the left ventricle
  /// (Cerqueira et al. 2002, Circulation 105:539; shared/reference/
  /// physiology.md) on a reference ventricle.
  ///
  /// Wall coordinates: the apicobasal level l(X) = (X - apex) . e / L in
  /// [0, 1] along the long axis e (the base plane's normal, apex to base; L
  /// the distance of the epicardial apex from the base plane), and the
  /// circumferential angle theta(X) of X about the axis from the reference
  /// (anterior) direction, counter-clockwise seen from the apex as in the
  /// bull's-eye plot (right-handed about -e), in [0, 2 pi).
  ///
  /// Segments: l < cap level (the endocardial apex: the myocardium beyond
  /// the cavity) is the apex cap, 17; above it the long axis is cut into
  /// equal thirds: apical (13-16, 90 degrees each, 13 centred on the
  /// reference direction), mid (7-12) and basal (1-6, 60 degrees each, 1 and
  /// 7 centred on it). Going counter-clockwise from anterior: anterior,
  /// anteroseptal, inferoseptal, inferior, inferolateral, anterolateral (the
  /// apical ring: anterior, septal, inferior, lateral).
  class AhaSegments
  {
  public:
    struct Axis
    {
      dealii::Point<3>     apex;          ///< epicardial apex [mm]
      dealii::Tensor<1, 3> direction;     ///< unit, apex to base
      double               length    = 1; ///< apex to base plane [mm]
      double               cap_level = 0; ///< level of the endocardial apex
      /// Unit, orthogonal to direction: theta = 0 (anterior).
      dealii::Tensor<1, 3> reference;
    };

    explicit AhaSegments(const Axis &axis);

    /// The axis of the left ventricle @p wall of @p tria: the plane of the
    /// boundary part "base", the vertex of the LV wall's cells farthest from
    /// it (the apex) and the farthest vertex of the LV endocardium (the cap
    /// level); @p reference projected onto the plane orthogonal to the axis.
    /// Collective. Throws if a part is missing or @p reference is (nearly)
    /// parallel to the axis.
    static Axis
    axis_of(const dealii::Triangulation<3, 3> &tria,
            const Geometry::BoundaryNames     &names,
            const LvWall                      &wall,
            const dealii::Tensor<1, 3>        &reference);

    const Axis &
    axis() const;

    /// Apicobasal level l(X) [-] (0 at the apex, 1 on the base plane).
    double
    level(const dealii::Point<3> &X) const;

    /// Circumferential angle theta(X) [rad] in [0, 2 pi).
    double
    angle(const dealii::Point<3> &X) const;

    /// Segment 1 ... 17 of @p X.
    unsigned int
    segment(const dealii::Point<3> &X) const;

    /// 0: apex cap, 1: apical, 2: mid, 3: basal ring of level @p l.
    unsigned int
    ring(const double l) const;

    /// "basal anterior", ..., "apex".
    static std::string
    name(const unsigned int segment);

    static constexpr unsigned int n_segments = 17;

  private:
    Axis                 geometry;
    dealii::Tensor<1, 3> binormal; ///< theta = 90 degrees
  };
} // namespace systole::Postprocess
