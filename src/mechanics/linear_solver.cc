#include "mechanics/linear_solver.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/solver_control.h>

#include "mechanics/field_layout.h"
#include "mechanics/p_multigrid.h"
#include "mechanics/petsc_tools.h"

#include <petscksp.h>

#include <algorithm>
#include <array>

namespace systole::Mechanics
{
  namespace
  {
    /// A solver of the penalty formulation's systems (displacement only): no
    /// pressure matrix and no augmentation.
    class PenaltySolver : public LinearSolver
    {
    public:
      void
      setup(const LA::MPI::SparseMatrix &K,
            const PressureMatrix *,
            const LA::MPI::SparseMatrix *augmentation) final
      {
        AssertThrow(augmentation == nullptr,
                    dealii::ExcInternalError("augmented penalty solve"));
        setup_displacement(K);
      }

    protected:
      /// setup() with the displacement tangent @p K.
      virtual void
      setup_displacement(const LA::MPI::SparseMatrix &K) = 0;
    };

    /// MUMPS through PETSc (KSPPREONLY): Cholesky (LDL^T) for symmetric
    /// matrices, LU otherwise. A new factorization per setup(); the solves
    /// after it reuse it.
    class DirectSolver : public PenaltySolver
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
      setup_displacement(const LA::MPI::SparseMatrix &K) override
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
            // PETSc options with the prefix -mechanics_direct_ (e.g.
            // -mechanics_direct_mat_mumps_icntl_7 for the ordering) apply.
            check_petsc(KSPSetOptionsPrefix(ksp, "mechanics_direct_"),
                        "KSPSetOptionsPrefix");
            check_petsc(KSPSetFromOptions(ksp), "KSPSetFromOptions");
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
        negative = -1;
        if (code == 0 && failure == PC_NOERROR && symmetric)
          {
            Mat      F;
            PetscInt n = -1;
            if (PCFactorGetMatrix(pc, &F) == 0 &&
                MatMumpsGetInfog(F, 12, &n) == 0)
              negative = n;
          }
        return code == 0 && failure == PC_NOERROR;
      }

    public:
      long
      negative_pivots() const override
      {
        return negative;
      }

      bool
      direct() const override
      {
        return true;
      }

    private:
      long negative = -1;

