#include "mechanics/linear_solver.h"

#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/solver_control.h>

#include <petscksp.h>

#include <array>

namespace systole::Mechanics
{
  namespace
  {
    void
    check_petsc(const PetscErrorCode code, const char *what)
    {
      AssertThrow(code == 0,
                  dealii::ExcMessage(std::string("PETSc failed in ") + what +
                                     " (error code " + std::to_string(code) +
                                     ")."));
    }

    /// MUMPS through PETSc (KSPPREONLY): Cholesky (LDL^T) for symmetric
    /// matrices, LU otherwise. A new factorization per setup(); the solves
    /// after it reuse it.
    class DirectSolver : public LinearSolver
    {
    public:
      explicit DirectSolver(const bool symmetric)
        : symmetric(symmetric)
      {}

      ~DirectSolver() override
      {
        KSPDestroy(&ksp);
      }

      void
      setup(const LA::MPI::SparseMatrix &K) override
      {
        // The sparsity pattern never changes: after the first factorization
        // MUMPS reuses its analysis (ordering, symbolic factorization) and
        // factorizes numerically only. If that fails (pivoting needs more
        // room than the old analysis planned), analyse afresh once.
        if (ksp != nullptr && factorize(K, true))
          return;
        KSPDestroy(&ksp);
        AssertThrow(factorize(K, false),
                    dealii::ExcMessage(
                      "MUMPS could not factorize the tangent (PETSc PC "
                      "failure reason " +
                      std::to_string(static_cast<int>(failure)) +
                      "): it is singular; is the body held against rigid "
                      "motions (Mechanics / Fixed boundaries)?"));
      }

      unsigned int
      solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) override
      {
        Assert(ksp != nullptr, dealii::ExcMessage("setup() first"));
        check_petsc(KSPSolve(ksp, b, x), "KSPSolve (MUMPS)");
        KSPConvergedReason reason;
        KSPGetConvergedReason(ksp, &reason);
        AssertThrow(reason >= 0,
                    dealii::ExcMessage("MUMPS failed (PETSc reason " +
                                       std::to_string(reason) + ")."));
        return 1;
      }

      std::string
      name() const override
      {
        return symmetric ? "direct (MUMPS, symmetric LDL^T)"
                         : "direct (MUMPS LU)";
      }

    private:
      /// Factorize @p K with the existing solver (@p reuse) or a new one;
      /// false if the factorization failed.
      bool
      factorize(const LA::MPI::SparseMatrix &K, const bool reuse)
      {
        Mat A = K;
        if (!reuse)
          {
            check_petsc(KSPCreate(K.get_mpi_communicator(), &ksp), "KSPCreate");
            check_petsc(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
            PC pc;
            check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
            check_petsc(PCSetType(pc, symmetric ? PCCHOLESKY : PCLU),
                        "PCSetType");
            check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS),
                        "PCFactorSetMatSolverType");
            check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
            // Room for delayed pivots when the analysis is reused.
            check_petsc(PCFactorSetUpMatSolverType(pc),
                        "PCFactorSetUpMatSolverType");
            Mat F;
            check_petsc(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
            check_petsc(MatMumpsSetIcntl(F, 14, 100), "MatMumpsSetIcntl");
          }
        else
          check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
        const PetscErrorCode code = KSPSetUp(ksp);
        PC                   pc;
        KSPGetPC(ksp, &pc);
        failure = PC_NOERROR;
        PCGetFailedReason(pc, &failure);
        return code == 0 && failure == PC_NOERROR;
      }

      bool           symmetric;
      KSP            ksp     = nullptr;
      PCFailedReason failure = PC_NOERROR;
    };

