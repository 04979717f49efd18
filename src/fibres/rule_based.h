#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "fibres/fibre_basis.h"
#include "fibres/laplace_fields.h"
#include "geometry/boundary_names.h"

#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
}

namespace systole::Fibres
{
  /// The local frame of the ventricular wall at one point, from the solves of
  /// WallCoordinates.
  struct WallFrame
  {
    double transmural = 0; ///< phi: 0 on the endocardium, 1 on the epicardium
    double apicobasal = 0; ///< psi: 0 at the apex, 1 on the base
    /// Unit wall normal grad phi / |grad phi| (endocardium to epicardium).
    dealii::Tensor<1, 3> e_t;
    /// Unit longitudinal direction (apex to base): grad psi minus its e_t
    /// part, normalized, so tangent to the wall.
    dealii::Tensor<1, 3> e_l;
    /// Circumferential direction e_l x e_t.
    dealii::Tensor<1, 3> e_c;
    /// grad psi is (nearly) normal to the wall, as on the long axis at the
    /// apex: e_l is then an arbitrary tangent.
    bool degenerate = false;
  };

  /// The wall frame at @p where of the transmural field @p phi and the
  /// apicobasal field @p psi (values and gradients there): e_t along
  /// grad phi, e_l the wall-tangent part of grad psi (any tangent where
  /// grad psi is normal to the wall: degenerate), e_c = e_l x e_t. Throws if
  /// grad phi vanishes (@p what names the caller in the message).
  WallFrame
  wall_frame(const FieldValue       &phi,
             const FieldValue       &psi,
             const dealii::Point<3> &where,
             const std::string      &what);

  /// How the apicobasal coordinate psi is defined.
  enum class ApicobasalField
  {
    /// Bayer et al. 2012: Laplace psi = 1 on the base, psi = 0 at the apex
    /// vertex (the epicardial vertex farthest from the base plane). A point
    /// condition is singular in 3D: the frames near it are poorly resolved.
    laplace,
    /// -Laplace u = 1, u = 0 on the base, zero flux elsewhere, and
    /// psi = 1 - u / max u: psi = 1 on the base and 0 at the apex (where u
    /// peaks), and grad psi is smooth everywhere (no point condition).
    poisson
  };

  /// What the two solves cost (for the log and the inspection table).
  struct WallCoordinatesReport
  {
    std::string        element               = "Q2"; ///< or "P2", "Q1", ...
    unsigned int       degree                = 2;
    unsigned long long n_dofs                = 0;
    unsigned int       transmural_iterations = 0; ///< of CG
    unsigned int       apicobasal_iterations = 0; ///< of CG
    /// CG + AMG broke down (an indefinite matrix: tangled cells) and MUMPS
    /// solved.
    bool transmural_direct = false;
    bool apicobasal_direct = false;
    /// Cells with a non-positive Jacobian at a quadrature point.
    unsigned int     n_tangled_cells    = 0;
    double           setup_seconds      = 0; ///< DoFs, apex search
    double           transmural_seconds = 0; ///< assembly, AMG and CG
    double           apicobasal_seconds = 0; ///< assembly, AMG and CG
    dealii::Point<3> apex;                   ///< where psi = 0 [mm]

    /// One line for the log.
    std::string
    summary() const;
  };

  /// The transmural and apicobasal coordinates of an LV mesh and the wall
  /// frame built from their gradients (the first half of the rule of Bayer et
  /// al. 2012, Ann. Biomed. Eng. 40:2243).
  ///
  /// On the mesh @p tria (serial or distributed, hexahedra or tetrahedra)
  /// with boundary parts "endocardium", "epicardium" and "base", solves with
  /// LaplaceFields (Q_k or P_k elements as Geometry::CellKind picks them,
  /// PETSc CG preconditioned by BoomerAMG)
  /// @f[ \Delta\phi = 0,\quad \phi|_{endo} = 0,\quad \phi|_{epi} = 1 @f]
  /// with zero flux on the base, and the apicobasal problem of
  /// ApicobasalField. Nothing else of the mesh is used: no ellipsoidal
  /// coordinates, no axis. Both solutions are kept with ghost values, so
  /// frames can be evaluated on every locally owned cell. The object keeps
  /// @p tria by reference (its DoFHandler subscribes to it): it must not
  /// outlive the mesh, and the mesh must not be refined meanwhile.
  /// Collective.
  ///
  /// The frame (WallFrame) takes the wall normal from grad phi first and
  /// projects grad psi onto the wall, not Bayer's order (e_l = grad psi
  /// first): grad psi has a transmural component, and Bayer's order tilts the
  /// frame out of the wall (helix errors of 5 to 16 degrees against the
  /// analytic ellipsoid frame).
  class WallCoordinates
  {
  public:
    struct Parameters
    {
      /// Degree of the Lagrange elements: Q1 gradients are too rough for the
      /// frame (helix errors of several degrees on meshes of 10^4 DoFs), Q2
      /// stays below one degree (hundredths on average).
      unsigned int    degree     = 2;
      ApicobasalField apicobasal = ApicobasalField::poisson;
    };