      bool           symmetric;
      KSP            ksp     = nullptr;
      PCFailedReason failure = PC_NOERROR;
    };

    /// Throws with the Krylov method's PETSc reason when it did not
    /// converge; returns the iterations.
    unsigned int
    checked_iterations(KSP ksp, const std::string &what)
    {
      KSPConvergedReason reason;
      KSPGetConvergedReason(ksp, &reason);
      PetscInt iterations = 0;
      KSPGetIterationNumber(ksp, &iterations);
      AssertThrow(reason > 0,
                  dealii::ExcMessage(
                    "The iterative linear solver (" + what +
                    ") did not converge (PETSc reason " +
                    std::to_string(reason) + ", " + std::to_string(iterations) +
                    " iterations). Try Mechanics / Linear solver = direct."));
      return iterations;
    }

    /// GMRES + GAMG with the rigid-body modes as near-null space (the
    /// penalty formulation: displacement only), or FGMRES + p-multigrid (its
    /// smoothers make the preconditioner vary from one application to the
    /// next).
    class IterativeSolver : public PenaltySolver
    {
    public:
      IterativeSolver(const dealii::Mapping<3, 3>    &mapping,
                      const dealii::DoFHandler<3, 3> &dof_handler,
                      const double                    tolerance,
                      std::unique_ptr<PMultigrid>     p_multigrid,
                      const std::string              &fallback)
        : modes(rigid_body_modes(mapping, dof_handler))
        , p_multigrid(std::move(p_multigrid))
        , fallback(fallback)
      {
        check_petsc(KSPCreate(dof_handler.get_communicator(), &ksp),
                    "KSPCreate");
        check_petsc(KSPSetType(ksp, this->p_multigrid ? KSPFGMRES : KSPGMRES),
                    "KSPSetType");
        check_petsc(KSPGMRESSetRestart(ksp, 200), "KSPGMRESSetRestart");
        PC pc;
        check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
        if (this->p_multigrid)
          this->p_multigrid->attach(pc);
        else
          check_petsc(PCSetType(pc, PCGAMG), "PCSetType");
        IterativeSolver::set_tolerance(tolerance);
      }

      ~IterativeSolver() override
      {
        KSPDestroy(&ksp);
      }

      void
      setup_displacement(const LA::MPI::SparseMatrix &K) override
      {
        Mat A = K;
        set_near_null_space(A, modes);
        check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
      }

      void
      set_tolerance(const double tolerance) override
      {
        check_petsc(KSPSetTolerances(ksp, tolerance, 1e-300, 1e10, 2000),
                    "KSPSetTolerances");
      }

      unsigned int
      solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) override
      {
        x = 0;
        check_petsc(KSPSolve(ksp, b, x), "KSPSolve");
        return checked_iterations(ksp,
                                  p_multigrid ? "FGMRES + p-multigrid"
                                              : "GMRES + GAMG");
      }

      std::string
      name() const override
      {
        return p_multigrid ? "iterative (FGMRES + " + p_multigrid->name() + ")"
                           : "iterative (GMRES + GAMG" + fallback + ")";
      }

    private:
      std::array<LA::MPI::Vector, 6> modes;
      /// Null for GAMG. The PC of ksp points into it (ksp is destroyed
      /// first, in the destructor's body).
      std::unique_ptr<PMultigrid> p_multigrid;
      /// Why GAMG although p-multigrid was asked for ("" otherwise).
      std::string fallback;
      KSP         ksp = nullptr;
    };

    /// FGMRES with the block (Schur) preconditioner of the mixed systems.
    class BlockSolver : public LinearSolver
    {
    public:
      BlockSolver(const dealii::Mapping<3, 3>    &mapping,
                  const dealii::DoFHandler<3, 3> &dof_handler,
                  const FieldLayout              &layout,
                  const double                    tolerance,
                  std::unique_ptr<PMultigrid>     p_multigrid,
                  const std::string              &fallback)
        : p_multigrid(std::move(p_multigrid))
        , fallback(fallback)
      {
        const MPI_Comm comm = dof_handler.get_communicator();
        const auto    &u    = layout.owned(0);
        const auto    &p    = layout.owned(1);
        const PetscInt n_u  = u.n_elements();
        const PetscInt n_p  = p.n_elements();
        const PetscInt u0   = n_u > 0 ? *u.begin() : 0;
        const PetscInt p0   = n_p > 0 ? *p.begin() : u0 + n_u;
        check_petsc(ISCreateStride(comm, n_u, u0, 1, &is_u), "ISCreateStride");
        check_petsc(ISCreateStride(comm, n_p, p0, 1, &is_p), "ISCreateStride");
        if (layout.displacement_interleaved())
          check_petsc(ISSetBlockSize(is_u, 3), "ISSetBlockSize");

        // The rigid-body modes restricted to the displacement block, as the
        // near-null space of its submatrix (PCFIELDSPLIT looks it up on the
        // IS).
        const auto         modes = rigid_body_modes(mapping, dof_handler);
        std::array<Vec, 6> sub;
        for (unsigned int i = 0; i < 6; ++i)
          {
            check_petsc(VecCreateMPI(comm, n_u, PETSC_DETERMINE, &sub[i]),
                        "VecCreateMPI");
            if (layout.displacement_interleaved())
              VecSetBlockSize(sub[i], 3);
            const PetscScalar *full;
            PetscScalar       *part;
            VecGetArrayRead(modes[i], &full);
            VecGetArray(sub[i], &part);
            std::copy(full, full + n_u, part);
            VecRestoreArray(sub[i], &part);
            VecRestoreArrayRead(modes[i], &full);
          }
        MatNullSpace near_null_space;
        check_petsc(MatNullSpaceCreate(comm,
                                       PETSC_FALSE,
                                       6,
                                       sub.data(),
                                       &near_null_space),
                    "MatNullSpaceCreate");
        check_petsc(PetscObjectCompose(reinterpret_cast<PetscObject>(is_u),
                                       "nearnullspace",
                                       reinterpret_cast<PetscObject>(
                                         near_null_space)),
                    "PetscObjectCompose");
        MatNullSpaceDestroy(&near_null_space);
        for (auto &v : sub)
          VecDestroy(&v);

        // Defaults, unless given in PETSc's options database.
        const std::string prefix = "-mechanics_";
        set_default_petsc_option(prefix + "pc_fieldsplit_type", "schur");
        set_default_petsc_option(prefix + "pc_fieldsplit_schur_fact_type",
                                 "upper");
        set_default_petsc_option(prefix + "fieldsplit_u_ksp_type", "preonly");
        // The displacement block's PC (GAMG or p-multigrid) is set on the
        // split's KSP below, not here: a default in the options database
        // would also be the next solver's. GAMG's smoothing: two GMRES
        // iterations with Jacobi: the tangent of a follower pressure on an open
        // surface is not symmetric, and with PETSc's default (Chebyshev-Jacobi)
        // FGMRES stalls on the bending beam of Land problem 1 refined twice;
        // SOR smoothing breaks down in GAMG's eigenvalue estimate there.
        set_default_petsc_option(prefix + "fieldsplit_u_mg_levels_ksp_type",
                                 "gmres");
        set_default_petsc_option(prefix + "fieldsplit_u_mg_levels_ksp_max_it",
                                 "2");
        set_default_petsc_option(prefix + "fieldsplit_u_mg_levels_pc_type",
                                 "jacobi");
        set_default_petsc_option(prefix + "fieldsplit_p_ksp_type", "preonly");
        set_default_petsc_option(prefix + "fieldsplit_p_pc_type", "bjacobi");

        check_petsc(KSPCreate(comm, &ksp), "KSPCreate");
        check_petsc(KSPSetOptionsPrefix(ksp, "mechanics_"),
                    "KSPSetOptionsPrefix");
        check_petsc(KSPSetType(ksp, KSPFGMRES), "KSPSetType");
        check_petsc(KSPGMRESSetRestart(ksp, 100), "KSPGMRESSetRestart");
        BlockSolver::set_tolerance(tolerance);
        PC pc;
        check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
        check_petsc(PCSetType(pc, PCFIELDSPLIT), "PCSetType");
        check_petsc(PCFieldSplitSetIS(pc, "u", is_u), "PCFieldSplitSetIS");
        check_petsc(PCFieldSplitSetIS(pc, "p", is_p), "PCFieldSplitSetIS");
        // The split's solvers exist from PCFieldSplitSetIS on; before the
        // options make the split a Schur one, PETSc hands them out without a
        // set-up. -mechanics_fieldsplit_u_pc_type still overrides the choice
        // (the split reads its options at the first set-up).
        KSP     *splits   = nullptr;
        PetscInt n_splits = 0;
        check_petsc(PCFieldSplitGetSubKSP(pc, &n_splits, &splits),
                    "PCFieldSplitGetSubKSP");
        PC pc_u;
        check_petsc(KSPGetPC(splits[0], &pc_u), "KSPGetPC");
        PetscFree(splits);
        if (this->p_multigrid)
          this->p_multigrid->attach(pc_u);
        else
          check_petsc(PCSetType(pc_u, PCGAMG), "PCSetType");
      }

      ~BlockSolver() override
      {
        KSPDestroy(&ksp);
        ISDestroy(&is_u);
        ISDestroy(&is_p);
      }

      void
      setup(const LA::MPI::SparseMatrix &K,
            const PressureMatrix        *schur,
            const LA::MPI::SparseMatrix *augmentation) override
      {
        AssertThrow(schur != nullptr,
                    dealii::ExcInternalError("no pressure matrix"));
        this->augmentation = augmentation;
        Mat A              = K;
        check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
        // (The options first: they would reset the Schur preconditioner to
        // PETSc's default, the pressure block of K, zero when
        // incompressible.)
        if (!configured)
          {
            check_petsc(KSPSetFromOptions(ksp), "KSPSetFromOptions");
            configured = true;
          }
        PC pc;
        check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
        check_petsc(PCFieldSplitSetSchurPre(pc,
                                            PC_FIELDSPLIT_SCHUR_PRE_USER,
                                            schur->petsc()),
                    "PCFieldSplitSetSchurPre");
      }

      unsigned int
      solve(LA::MPI::Vector &x, const LA::MPI::Vector &b) override
      {
        x = 0;
        if (augmentation != nullptr)
          {
            // T b = b + G b (G reads the pressure part, writes the
            // displacement part).
            augmented = b;
            augmentation->vmult_add(augmented, b);
            check_petsc(KSPSolve(ksp, augmented, x), "KSPSolve");
          }
        else
          check_petsc(KSPSolve(ksp, b, x), "KSPSolve");
        return checked_iterations(ksp, "FGMRES + block preconditioner");
      }

      void
      set_tolerance(const double tolerance) override
      {
        check_petsc(KSPSetTolerances(ksp, tolerance, 1e-300, 1e10, 1000),
                    "KSPSetTolerances");
      }

      bool
      needs_pressure_matrix() const override
      {
        return true;
      }

      std::string
      name() const override
      {
        return "iterative (FGMRES, Schur block preconditioner: " +
               (p_multigrid ? p_multigrid->name() : std::string("GAMG")) +
               " on u, scaled pressure mass matrix" + fallback + ")";
      }

    private:
      /// Null for GAMG. The displacement split's PC points into it (ksp is
      /// destroyed first, in the destructor's body).
      std::unique_ptr<PMultigrid> p_multigrid;
      /// Why GAMG although p-multigrid was asked for ("" otherwise).
      std::string fallback;
      bool        configured = false;
      /// G of the augmented Lagrangian (null: none), and T b.
      const LA::MPI::SparseMatrix *augmentation = nullptr;
      LA::MPI::Vector              augmented;
      KSP                          ksp  = nullptr;
      IS                           is_u = nullptr, is_p = nullptr;
    };
  } // namespace

  std::unique_ptr<LinearSolver>
  create_linear_solver(const LinearSolverInputs &in)
  {
    if (in.type == "direct")
      return std::make_unique<DirectSolver>(in.symmetric);
    AssertThrow(in.type == "iterative",
                dealii::ExcMessage("Unknown linear solver '" + in.type + "'."));
    // p-multigrid needs a coarser degree: Q1 displacements get GAMG, and the
    // solver's name (in the run banner) says why.
    std::unique_ptr<PMultigrid> p_multigrid;
    std::string                 fallback;
    if (in.preconditioner == DisplacementPreconditioner::p_multigrid)
      {
        if (PMultigrid::applicable(in.dof_handler))
          p_multigrid =
            std::make_unique<PMultigrid>(in.mapping,
                                         in.dof_handler,
                                         in.layout,
                                         in.constraints,
                                         in.layout.mixed()
                                           ? "mechanics_fieldsplit_u_pmg_"
                                           : "mechanics_pmg_");
        else
          fallback = "; not the p-multigrid asked for: Q1 displacements "
                     "have no coarser degree";
      }
    if (in.layout.mixed())
      return std::make_unique<BlockSolver>(in.mapping,
                                           in.dof_handler,
                                           in.layout,
                                           in.tolerance,
                                           std::move(p_multigrid),
                                           fallback);
    return std::make_unique<IterativeSolver>(in.mapping,
                                             in.dof_handler,
                                             in.tolerance,
                                             std::move(p_multigrid),
                                             fallback);
  }

  PressureMatrix::PressureMatrix(const FieldLayout &layout,
                                 const MPI_Comm     comm,
                                 const unsigned int row_length)
  {
    const auto &p       = layout.owned(1);
    const auto  n_local = p.n_elements();
    const auto  n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    const dealii::types::global_dof_index mine =
      n_local > 0 ? *p.begin() : dealii::numbers::invalid_dof_index;
    first = dealii::Utilities::MPI::all_gather(comm, mine);
    count = dealii::Utilities::MPI::all_gather(
      comm,
      static_cast<dealii::types::global_dof_index>(n_local));
    offset.assign(n_ranks, 0);
    for (unsigned int r = 1; r < n_ranks; ++r)
      offset[r] = offset[r - 1] + count[r - 1];
    // Keep the ranks that own pressure DoFs: their ranges are increasing, so
    // index() finds the owner by bisection (it is called for every entry).
    std::size_t kept = 0;
    for (unsigned int r = 0; r < n_ranks; ++r)
      if (count[r] > 0)
        {
          first[kept]  = first[r];
          count[kept]  = count[r];
          offset[kept] = offset[r];
          ++kept;
        }
    first.resize(kept);
    count.resize(kept);
    offset.resize(kept);
    check_petsc(MatCreateAIJ(comm,
                             n_local,
                             n_local,
                             PETSC_DETERMINE,
                             PETSC_DETERMINE,
                             row_length,
                             nullptr,
                             row_length,
                             nullptr,
                             &matrix),
                "MatCreateAIJ");
    check_petsc(MatSetOption(matrix,
                             MAT_NEW_NONZERO_ALLOCATION_ERR,
                             PETSC_FALSE),
                "MatSetOption");
  }

  PressureMatrix::~PressureMatrix()
  {
    MatDestroy(&matrix);
  }

  PetscInt
  PressureMatrix::index(const dealii::types::global_dof_index dof) const
  {
    const auto it = std::upper_bound(first.begin(), first.end(), dof);
    AssertThrow(it != first.begin(),
                dealii::ExcInternalError("not a pressure DoF"));
    const std::size_t r = (it - first.begin()) - 1;
    AssertThrow(dof < first[r] + count[r],
                dealii::ExcInternalError("not a pressure DoF"));
    return static_cast<PetscInt>(offset[r] + (dof - first[r]));
  }

  void
  PressureMatrix::zero()
  {
    check_petsc(MatZeroEntries(matrix), "MatZeroEntries");
  }

  void
  PressureMatrix::add(const std::vector<dealii::types::global_dof_index> &dofs,
                      const dealii::FullMatrix<double>                   &local)
  {
    rows.resize(dofs.size());
    values.resize(dofs.size() * dofs.size());
    for (unsigned int i = 0; i < dofs.size(); ++i)
      {
        rows[i] = index(dofs[i]);
        for (unsigned int j = 0; j < dofs.size(); ++j)
          values[i * dofs.size() + j] = local(i, j);
      }
    const auto n = static_cast<PetscInt>(rows.size());
    check_petsc(MatSetValues(matrix,
                             n,
                             rows.data(),
                             n,
                             rows.data(),
                             values.data(),
                             ADD_VALUES),
                "MatSetValues");
  }

  void
  PressureMatrix::compress()
  {
    check_petsc(MatAssemblyBegin(matrix, MAT_FINAL_ASSEMBLY),
                "MatAssemblyBegin");
    check_petsc(MatAssemblyEnd(matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  }
} // namespace systole::Mechanics