    /// GMRES + GAMG with the rigid-body modes as near-null space.
    class IterativeSolver : public LinearSolver
    {
    public:
      IterativeSolver(const dealii::Mapping<3, 3>    &mapping,
                      const dealii::DoFHandler<3, 3> &dof_handler,
                      const double                    tolerance)
        : tolerance(tolerance)
      {
        const MPI_Comm comm  = dof_handler.get_communicator();
        const auto    &owned = dof_handler.locally_owned_dofs();
        for (auto &mode : modes)
          mode.reinit(owned, comm);

        // Position and component of every locally owned DoF.
        const auto                 &fe = dof_handler.get_fe();
        const dealii::Quadrature<3> support(fe.get_unit_support_points());
        dealii::FEValues<3>         fe_values(mapping,
                                      fe,
                                      support,
                                      dealii::update_quadrature_points);
        std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              fe_values.reinit(cell);
              cell->get_dof_indices(dofs);
              for (unsigned int i = 0; i < dofs.size(); ++i)
                if (owned.is_element(dofs[i]))
                  {
                    const unsigned int c =
                      fe.system_to_component_index(i).first;
                    const auto &x     = fe_values.quadrature_point(i);
                    modes[c](dofs[i]) = 1.0; // translations
                    // rotations about the axes: (e_k x x)_c
                    const unsigned int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
                    // (e_k x x)_c = eps_{c k m} x_m: nonzero for k = c1 (x_c2)
                    // and k = c2 (-x_c1).
                    modes[3 + c1](dofs[i]) = x[c2];
                    modes[3 + c2](dofs[i]) = -x[c1];
                  }
            }
        for (auto &mode : modes)
          mode.compress(dealii::VectorOperation::insert);

        // Orthonormalize (modified Gram-Schmidt), as PETSc requires.
        for (unsigned int i = 0; i < modes.size(); ++i)
          {
            for (unsigned int j = 0; j < i; ++j)
              modes[i].add(-(modes[i] * modes[j]), modes[j]);
            modes[i] /= modes[i].l2_norm();
          }

        check_petsc(KSPCreate(comm, &ksp), "KSPCreate");
        check_petsc(KSPSetType(ksp, KSPGMRES), "KSPSetType");
        check_petsc(KSPGMRESSetRestart(ksp, 200), "KSPGMRESSetRestart");
        PC pc;
        check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
        check_petsc(PCSetType(pc, PCGAMG), "PCSetType");
        check_petsc(KSPSetTolerances(ksp, tolerance, 1e-300, 1e10, 2000),
                    "KSPSetTolerances");
      }

      ~IterativeSolver() override
      {
        KSPDestroy(&ksp);
      }

      void
      setup(const LA::MPI::SparseMatrix &K) override
      {
        Mat                A = K;
        std::array<Vec, 6> vectors;
        for (unsigned int i = 0; i < 6; ++i)
          vectors[i] = modes[i];
        MatNullSpace near_null_space;
        check_petsc(MatNullSpaceCreate(K.get_mpi_communicator(),
                                       PETSC_FALSE,
                                       6,
                                       vectors.data(),
                                       &near_null_space),
                    "MatNullSpaceCreate");
        check_petsc(MatSetNearNullSpace(A, near_null_space),
                    "MatSetNearNullSpace");
        MatNullSpaceDestroy(&near_null_space);

        check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
      }

      unsigned int
      solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) override
      {
        x = 0;
        check_petsc(KSPSolve(ksp, b, x), "KSPSolve");
        KSPConvergedReason reason;
        KSPGetConvergedReason(ksp, &reason);
        PetscInt iterations = 0;
        KSPGetIterationNumber(ksp, &iterations);
        AssertThrow(reason > 0,
                    dealii::ExcMessage(
                      "The iterative linear solver (GMRES + GAMG) did not "
                      "converge (PETSc reason " +
                      std::to_string(reason) + ", " +
                      std::to_string(iterations) +
                      " iterations). Try Mechanics / Linear solver = direct."));
        return iterations;
      }

      std::string
      name() const override
      {
        return "iterative (GMRES + GAMG)";
      }

    private:
      double                         tolerance;
      std::array<LA::MPI::Vector, 6> modes;
      KSP                            ksp = nullptr;
    };
  } // namespace

  std::unique_ptr<LinearSolver>
  create_linear_solver(const std::string              &type,
                       const dealii::Mapping<3, 3>    &mapping,
                       const dealii::DoFHandler<3, 3> &dof_handler,
                       const double                    tolerance,
                       const bool                      symmetric)
  {
    if (type == "direct")
      return std::make_unique<DirectSolver>(symmetric);
    AssertThrow(type == "iterative",
                dealii::ExcMessage("Unknown linear solver '" + type + "'."));
    return std::make_unique<IterativeSolver>(mapping, dof_handler, tolerance);
  }
} // namespace systole::Mechanics