    /// @param[in] logger if not null, receives one line with the cost of the
    /// solves.
    WallCoordinates(const Parameters                  &params,
                    const dealii::Triangulation<3, 3> &tria,
                    const Geometry::BoundaryNames     &names,
                    Logger                            *logger = nullptr);
    ~WallCoordinates();

    /// Frames at the real points @p points, which lie in the locally owned
    /// (or ghost) cell @p cell of the mesh given to the constructor. Points a
    /// little outside (e.g. from another mapping) are projected onto it;
    /// points the inverse mapping cannot place (in a tangled cell) take the
    /// nearest of a lattice of reference points (LaplaceFields::evaluate()).
    void
    evaluate(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
             const std::vector<dealii::Point<3>>                     &points,
             std::vector<WallFrame> &frames) const;

    const WallCoordinatesReport &
    report() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// The Laplace-Dirichlet rule-based fibres (Bayer et al. 2012) on any LV
  /// mesh, hexahedral or tetrahedral, from its boundary parts alone: in the
  /// wall frame (e_t, e_l, e_c) of WallCoordinates,
  /// @f[ f = \sin\alpha\, e_l + \cos\alpha\, e_c,\qquad
  ///     \alpha(\phi) = \alpha_{endo} + (\alpha_{epi} - \alpha_{endo})\,\phi,
  /// @f]
  /// the sheet s is the wall normal e_t rotated by beta about f, and
  /// n = f x s.
  ///
  /// Conventions (those of AnalyticHelix, with e_l for e_u, e_c for e_v and
  /// e_t for the outward normal e_v x e_u, so on the generated ellipsoid
  /// both rules agree up to the difference between phi and the geometric
  /// transmural coordinate t):
  ///  - e_t = grad phi / |grad phi| points from the endocardium to the
  ///    epicardium (out of the cavity);
  ///  - the longitudinal e_l points from the apex to the base (grad psi,
  ///    psi = 0 at the apex, 1 on the base, projected onto the wall);
  ///  - the circumferential e_c = e_l x e_t turns counterclockwise about the
  ///    long axis seen from the base (looking towards the apex);
  ///  - the helix angle alpha = atan2(f . e_l, f . e_c) (helix_angle()) is
  ///    positive where the fibre rises towards the base as it turns along
  ///    e_c: alpha > 0 is a right-handed helix (the endocardium's, +60
  ///    degrees by default), alpha < 0 a left-handed one (the epicardium's,
  ///    -60); f is taken with f . e_c > 0 (|alpha| < 90 degrees);
  ///  - s = cos(beta) e_t + sin(beta) (f x e_t): beta = 0 puts the sheet
  ///    along the outward wall normal; n = f x s completes a right-handed
  ///    frame.
  /// Bayer's sheet rotation (about the rotated e_l) is replaced by this one,
  /// which is the analytic rule's.
  class RuleBased
  {
  public:
    static constexpr const char *name = "rule-based";

    struct Parameters
    {
      double                      alpha_endo = 60.0 * M_PI / 180;  ///< [rad]
      double                      alpha_epi  = -60.0 * M_PI / 180; ///< [rad]
      double                      beta       = 0.0;                ///< [rad]
      WallCoordinates::Parameters coordinates;
    };

    /// Collective: solves the two problems of WallCoordinates.
    RuleBased(const Parameters                  &params,
              const dealii::Triangulation<3, 3> &tria,
              const Geometry::BoundaryNames     &names,
              Logger                            *logger = nullptr);

    /// Validated frames at the real points @p points of the locally owned
    /// cell @p cell (the FibreField signature).
    void
    operator()(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
               const std::vector<dealii::Point<3>>                     &points,
               std::vector<FibreBasis> &bases) const;

    /// The fibre frame in the wall frame @p frame.
    FibreBasis
    basis(const WallFrame &frame) const;

    const WallCoordinates &
    coordinates() const;

  private:
    Parameters      params;
    WallCoordinates wall;
  };
} // namespace systole::Fibres
