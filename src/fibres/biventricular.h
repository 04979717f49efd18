#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "fibres/fibre_basis.h"
#include "fibres/rule_based.h"
#include "geometry/boundary_names.h"

#include <array>
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

  /// A unit quaternion (w, x, y, z).
  using Quaternion = std::array<double, 4>;

  /// The unit quaternion of the rotation whose matrix has the columns f, s, n
  /// of the orthonormal right-handed frame @p basis (Shepperd's method).
  Quaternion
  quaternion(const FibreBasis &basis);

  /// The frame (columns of the rotation matrix) of the unit quaternion @p q.
  FibreBasis
  basis(const Quaternion &q);

  /// Spherical linear interpolation from @p q0 (t = 0) to @p q1 (t = 1) on the
  /// shorter of the two arcs (q and -q are the same rotation).
  Quaternion
  slerp(const Quaternion &q0, const Quaternion &q1, const double t);

  /// Bayer et al. 2012's bislerp: the frames are axes, so @p a also stands for
  /// the frames turned by pi about one of its own axes (f, -s, -n),
  /// (-f, s, -n), (-f, -s, n). Of those four, the one closest to @p b is
  /// interpolated to @p b by slerp: t = 0 gives (that equivalent of) @p a,
  /// t = 1 gives @p b, and the path is the shortest rotation between the two
  /// sets of axes.
  FibreBasis
  bislerp(const FibreBasis &a, const FibreBasis &b, const double t);

  /// The fibre frame of a wall with unit normal along @p transmural
  /// (pointing from the endocardium to the epicardium) and longitudinal
  /// direction from @p apicobasal (the gradient of psi, projected onto the
  /// wall): e_t, e_l, e_c = e_l x e_t, f = sin(alpha) e_l + cos(alpha) e_c,
  /// s = e_t rotated by beta about f, n = f x s (the conventions of
  /// RuleBased). Angles in rad.
  FibreBasis
  wall_basis(const dealii::Tensor<1, 3> &transmural,
             const dealii::Tensor<1, 3> &apicobasal,
             const double                alpha,
             const double                beta);

  /// The coordinates of the biventricular rule at one point.
  struct BiventricularCoordinates
  {
    double phi_epi = 0; ///< 0 on both endocardia, 1 on the epicardium
    double phi_lv  = 0; ///< 1 on the LV endocardium, 0 on RV endo and epi
    double phi_rv  = 0; ///< 1 on the RV endocardium, 0 on LV endo and epi
    double psi     = 0; ///< 0 at the apex, 1 on the base
    /// d = phi_rv / (phi_lv + phi_rv): 0 on the LV endocardium, 1 on the RV
    /// endocardium, through the septum in between.
    double depth = 0;
  };

  /// The Laplace-Dirichlet rule-based fibres of Bayer et al. 2012 (Ann.
  /// Biomed. Eng. 40:2243) for two ventricles, on any mesh (hexahedral or
  /// tetrahedral) with the boundary parts lv_endocardium, rv_endocardium,
  /// epicardium and base, from those parts alone.
  ///
  /// Four solves (Q2 or P2, LaplaceFields): phi_epi, phi_lv, phi_rv (Laplace,
  /// the Dirichlet values of BiventricularCoordinates, zero flux on the base)
  /// and the apicobasal psi = 1 - u / max u with -Laplace u = 1, u = 0 on the
  /// base (as RuleBased's default). At a point, with d the septal depth and e =
  /// phi_epi:
  ///  - Q_endo = bislerp(Q_lv, Q_rv, d) (Bayer's septal rule), with
  ///    Q_lv = wall_basis(-grad phi_lv, grad psi, alpha_s(d), beta_s(d)) and
  ///    Q_rv = wall_basis(+grad phi_rv, ...): both oriented from the LV into
  ///    the RV, where the RV's own angles (alpha, beta) read (-alpha, -beta);
  ///    alpha_s runs linearly from the LV endocardial angle (d = 0) to the
  ///    septal one (d = 1/2) to minus the RV endocardial one (d = 1), beta_s
  ///    likewise;
  ///  - Q_mid, Q_epi = bislerp(LV frame, RV frame, d) of
  ///    wall_basis(grad phi_epi, grad psi, angles) with the mid-wall (mean of
  ///    endo and epi) and the epicardial angles of each ventricle;
  ///  - Q = bislerp(Q_endo, Q_mid, 2e) for e <= 1/2, else
  ///    bislerp(Q_mid, Q_epi, 2e - 1).
  /// So on the LV (RV) endocardium the helix and sheet angles are the LV (RV)
  /// endocardial ones, measured in that ventricle's own wall frame (normal
  /// out of its cavity), on the epicardium those of the ventricle beneath,
  /// and through the free walls the frame turns about the wall normal,
  /// linearly in phi_epi. The mid-wall frame is not Bayer's: his Q_epi carries
  /// alpha(phi_epi) and one bislerp spans the wall, which turns the short way
  /// (and jumps) where the turn exceeds 90 degrees (120 for +-60). With equal
  /// angles in both ventricles and a septal angle of 0, the septum turns from
  /// +alpha_endo (LV side) through 0 to -alpha_endo (RV side, in the LV's
  /// orientation), as in Bayer's rule.
  class Biventricular
  {
  public:
    static constexpr const char *name = "biventricular";

    /// Subsection "Fibres / Biventricular". Angles in rad.
    struct Parameters
    {
      double lv_alpha_endo = 60.0 * M_PI / 180;
      double lv_alpha_epi  = -60.0 * M_PI / 180;
      double lv_beta_endo  = -20.0 * M_PI / 180;
      double lv_beta_epi   = 20.0 * M_PI / 180;
      double rv_alpha_endo = 60.0 * M_PI / 180;
      double rv_alpha_epi  = -60.0 * M_PI / 180;
      double rv_beta_endo  = -20.0 * M_PI / 180;
      double rv_beta_epi   = 20.0 * M_PI / 180;
      double septum_alpha  = 0.0;
      double septum_beta   = 0.0;
      /// Degree of the Lagrange elements of the four solves.
      unsigned int degree = 2;

      static void
      declare(dealii::ParameterHandler &prm);
      static Parameters
      parse(const dealii::ParameterHandler &prm);
    };

    /// Collective: the four solves. @p logger, if not null, receives one
    /// line with their cost.
    Biventricular(const Parameters                  &params,
                  const dealii::Triangulation<3, 3> &tria,
                  const Geometry::BoundaryNames     &names,
                  Logger                            *logger = nullptr);
    ~Biventricular();

    /// Validated frames at the real points @p points of the locally owned
    /// cell @p cell (the FibreField signature).
    void
    operator()(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
               const std::vector<dealii::Point<3>>                     &points,
               std::vector<FibreBasis> &bases) const;

    /// The coordinates at the same kind of points.
    void
    coordinates(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
                const std::vector<dealii::Point<3>>                     &points,
                std::vector<BiventricularCoordinates> &result) const;

    /// A wall frame from the transmural and apicobasal fields alone (e_t
    /// along grad phi_epi, e_l the wall-tangent part of grad psi, e_c =
    /// e_l x e_t; transmural = phi_epi, apicobasal = psi), in which
    /// systole-fibres measures helix angles. In the septum, where phi_epi
    /// is nearly 0 on both sides, it is not the septal wall's frame.
    void
    wall_frames(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
                const std::vector<dealii::Point<3>>                     &points,
                std::vector<WallFrame> &frames) const;

    /// One line: DOFs, CG iterations and wall time of the solves.
    const std::string &
    summary() const;

  private:
    Parameters                     params;
    std::unique_ptr<LaplaceFields> fields;
    std::string                    report;
  };
} // namespace systole::Fibres
