#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include "base/registry.h"
#include "fibres/biventricular.h"
#include "fibres/dti_import.h"
#include "fibres/fibre_basis.h"
#include "fibres/frames.h"
#include "fibres/rule_based.h"
#include "geometry/ellipsoid.h"

#include <functional>
#include <string>

namespace systole
{
  class Logger;
}

namespace systole::Fibres
{
  /// The analytic helix rule of Land et al. 2015, problem 3, on the
  /// truncated-ellipsoid ventricle: at a wall point with transmural coordinate
  /// t and ellipsoidal coordinates (u, v) (x = r_s(t) sin u cos v,
  /// y = r_s(t) sin u sin v, z = r_l(t) cos u, u in (-pi, 0)),
  /// @f[ f = \sin\alpha\, e_u + \cos\alpha\, e_v,\qquad
  ///     \alpha(t) = \alpha_{endo} + (\alpha_{epi} - \alpha_{endo})\,t @f]
  /// with e_u (meridional, apex to base) and e_v (circumferential) the unit
  /// tangents of the point's own spheroid. The sheet s is the unit wall normal
  /// e_v x e_u (pointing out of the cavity) rotated by the sheet angle beta
  /// about f, and n = f x s. Undefined on the axis (the apex): there the
  /// frame of a nearby point is used.
  class AnalyticHelix
  {
  public:
    /// @param[in] alpha_endo, alpha_epi helix angles [rad]
    /// @param[in] beta sheet angle [rad]
    AnalyticHelix(const Geometry::LVShape &shape,
                  const double             alpha_endo,
                  const double             alpha_epi,
                  const double             beta);

    FibreBasis
    operator()(const dealii::Point<3> &X) const;

    /// The local frame (e_u, e_v, wall normal) and t at @p X.
    void
    local_frame(const dealii::Point<3> &X,
                dealii::Tensor<1, 3>   &e_u,
                dealii::Tensor<1, 3>   &e_v,
                double                 &t) const;

  private:
    Geometry::LVShape                 shape;
    Geometry::EllipsoidalWallManifold manifold;
    double                            alpha_endo, alpha_epi, beta;
  };

  /// Subsection "Fibres": the generator and its parameters.
  struct Parameters
  {
    /// "analytic", "arostica" (arostica.h), "biventricular"
    /// (biventricular.h), "cartesian", "dti" (dti_import.h), "rule-based"
    /// (rule_based.h) or "vtu" (per-cell vectors of a .vtu mesh file)
    std::string generator  = "cartesian";
    double      alpha_endo = 60.0;  ///< [degrees]
    double      alpha_epi  = -60.0; ///< [degrees]
    double      beta       = 0.0;   ///< [degrees]
    /// Subsection "Fibres / Rule-based": how the rule-based generator
    /// solves for its wall coordinates.
    WallCoordinates::Parameters rule_based;
    /// Subsection "Fibres / Biventricular".
    Biventricular::Parameters biventricular;
    /// Subsection "Fibres / DTI": the diffusion-tensor image.
    DTIParameters dti;
    /// Subsection "Fibres / VTU": per-cell vectors of a .vtu mesh file.
    std::string vtu_file;                   ///< absolute
    std::string vtu_fibre_array = "fibres"; ///< cell or point array
    std::string vtu_sheet_array;            ///< empty: none

    static void
    declare(dealii::ParameterHandler &prm);
    /// @param[in] base_directory folder of the parameter file (relative
    /// DTI file names are resolved against it)
    static Parameters
    parse(const dealii::ParameterHandler &prm,
          const std::string              &base_directory = "");
  };

  /// What a generator builds its field on: the generated ellipsoid
  /// (analytic and arostica rules only), the mesh (kept by reference), its
  /// boundary parts, and a logger for the one-line cost report (may be null).
  struct GeneratorInputs
  {
    const Geometry::LVShape           &shape;
    const dealii::Triangulation<3, 3> &tria;
    const Geometry::BoundaryNames     &names;
    Logger                            *logger;
  };

  using FibreGeneratorRegistry =
    Registry<FibreField(const Parameters &, const GeneratorInputs &)>;

  /// The table of fibre generators (fibre_field.cc). A generator's entries
  /// are fields of Parameters (shared angles) or a subsection it declares.
  FibreGeneratorRegistry &
  fibre_generators();

  /// The fibre field of the generator of @p params, on the mesh @p tria
  /// (kept by reference) whose boundary parts are @p names; @p shape is the
  /// generated ellipsoid (used by the analytic rule only). Every frame it
  /// returns is validated. Collective for generators that solve on the mesh
  /// (rule-based); their field must not outlive @p tria. @p logger, if not
  /// null, receives their one-line cost report.
  FibreField
  create_fibre_field(const Parameters                  &params,
                     const Geometry::LVShape           &shape,
                     const dealii::Triangulation<3, 3> &tria,
                     const Geometry::BoundaryNames     &names,
                     Logger                            *logger = nullptr);
} // namespace systole::Fibres
