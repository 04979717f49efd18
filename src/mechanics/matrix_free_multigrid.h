#pragma once

#include <deal.II/base/types.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "mechanics/hyperelastic_kernel.h"

#include <memory>
#include <set>

namespace systole::Mechanics
{
  /// Conjugate gradients on the matrix-free tangent (MatrixFreeTangent's
  /// operator, Variant::cached) preconditioned by one geometric multigrid
  /// V-cycle on matrix-free levels (deal.II step-37's set-up: local
  /// smoothing on the levels of a globally refined mesh,
  /// MGTransferMatrixFree, Chebyshev smoothing with the point Jacobi
  /// diagonal computed matrix-free, and a Chebyshev-accelerated solve on the
  /// coarsest level). Every level is linearized at the displacement
  /// interpolated to it (Davydov et al. 2020). Homogeneous Dirichlet
  /// conditions on the given boundary ids on every level.
  ///
  /// Preconditions: @p dof_handler's triangulation was built with
  /// construct_multigrid_hierarchy, distribute_mg_dofs() was called, and
  /// the element is Q2 (3 components) on hexahedra.
  class MatrixFreeMultigrid
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;

    /// The V-cycle's smoother.
    struct Settings
    {
      unsigned int smoothing_degree      = 4;    ///< Chebyshev degree per level
      double       smoothing_range       = 20.0; ///< lambda_max / lambda_min
      unsigned int eigenvalue_iterations = 15;   ///< CG steps of the estimate
      /// The level operators' tangent in single precision
      /// (MatrixFreeTangent::Variant::cached_single; the active level's
      /// operator, on which CG runs, stays in double precision).
      bool single_precision_levels = false;
    };

    MatrixFreeMultigrid(const dealii::Mapping<3>                   &mapping,
                        const dealii::DoFHandler<3>                &dof_handler,
                        const std::set<dealii::types::boundary_id> &fixed,
                        const NeoHookeanPenalty                    &law,
                        const Settings                             &settings);

    ~MatrixFreeMultigrid();

    /// Sizes @p v in the active level's layout.
    void
    initialize_dof_vector(Vector &v) const;

    /// Linearize every level at @p u (active layout; interpolated to the
    /// levels) and set up the smoothers (eigenvalue estimates). Collective.
    void
    update(const Vector &u);

    /// dst = K src on the active level (constrained rows: the identity).
    void
    vmult(Vector &dst, const Vector &src) const;

    /// Solve K x = b with CG to |r| <= @p relative_tolerance |b| (x starts
    /// from zero; b's constrained entries must be zero). Returns the CG
    /// iterations; throws if CG does not converge in 500.
    unsigned int
    solve(Vector &x, const Vector &b, const double relative_tolerance) const;

    /// Number of multigrid levels.
    unsigned int
    n_levels() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Mechanics
