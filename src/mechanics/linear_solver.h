#pragma once

#include <deal.II/base/index_set.h>

#include "base/linear_algebra.h"

#include <memory>
#include <string>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class DoFHandler;
  template <int dim, int spacedim>
  class Mapping;
} // namespace dealii

namespace systole::Mechanics
{
  /// Solves K x = b for the mechanics tangent: MUMPS LU ("direct"), or GMRES
  /// preconditioned by PETSc's smoothed-aggregation multigrid GAMG, which is
  /// given the six rigid-body modes of the displacement as near-null space
  /// ("iterative").
  class LinearSolver
  {
  public:
    virtual ~LinearSolver() = default;

    /// Prepare solves with @p K (the direct solver factorizes it; the
    /// iterative one builds its preconditioner). @p K must stay alive and
    /// unchanged until the next setup().
    virtual void
    setup(const LA::MPI::SparseMatrix &K) = 0;

    /// Solve K x = b with the K of the last setup(); returns the number of
    /// iterations (1 for the direct solver). Several right-hand sides share
    /// one factorization. Throws ExcMessage when the solve fails (the Newton
    /// loop treats that as a failed step).
    virtual unsigned int
    solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) = 0;

    /// setup(K), then solve(x, b).
    unsigned int
    solve(const LA::MPI::SparseMatrix &K,
          LA::MPI::Vector             &x,
          const LA::MPI::Vector       &b)
    {
      setup(K);
      return solve(x, b);
    }

    virtual std::string
    name() const = 0;
  };

  /// The solver named @p type ("direct" or "iterative").
  /// @param[in] dof_handler vector-valued displacement DoFs (for the
  ///            rigid-body modes of the iterative solver)
  /// @param[in] tolerance relative residual reduction of the iterative solver
  /// @param[in] symmetric whether the matrices are symmetric (the direct
  ///            solver then factorizes LDL^T, about half the work of LU)
  std::unique_ptr<LinearSolver>
  create_linear_solver(const std::string              &type,
                       const dealii::Mapping<3, 3>    &mapping,
                       const dealii::DoFHandler<3, 3> &dof_handler,
                       const double                    tolerance,
                       const bool                      symmetric);
} // namespace systole::Mechanics
