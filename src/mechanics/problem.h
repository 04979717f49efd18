#pragma once

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include "fibres/fibre_field.h"
#include "geometry/boundary_names.h"
#include "mechanics/parameters.h"

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class DataOut;
  template <int dim, int spacedim>
  class Mapping;

  namespace parallel::distributed
  {
    template <int dim, int spacedim>
    class Triangulation;
  }
} // namespace dealii

namespace systole
{
  class Logger;
}

namespace systole::Materials
{
  class PassiveLaw;
  class VolumetricLaw;
} // namespace systole::Materials

namespace systole::Mechanics
{
  /// What one Newton solve did.
  struct NewtonReport
  {
    unsigned int iterations = 0; ///< with a new tangent each
    /// Iterations with the factorized tangent of an earlier solve (chord
    /// iterations of solve_volume(); not counted in iterations).
    unsigned int reused_iterations = 0;
    double       initial_residual  = 0; ///< |R| before the first update
    double       final_residual    = 0; ///< |R| at convergence
    unsigned int linear_iterations = 0; ///< summed over the Newton iterations
  };

  using FibreFunction = Fibres::FibreField;

  /// Quasi-static finite-strain mechanics of the myocardium on a distributed
  /// mesh: displacement-based, Q1 or Q2, with a volumetric penalty for the
  /// near-incompressibility, follower pressure, Dirichlet (fixed or sliding)
  /// and Robin boundaries, and a prescribed active tension along the fibres.
  ///
  /// Equilibrium: @f$R(u) = \int_{\Omega_0} P(F) : \nabla\delta u\,dV
  /// - p\,\frac{dV}{du} + R_\mathrm{Robin} = 0@f$, solved by Newton's method
  /// with the consistent tangent. Cheap to include (pimpl).
  class Problem
  {
  public:
    /// @param[in] tria the mesh (kept by reference; must outlive this object)
    /// @param[in] names its boundary parts; every part named in @p params must
    ///            exist (clear error otherwise)
    /// @param[in] degree polynomial degree of the displacement (1 or 2)
    /// @param[in] mapping_degree degree of the geometry mapping
    /// @param[in] fibres fibre field (evaluated once at the quadrature
    ///            points of every locally owned cell)
    Problem(const Parameters                                   &params,
            dealii::parallel::distributed::Triangulation<3, 3> &tria,
            const Geometry::BoundaryNames                      &names,
            const unsigned int                                  degree,
            const unsigned int                                  mapping_degree,
            const Materials::PassiveLaw                        &passive_law,
            const Materials::VolumetricLaw                     &volumetric_law,
            const FibreFunction                                &fibres,
            Logger                                             &logger);
    ~Problem();

    /// Solve for equilibrium under @p pressure [kPa] and @p active_tension
    /// [kPa], starting from the current displacement. Throws
    /// ExcNewtonDidNotConverge (on every rank alike) when Newton fails; the
    /// displacement is then undefined: restore() it.
    NewtonReport
    solve(const double pressure, const double active_tension);

    /// Solve for equilibrium (u, p) under the cavity volume constraint
    /// V(u) = @p target_volume [mm^3]: the cavity pressure p [kPa] is the
    /// Lagrange multiplier. Newton on the bordered system
    /// [K -b; b^T 0][du; dp] = -[R; V - V_target] (b = dV/du), solved with
    /// two solves of one factorization of K and a scalar Schur complement.
    /// @p pressure is the initial guess on entry and the solution on exit.
    /// Converged when the residual meets the Newton tolerances and
    /// |V - V_target| <= 2e-9 V_target. Throws like solve().
    ///
    /// While a factorization of an earlier volume-constrained solve exists,
    /// the solve starts with chord iterations on it (the bordered system of
    /// that tangent, one back substitution each, residual without tangent);
    /// when they converge slower than a factor 4 per iteration it continues
    /// with full Newton. Consecutive solves of a time integration differ
    /// little, so most need no new factorization.
    NewtonReport
    solve_volume(const double target_volume,
                 const double active_tension,
                 double      &pressure);

