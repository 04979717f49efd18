#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "mechanics/linear_solver.h"

#include <functional>
#include <memory>
#include <string>

namespace systole::Mechanics
{
  class MatrixFreeTangent;

  /// Linear solver = matrix-free (issue 40): Krylov on the general
  /// MatrixFreeTangent (Q2 hexahedra, the penalty formulation; the tangent
  /// of the assembly's own point kernel, with the follower pressure's face
  /// term), no sparse Q2 matrix at all. The solver owns the tangent; the
  /// Problem refills it where the matrix-based solvers assemble their matrix
  /// (Problem::Impl::assemble()).
  ///
  /// - Krylov: CG when the tangent is symmetric, else GMRES (right
  ///   preconditioned); either stops at |K x - b| <= tolerance |b|, on
  ///   LinearAlgebra::distributed::Vector;
  /// - preconditioner: one two-level p-multigrid V-cycle Q2 -> Q1 on the
  ///   same mesh: Chebyshev smoothing (degree 4, deal.II's
  ///   PreconditionChebyshev) with the inverse diagonal of the matrix-free
  ///   tangent (its bulk term, summed from the stored points), before
  ///   and after the coarse correction; the transfer MGTwoLevelTransfer
  ///   (polynomial); the coarse matrix on FE_Q(1)^3 assembled from the same
  ///   cached dP/dF at the same Q2 quadrature points (MatrixFree with both
  ///   DoFHandlers: the Galerkin projection P^T K P of the bulk term, the
  ///   follower pressure left out: symmetric), solved by MUMPS LDL^T
  ///   through PETSc (PETSc options prefix -mechanics_mf_coarse_, e.g.
  ///   -mechanics_mf_coarse_pc_type gamg: the six rigid-body modes of the Q1
  ///   space are its near-null space).
  /// setup() builds the preconditioner (the diagonal, the Chebyshev
  /// eigenvalue estimate, the coarse matrix and its factorization) from the
  /// tangent as last updated and ignores its matrix argument; solve() uses
  /// the tangent as it is then (a Newton chord reuses the preconditioner, as
  /// the matrix-based iterative solver does).
  /// Throws the matrix-free solvers' error for a Krylov solve (@p what)
  /// that did not converge in @p iterations to @p residual, naming the
  /// alternatives.
  [[noreturn]] void
  throw_no_convergence(const std::string &what,
                       const unsigned int iterations,
                       const double       residual);

  class MatrixFreeSolver : public LinearSolver
  {
  public:
    /// Builds the constraints of a displacement DoFHandler as the problem's
    /// (fixed and sliding boundaries, hanging nodes), for the Q1 level.
    using MakeConstraints =
      std::function<void(const dealii::DoFHandler<3> &,
                         dealii::AffineConstraints<double> &)>;

    /// @param[in] dof_handler the Q2 displacement (FESystem of 3 FE_Q(2) on
    ///   hexahedra), @p constraints its (homogeneous) constraints. All must
    ///   outlive the solver. Throws (naming the alternatives) for another
    ///   element.
    /// @param[in] tolerance relative residual reduction of the Krylov solve
    /// @param[in] symmetric whether the tangent is symmetric (CG, else
    ///   GMRES): a follower pressure is symmetric only on a cavity whose rim
    ///   stays in the base plane (Problem's symmetric_tangent())
    MatrixFreeSolver(const dealii::Mapping<3>                &mapping,
                     const dealii::DoFHandler<3>             &dof_handler,
                     const dealii::AffineConstraints<double> &constraints,
                     const MakeConstraints                   &make_constraints,
                     const double                             tolerance,
                     const bool                               symmetric);
    ~MatrixFreeSolver() override;

    /// The tangent the solves use (general, Variant::cached, with the
    /// boundary faces and the Q1 level).
    MatrixFreeTangent &
    tangent();

    void
    setup(const LA::MPI::SparseMatrix &K,
          const PressureMatrix        *schur        = nullptr,
          const LA::MPI::SparseMatrix *augmentation = nullptr) override;

    unsigned int
    solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) override;

    void
    set_tolerance(const double tolerance) override;

    MatrixFreeTangent *
    matrix_free_tangent() override;

    /// One V-cycle of the preconditioner built by the last setup(): dst =
    /// M^-1 src (in the tangent's layout; MatrixFreeMixedSolver's
    /// displacement block).
    void
    precondition(
      dealii::LinearAlgebra::distributed::Vector<double>       &dst,
      const dealii::LinearAlgebra::distributed::Vector<double> &src) const;

    std::string
    name() const override;

    /// Bytes of this rank: the tangent (MatrixFree, point storage), the
    /// Q1 level (DoFs, matrix and its factorization not counted: PETSc's),
    /// the smoother's diagonal.
    std::size_t
    memory_consumption() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Mechanics
