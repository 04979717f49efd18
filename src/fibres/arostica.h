#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "fibres/fibre_basis.h"
#include "geometry/boundary_names.h"
#include "geometry/ellipsoid.h"

#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
}

namespace systole::Fibres
{
  class LaplaceFields;

  /// The fibres of the Aróstica et al. 2025 cardiac elastodynamics benchmark
  /// (CMAME 435:117485), on the truncated ellipsoid of @p shape (any frame of
  /// Geometry::LVShape; the benchmark's own is LVShape::arostica()).
  ///
  /// The transmural coordinate t̄ solves the Laplace problem t̄ = 0 on the
  /// endocardium, 1 on the epicardium, zero flux on the base (LaplaceFields,
  /// Q<degree>); the radii are interpolated linearly in it,
  /// r_s = r_s,endo + t̄ (r_s,epi - r_s,endo) and likewise r_l. In the
  /// benchmark's frame x = r_l cos mu, y = r_s sin mu cos theta,
  /// z = r_s sin mu sin theta (mu in [-pi, mu_b], apex at mu = -pi) a point
  /// has mu = -atan2(sqrt(y^2 + z^2) / r_s, x / r_l) and theta from (y, z);
  /// e_mu and e_theta are the unit tangents of that parametrisation (e_mu
  /// from apex to base, e_theta right-handed about the apex-to-base axis),
  /// @f[ f = \sin\alpha\, e_\mu + \cos\alpha\, e_\theta,\qquad
  ///     \alpha = \alpha_{endo} + (\alpha_{epi} - \alpha_{endo})\,\bar t, @f]
  /// and, with the benchmark's n_b = e_mu x e_theta / |.| (which points into
  /// the cavity), its sheet s = f x n_b (in the wall, across the fibre).
  /// Systole's frames are right-handed (n = f x s, Fibres::validate), so the
  /// sheet normal stored is n = -n_b, the outward wall normal; the laws see
  /// only s and f (the Holzapfel-Ogden sheet terms), which are the
  /// benchmark's. The twist has the sense of the analytic and rule-based
  /// generators (helix angle +60 degrees at the endocardium: a right-handed
  /// helix about the apex-to-base axis). On the axis (the apex) the frame of
  /// a point 1e-8 r_s off it is used.
  class Arostica
  {
  public:
    static constexpr const char *name = "arostica";

    struct Parameters
    {
      double       alpha_endo = 60.0 * M_PI / 180;  ///< [rad]
      double       alpha_epi  = -60.0 * M_PI / 180; ///< [rad]
      unsigned int degree     = 2; ///< of the Laplace solve's elements
    };

    /// Collective: solves the Laplace problem on @p tria (kept by
    /// reference), which needs boundary parts endocardium and epicardium.
    Arostica(const Parameters                  &params,
             const Geometry::LVShape           &shape,
             const dealii::Triangulation<3, 3> &tria,
             const Geometry::BoundaryNames     &names,
             Logger                            *logger = nullptr);
    ~Arostica();

    /// Validated frames at the real points @p points of the locally owned
    /// cell @p cell (the FibreField signature).
    void
    operator()(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
               const std::vector<dealii::Point<3>>                     &points,
               std::vector<FibreBasis> &bases) const;

    /// The transmural coordinate t̄ at the points (clamped to [0, 1]).
    void
    transmural(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
               const std::vector<dealii::Point<3>>                     &points,
               std::vector<double> &values) const;

    /// The frame at @p X for the transmural coordinate @p t (no solve: the
    /// pointwise half of the rule).
    FibreBasis
    basis(const dealii::Point<3> &X, const double t) const;

  private:
    Parameters                     params;
    Geometry::LVShape              shape;
    std::unique_ptr<LaplaceFields> fields;
  };
} // namespace systole::Fibres
