#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>

#include "base/linear_algebra.h"
#include "mechanics/parameters.h"
#include "mechanics/petsc_tools.h"

#include <petscmat.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace systole::Mechanics
{
  class FieldLayout;
  class MatrixFreeTangent;
  class MatrixFreeMixedSolver;

  /// A PETSc matrix on the pressure DoFs alone (block 1 of a FieldLayout,
  /// numbered in the order of the global DoFs): the approximation
  /// @f$-(1/\mu + 1/\kappa) M_p@f$ of the pressure Schur complement
  /// @f$-M_p/\kappa - B A^{-1} B^T@f$ that preconditions the mixed systems.
  class PressureMatrix
  {
  public:
    /// @param[in] layout the renumbered layout (its owned pressure ranges)
    /// @param[in] row_length upper bound of the entries per row
    PressureMatrix(const FieldLayout &layout,
                   const MPI_Comm     comm,
                   const unsigned int row_length);
    ~PressureMatrix();
    PressureMatrix(const PressureMatrix &) = delete;
    PressureMatrix &
    operator=(const PressureMatrix &) = delete;

    /// Set all entries to zero (keeps the pattern).
    void
    zero();

    /// Add the cell matrix @p local of the pressure DoFs @p dofs (global DoF
    /// indices of block 1, any owner).
    void
    add(const std::vector<dealii::types::global_dof_index> &dofs,
        const dealii::FullMatrix<double>                   &local);

    /// Exchange the entries of other ranks' rows (collective).
    void
    compress();

    Mat
    petsc() const
    {
      return matrix;
    }

  private:
    PetscInt
    index(const dealii::types::global_dof_index dof) const;

    Mat matrix = nullptr;
    /// Per rank: first pressure DoF, number of pressure DoFs, first index in
    /// the pressure numbering.
    std::vector<dealii::types::global_dof_index> first, count, offset;
    std::vector<PetscInt>                        rows;
    std::vector<PetscScalar>                     values;
  };

  /// Solves K x = b for the mechanics tangent.
  /// - "direct": MUMPS, LDL^T for symmetric matrices (also the symmetric
  ///   indefinite mixed systems), LU otherwise;
  /// - "iterative", penalty formulation: GMRES preconditioned by PETSc's
  ///   smoothed-aggregation multigrid GAMG, given the six rigid-body modes of
  ///   the displacement as near-null space;
  /// - "iterative", mixed formulations: FGMRES with PETSc's PCFIELDSPLIT
  ///   Schur preconditioner (upper block-triangular): one GAMG V-cycle (with
  ///   the rigid-body modes and block size 3) for the displacement block, and
  ///   the PressureMatrix (block Jacobi + ILU: exact for a discontinuous
  ///   pressure) for the Schur complement. PETSc options with the prefix
  ///   -mechanics_ (e.g. in PETSC_OPTIONS) override the choices.
  /// With DisplacementPreconditioner::p_multigrid and Q2 displacements, the
  /// GAMG V-cycle (on the displacement block, or on K for the penalty, then
  /// with FGMRES) is replaced by a PMultigrid V-cycle (options prefix
  /// -mechanics_fieldsplit_u_pmg_, penalty -mechanics_pmg_).
  class LinearSolver
  {
  public:
    virtual ~LinearSolver() = default;

    /// Prepare solves with @p K (the direct solver factorizes it; the
    /// iterative ones build their preconditioner; the mixed iterative one
    /// needs @p schur). With @p augmentation G (the mixed iterative solver's
    /// augmented Lagrangian), @p K is T K_0 with T = [I, G; 0, I], and
    /// solve() applies T to its right-hand side: it solves K_0 x = b. All
    /// must stay alive and unchanged until the next setup().
    virtual void
    setup(const LA::MPI::SparseMatrix &K,
          const PressureMatrix        *schur        = nullptr,
          const LA::MPI::SparseMatrix *augmentation = nullptr) = 0;

    /// Solve K x = b with the K of the last setup(); returns the number of
    /// iterations (1 for the direct solver). Several right-hand sides share
    /// one factorization. Throws ExcMessage when the solve fails (the Newton
    /// loop treats that as a failed step).
    virtual unsigned int
    solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) = 0;

    /// The relative residual reduction of the next solves (the iterative
    /// solvers; the direct one ignores it). Newton's forcing terms set it
    /// per update (ForcingTerm).
    virtual void
    set_tolerance(const double)
    {}

    /// Number of negative pivots of the last LDL^T factorization (MUMPS
    /// INFOG(12)), the number of negative eigenvalues of K (Sylvester's law
    /// of inertia); -1 when unknown (LU, iterative solvers). A stable
    /// equilibrium of the mixed formulation has exactly as many as there are
    /// pressure DoFs (the saddle point), of the penalty one none.
    virtual long
    negative_pivots() const
    {
      return -1;
    }

    /// Whether solve() is a back substitution with a factorization (much
    /// cheaper than setup()), not a Krylov solve (as costly as a few
    /// preconditioner set-ups).
    virtual bool
    direct() const
    {
      return false;
    }

    /// Whether this solver needs the PressureMatrix in setup().
    virtual bool
    needs_pressure_matrix() const
    {
      return false;
    }

    /// The matrix-free solver's tangent, which the Problem refills instead
    /// of assembling a matrix (MatrixFreeSolver); nullptr for the
    /// matrix-based solvers.
    virtual MatrixFreeTangent *
    matrix_free_tangent()
    {
      return nullptr;
    }

    /// The matrix-free solver of the mixed formulations (whose tangent the
    /// Problem fills with the pressure coupling); nullptr for the others.
    virtual MatrixFreeMixedSolver *
    matrix_free_mixed()
    {
      return nullptr;
    }

    virtual std::string
    name() const = 0;
  };

  /// What create_linear_solver() builds a solver from.
  struct LinearSolverInputs
  {
    const std::string           &type; ///< "direct" or "iterative"
    const dealii::Mapping<3, 3> &mapping;
    /// the mechanics DoFs, renumbered by layout (for the rigid-body modes
    /// and the blocks)
    const dealii::DoFHandler<3, 3> &dof_handler;
    const FieldLayout              &layout;
    /// the constraints of the tangent (p-multigrid)
    const dealii::AffineConstraints<double> &constraints;
    /// relative residual reduction of the iterative solver
    double tolerance;
    /// whether the matrices are symmetric (the direct solver then
    /// factorizes LDL^T, about half the work of LU)
    bool symmetric;
    /// of the displacement (block) of the iterative solvers; p-multigrid
    /// falls back to GAMG for Q1 (the name() says so)
    DisplacementPreconditioner preconditioner;
  };

  /// The solver named @p in.type.
  std::unique_ptr<LinearSolver>
  create_linear_solver(const LinearSolverInputs &in);
} // namespace systole::Mechanics