    /// Reference positions of the quadrature points of the mechanics, per
    /// locally owned cell (indexed by active cell index; empty for other
    /// cells), in the order set_active_tension() expects.
    void
    quadrature_points(std::vector<std::vector<dealii::Point<3>>> &points) const;

    /// A per-point active tension [kPa] (layout of quadrature_points()),
    /// added to the uniform one of solve(); an empty argument removes it.
    void
    set_active_tension(std::vector<std::vector<double>> tension);

    /// Verification hook: relative errors of the bordered Jacobian against
    /// central differences in a fixed pseudo-random direction (d, dp):
    /// {first block row (K d - b dp vs dR), second row (b.d vs dV)}. Both
    /// fall like h^2 when consistent. Leaves u unchanged.
    std::array<double, 2>
    bordered_jacobian_error(const double pressure,
                            const double active_tension,
                            const double h);

    /// Remember the current displacement (a converged state); the one saved
    /// before becomes the previous state for predict().
    void
    save();

    /// Extrapolate from the last two saved states: u = u_s + ratio (u_s -
    /// u_prev), the predictor of the next load step (ratio = next increment /
    /// last increment). No-op before the second save().
    void
    predict(const double ratio);

    /// predict(@p ratio), kept only if the residual under the loads of the
    /// next step (@p pressure [kPa], @p active_tension [kPa]) is smaller there
    /// than at the last saved state; otherwise the saved state (whose first
    /// Newton step is the tangent predictor). The secant extrapolation
    /// overshoots where the exponential laws stiffen. Collective; two
    /// residual assemblies.
    void
    predict(const double ratio,
            const double pressure,
            const double active_tension);
    /// Go back to the displacement of the last save().
    void
    restore();

    /// Verification hook: the relative difference between the assembled
    /// tangent applied to a fixed pseudo-random direction d (zero on
    /// constrained DoFs) and the central difference (R(u + h d) - R(u - h d)) /
    /// 2h of the residual, at the current displacement. It falls like h^2
    /// when the tangent is consistent. Leaves u unchanged.
    double
    tangent_error(const double pressure,
                  const double active_tension,
                  const double h);

    /// Verification hook: set the displacement to the interpolant of
    /// @p displacement (3 components, mm), then apply the constraints.
    void
    set_displacement(const dealii::Function<3> &displacement);

    /// Cavity volume [mm^3]: the pressure boundary closed by the plane of
    /// the base (requires has_cavity(); collective).
    double
    cavity_volume() const;

    /// Whether the pressure acts on a cavity: the pressure boundary is the
    /// endocardium and the mesh has a base.
    bool
    has_cavity() const;

    /// Deformed positions X + u(X) of reference points [mm] (collective;
    /// throws if a point lies outside the mesh).
    std::vector<dealii::Point<3>>
    deformed_positions(const std::vector<dealii::Point<3>> &points) const;

    /// Add the displacement field to @p data_out (the DoF handler is attached
    /// here; call before build_patches).
    void
    attach_output(dealii::DataOut<3, 3> &data_out) const;

    /// The mapping of the curved geometry, for build_patches.
    const dealii::Mapping<3, 3> &
    mapping() const;

    dealii::types::global_dof_index
    n_dofs() const;

    /// "direct (MUMPS)" or "iterative (GMRES + GAMG)".
    std::string
    linear_solver_name() const;

    /// The fields and elements, e.g. "Q2-P1disc (u-p, incompressible)".
    std::string
    discretization_name() const;

    /// Global DoFs of the displacement and of the pressure (0 for penalty).
    std::array<dealii::types::global_dof_index, 2>
    n_block_dofs() const;

    /// Total wall times [s] of the mechanics' timer sections so far
    /// ("Mechanics / Newton", and inside it "Mechanics / assembly",
    /// "Mechanics / linear solver", "Mechanics / cavity volume"), on this
    /// rank.
    std::map<std::string, double>
    timings() const;

    /// Verification hook (mixed formulations): set every pressure DoF i to
    /// amplitude sin(1 + 0.7 i) [kPa], a non-trivial pressure field.
    void
    set_pressure_field(const double amplitude);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Mechanics
