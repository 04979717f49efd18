#pragma once

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include "fibres/rule_based.h"
#include "geometry/boundary_names.h"

#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
}

namespace systole::Postprocess
{
  /// The wall of the left ventricle that the ventricle postprocessors (AHA
  /// segments, clinical kinematics, ventricle function, strain) measure,
  /// chosen from the boundary parts of the mesh:
  /// - a left ventricle (parts endocardium, epicardium, base): the whole
  ///   mesh; the cardiac frame is that of Fibres::WallCoordinates
  ///   (transmural 0 on the endocardium, 1 on the epicardium);
  /// - two ventricles (lv_endocardium, rv_endocardium with the septum's RV
  ///   side, epicardium, base; as Fibres::Biventricular): the LV free wall
  ///   and the septum, not the RV free wall. Five problems of
  ///   Fibres::LaplaceFields (zero flux where no value is given):
  ///   - the LV transmural t: 0 on lv_endocardium, 1 on epicardium and
  ///     rv_endocardium (across the septum from the LV to the RV cavity);
  ///   - the apicobasal psi of WallCoordinates (-Laplace u = 1, u = 0 on
  ///     the base, psi = 1 - u / max u);
  ///   - the interventricular v: 0 on lv_endocardium, 1 on rv_endocardium:
  ///     about 0 in the LV free wall, 1 in the RV free wall, 0 to 1 across
  ///     the septum;
  ///   - the septal s: 1 on lv_endocardium, 0 on epicardium: about 1 in the
  ///     septum (insulated on its RV side), 0 in the RV free wall;
  ///   - the epicardial transmural phi_epi: 0 on both endocardia, 1 on the
  ///     epicardium.
  ///   A cell whose centre has v > 1/2 and s < 1/2 is in the RV free wall,
  ///   every other cell in the LV wall. The cardiac frame is
  ///   Fibres::wall_frame() of (t, psi) in the LV wall (its transmural
  ///   coordinate t: the septum's LV third is endocardial) and of (phi_epi,
  ///   psi) in the RV free wall.
  /// Keeps @p tria by reference (see Fibres::LaplaceFields).
  class LvWall
  {
  public:
    /// Collective. Solves for the frames (a left ventricle: only if
    /// @p frames) and the wall of two ventricles. Throws one clear error if
    /// the mesh has neither endocardium nor lv_endocardium, or lacks
    /// another part of its kind. @p logger, if not null, receives one line.
    LvWall(const dealii::Triangulation<3, 3> &tria,
           const Geometry::BoundaryNames     &names,
           const bool                         frames,
           Logger                            *logger = nullptr);
    ~LvWall();

    /// Whether the mesh has two ventricles.
    bool
    biventricular() const;

    /// The boundary part of the LV endocardium: "endocardium" or
    /// "lv_endocardium".
    const std::string &
    endocardium() const;

    /// The boundary parts whose faces of the LV wall's cells bound it from
    /// outside: "epicardium", and for two ventricles also "rv_endocardium"
    /// (the septum's RV side).
    const std::vector<std::string> &
    outer_surface() const;

    /// Whether the locally owned or ghost cell @p cell is in the LV wall.
    bool
    contains(const dealii::Triangulation<3, 3>::cell_iterator &cell) const;

    /// Per active cell index, whether the cell is in the LV wall (locally
    /// owned and ghost cells; empty for a left ventricle: every cell).
    const std::vector<bool> &
    cells() const;

    /// The wall frames at the real points @p points of the locally owned
    /// cell @p cell (needs @p frames at construction).
    void
    frames(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
           const std::vector<dealii::Point<3>>                     &points,
           std::vector<Fibres::WallFrame> &result) const;

    /// Two ventricles: the mean of the rv_endocardium's face centres (on
    /// the septum's side of the LV) [mm].
    const dealii::Point<3> &
    rv_centroid() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Postprocess
