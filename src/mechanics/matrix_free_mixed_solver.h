#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "mechanics/linear_solver.h"
#include "mechanics/matrix_free_solver.h"

#include <memory>
#include <string>

namespace systole::Mechanics
{
  class FieldLayout;

  /// Linear solver = matrix-free for the mixed Q2-P1disc formulations
  /// (issue 40): no sparse matrix of the displacement block. It solves the
  /// augmented system of the matrix-based iterative solver, T K_0 x = T b
  /// with K_0 = [A, B^T; B, C] and T = [I, gamma B^T W^-1; 0, I] (the same
  /// x; docs: Augmented Lagrangian factor), whose blocks it applies cell by
  /// cell:
  /// - A_gamma = A + B^T Gamma B (Gamma = gamma W^-1): the general
  ///   MatrixFreeTangent on a displacement-only Q2 DoFHandler of the same
  ///   mesh, with its pressure coupling (the stored J F^-T of the points and
  ///   Gamma per cell), and the follower pressure's face term;
  /// - the pressure rows B u + C p and the columns B^T (p + Gamma C p);
  /// - FGMRES (restart 100) preconditioned by the upper block-triangular
  ///   [A_gamma, B^T + G C; 0, S]^-1 of the matrix-based solver: S the
  ///   scaled pressure mass matrix, inverted cell by cell (a discontinuous
  ///   pressure), and for A_gamma one V-cycle of MatrixFreeSolver's
  ///   p-multigrid (Chebyshev with the matrix-free diagonal of A_gamma, the
  ///   Q1 Galerkin matrix of A_gamma by MUMPS LDL^T).
  /// The Problem refills the tangent with the pressure coupling where the
  /// matrix-based solvers assemble their matrix (assembly.cc). Vectors of
  /// solve() are in the Problem's numbering (FieldLayout); the displacement
  /// DoFs are mapped to the displacement DoFHandler's once.
  class MatrixFreeMixedSolver : public LinearSolver
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;

    /// @param[in] dof_handler the mixed DoFs (FESystem of 3 FE_Q(2) and one
    ///   FE_DGP(1) on hexahedra), renumbered by @p layout; throws (naming
    ///   the alternatives) for another element. @p make_constraints builds
    ///   the constraints of a displacement DoFHandler as the problem's. The
    ///   references must outlive the solver.
    MatrixFreeMixedSolver(
      const dealii::Mapping<3>                &mapping,
      const dealii::DoFHandler<3>             &dof_handler,
      const FieldLayout                       &layout,
      const MatrixFreeSolver::MakeConstraints &make_constraints,
      const double                             tolerance);
    ~MatrixFreeMixedSolver() override;

    void
    setup(const LA::MPI::SparseMatrix &K,
          const PressureMatrix        *schur        = nullptr,
          const LA::MPI::SparseMatrix *augmentation = nullptr) override;

    unsigned int
    solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) override;

    void
    set_tolerance(const double tolerance) override;

    /// The displacement block's tangent (on the displacement DoFHandler):
    /// the Problem fills it with MatrixFreeTangent::update(const
    /// MixedCellTangents &, ...).
    MatrixFreeTangent *
    matrix_free_tangent() override;

    MatrixFreeMixedSolver *
    matrix_free_mixed() override
    {
      return this;
    }

    /// dst = K_0 src, the tangent itself (not T K_0), in the Problem's
    /// numbering (the finite-difference check ProblemChecks::tangent_error()).
    /// After setup(). Collective.
    void
    vmult(LA::MPI::Vector &dst, const LA::MPI::Vector &src) const;

    /// The displacement DoFHandler of the tangent.
    const dealii::DoFHandler<3> &
    displacement_dof_handler() const;

    /// The displacement part of @p mixed (the Problem's numbering, owned
    /// entries) in the tangent's layout.
    void
    displacement_of(const LA::MPI::Vector &mixed, Vector &u) const;

    std::string
    name() const override;

    /// Bytes of this rank (the displacement solver's and the maps).
    std::size_t
    memory_consumption() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Mechanics
