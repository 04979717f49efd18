#pragma once

#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include "mechanics/problem.h"

#include <array>
#include <memory>

namespace systole::Mechanics
{
  /// The verification hooks of Problem, for the tests and the benchmarks
  /// (not for a simulation): finite-difference checks of the tangents, the
  /// assembled matrix, a pressure field, a matrix-free tangent of its own. Each
  /// takes the problem it checks.
  class MatrixFreeTangent;

  class ProblemChecks
  {
  public:
    /// The relative difference between the tangent (the linear solver's:
    /// the assembled matrix, or the matrix-free operator) applied to a fixed
    /// pseudo-random direction d (zero on constrained DoFs) and the central
    /// difference (R(u + h d) - R(u - h d)) / 2h of the residual, at the
    /// current displacement, under @p pressure [kPa] on every pressure part
    /// and @p active_tension [kPa]. It falls like h^2 when the tangent is
    /// consistent. Leaves u unchanged. Collective.
    static double
    tangent_error(Problem     &problem,
                  const double pressure,
                  const double active_tension,
                  const double h);

    /// Relative errors of the bordered Jacobian against central differences
    /// in a fixed pseudo-random direction (d, dp) at the current u and the
    /// cavity pressures @p pressures [kPa] (size n_cavities()): {first block
    /// row (K d - B dp vs dR), second row (B^T d vs dV, Euclidean over the
    /// cavities)}. Both fall like h^2 when consistent. Leaves u unchanged.
    static std::array<double, 2>
    bordered_jacobian_error(Problem                      &problem,
                            const dealii::Vector<double> &pressures,
                            const double                  active_tension,
                            const double                  h);

    /// The same with @p pressure [kPa] in every cavity.
    static std::array<double, 2>
    bordered_jacobian_error(Problem     &problem,
                            const double pressure,
                            const double active_tension,
                            const double h);

    /// Assemble the residual and the tangent at the current displacement
    /// under @p pressure [kPa] on every pressure part and @p active_tension
    /// [kPa], and return the sparse tangent (condensed: a constrained row or
    /// column holds its diagonal entry alone; without the low-rank coupling
    /// of loaded lids), valid until the next assembly. Not with a
    /// matrix-free linear solver. Collective.
    static const dealii::PETScWrappers::MPI::SparseMatrix &
    assembled_tangent(Problem     &problem,
                      const double pressure,
                      const double active_tension);

    /// Mixed formulations: set every pressure DoF i to amplitude sin(1 + 0.7
    /// i) [kPa], a non-trivial pressure field.
    static void
    set_pressure_field(Problem &problem, const double amplitude);

    /// A new MatrixFreeTangent of the bulk term of @p problem at its current
    /// displacement under the uniform @p active_tension [kPa] (plus the
    /// per-point tensions and the tension model's step, as the assembly):
    /// the general cached tangent (Variant::cached, or cached_single with @p
    /// single) on the problem's mapping, DoFs and constraints, whose dP/dF
    /// at every point comes from the assembly's own point kernel (the
    /// passive law with the fibre frame, the volumetric penalty, the active
    /// tension) and first_elasticity_tangent(). The bulk term only: without
    /// follower pressure, Robin springs or loaded lids, it is the assembled
    /// tangent at zero cavity pressure without supports (the follower
    /// pressure: update_matrix_free_tangent() with a pressure). Penalty
    /// formulation, Q2 hexahedra, the full volumetric rule, quasi-static
    /// (throws otherwise). The Linear solver "matrix-free" holds its own.
    /// The problem must outlive it. Collective.
    static std::unique_ptr<MatrixFreeTangent>
    matrix_free_tangent(Problem     &problem,
                        const double active_tension,
                        const bool   single = false);

    /// Refill @p tangent (made by matrix_free_tangent() of @p problem) at
    /// the current displacement and @p active_tension [kPa]. Collective.
    static void
    update_matrix_free_tangent(Problem           &problem,
                               MatrixFreeTangent &tangent,
                               const double       active_tension);

    /// The same with the follower @p pressure [kPa] on every pressure part
    /// (its face term, MatrixFreeTangent::set_follower_pressure(), as
    /// assembled_tangent(problem, pressure, active_tension) has it).
    /// Collective.
    static void
    update_matrix_free_tangent(Problem           &problem,
                               MatrixFreeTangent &tangent,
                               const double       pressure,
                               const double       active_tension);
  };
} // namespace systole::Mechanics
