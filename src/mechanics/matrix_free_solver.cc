// Linear solver = matrix-free: Krylov on the general MatrixFreeTangent with a
// two-level p-multigrid (Q2 -> Q1) that needs no Q2 matrix (issue 40).
#include "mechanics/matrix_free_solver.h"

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/diagonal_matrix.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/multigrid/mg_transfer_global_coarsening.h>

#include "mechanics/matrix_free_tangent.h"
#include "mechanics/matrix_free_tangent_impl.h"
#include "mechanics/petsc_tools.h"

#include <petscksp.h>

#include <array>
#include <cstdlib>

namespace systole::Mechanics
{
  using internal::Operator;
  using internal::Smoother;
  using Vector = MatrixFreeTangent::Vector;

  namespace
  {
    /// Chebyshev degree of the smoother (before and after the coarse
    /// correction) and the range of the spectrum it smooths.
    constexpr unsigned int smoothing_degree = 4;
    constexpr double       smoothing_range  = 20.0;
  } // namespace


  struct MatrixFreeSolver::Impl
  {
    /// The Q1 element and its DoFHandler on @p triangulation; the
    /// constructor of MatrixFreeSolver sets up the rest.
    Impl(const dealii::Triangulation<3> &triangulation,
         const double                    tolerance,
         const bool                      symmetric)
      : tolerance(tolerance)
      , symmetric(symmetric)
      , fe_q1(dealii::FE_Q<3>(1), 3)
      , q1(triangulation)
    {}

    ~Impl()
    {
      KSPDestroy(&coarse_ksp);
    }

    /// One V-cycle: dst = M^-1 src.
    void
    vmult(Vector &dst, const Vector &src) const;

    double                                   tolerance;
    const bool                               symmetric;
    dealii::FESystem<3>                      fe_q1;
    dealii::DoFHandler<3>                    q1;
    dealii::AffineConstraints<double>        q1_constraints;
    std::unique_ptr<MatrixFreeTangent>       tangent;
    dealii::MGTwoLevelTransfer<3, Vector>    transfer;
    Smoother                                 smoother;
    dealii::PETScWrappers::MPI::SparseMatrix coarse_matrix;
    std::array<LA::MPI::Vector, 6>           coarse_modes;
    KSP                                      coarse_ksp = nullptr;
    bool                                     ready      = false;
    /// Work vectors of vmult().
    mutable Vector          residual, coarse_rhs, coarse_solution;
    mutable LA::MPI::Vector coarse_b, coarse_x;
    mutable Vector          x_mf, b_mf;
  };


  void
  MatrixFreeSolver::Impl::vmult(Vector &dst, const Vector &src) const
  {
    const Operator &op = tangent->implementation();
    // Pre-smoothing from zero, the residual, its coarse correction.
    smoother.vmult(dst, src);
    op.vmult(residual, dst);
    residual.sadd(-1.0, 1.0, src);
    coarse_rhs = 0.0;
    transfer.restrict_and_add(coarse_rhs, residual);
    copy_owned(coarse_rhs, coarse_b);
    check_petsc(KSPSolve(coarse_ksp, coarse_b, coarse_x),
                "KSPSolve (matrix-free p-multigrid, Q1 level)");
    copy_owned(coarse_x, coarse_solution);
    transfer.prolongate_and_add(dst, coarse_solution);
    // Post-smoothing.
    smoother.step(dst, src);
  }


  void
  throw_no_convergence(const std::string &what,
                       const unsigned int iterations,
                       const double       residual)
  {
    AssertThrow(false,
                dealii::ExcMessage(
                  "The " + what + " linear solver did not converge (" +
                  std::to_string(iterations) + " iterations, residual " +
                  std::to_string(residual) +
                  "). Try Mechanics / Linear solver = iterative or direct."));
    std::abort(); // (not reached)
  }


  MatrixFreeSolver::MatrixFreeSolver(
    const dealii::Mapping<3>                &mapping,
    const dealii::DoFHandler<3>             &dof_handler,
    const dealii::AffineConstraints<double> &constraints,
    const MakeConstraints                   &make_constraints,
    const double                             tolerance,
    const bool                               symmetric)
    : impl(std::make_unique<Impl>(dof_handler.get_triangulation(),
                                  tolerance,
                                  symmetric))
  {
    Impl       &m  = *impl;
    const auto &fe = dof_handler.get_fe();
    AssertThrow(fe.n_components() == 3 && fe.degree == 2 &&
                  fe.reference_cell() == dealii::ReferenceCells::Hexahedron,
                dealii::ExcMessage(
                  "Mechanics / Linear solver = matrix-free needs the penalty "
                  "formulation (displacement only) with Q2 (Polynomial "
                  "degree = 2) on hexahedra; got " +
                  fe.get_name() +
                  ". Use Linear solver = iterative (or direct)."));
    m.q1.distribute_dofs(m.fe_q1);
    make_constraints(m.q1, m.q1_constraints);
    MatrixFreeTangent::Options options;
    options.boundary_faces = true;
    options.q1             = &m.q1;
    options.q1_constraints = &m.q1_constraints;
    m.tangent =
      std::make_unique<MatrixFreeTangent>(mapping,
                                          dof_handler,
                                          constraints,
                                          MatrixFreeTangent::Variant::cached,
                                          options);
    m.transfer.reinit_polynomial_transfer(dof_handler,
                                          m.q1,
                                          constraints,
                                          m.q1_constraints);

    const MPI_Comm          comm  = m.q1.get_communicator();
    const dealii::IndexSet &owned = m.q1.locally_owned_dofs();
    dealii::IndexSet        relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(m.q1, relevant);
    dealii::DynamicSparsityPattern dsp(relevant);
    dealii::DoFTools::make_sparsity_pattern(m.q1, dsp, m.q1_constraints, false);
    dealii::SparsityTools::distribute_sparsity_pattern(dsp,
                                                       owned,
                                                       comm,
                                                       relevant);
    m.coarse_matrix.reinit(owned, owned, dsp, comm);
    m.coarse_modes = rigid_body_modes(mapping, m.q1);
    m.coarse_b.reinit(owned, comm);
    m.coarse_x.reinit(owned, comm);

    Operator &op = m.tangent->implementation();
    op.initialize_dof_vector(m.residual);
    op.initialize_dof_vector(m.x_mf);
    op.initialize_dof_vector(m.b_mf);
    op.matrix_free.initialize_dof_vector(m.coarse_rhs, 1);
    op.matrix_free.initialize_dof_vector(m.coarse_solution, 1);
  }


  MatrixFreeSolver::~MatrixFreeSolver() = default;


  MatrixFreeTangent &
  MatrixFreeSolver::tangent()
  {
    return *impl->tangent;
  }


  MatrixFreeTangent *
  MatrixFreeSolver::matrix_free_tangent()
  {
    return impl->tangent.get();
  }


  void
  MatrixFreeSolver::setup(const LA::MPI::SparseMatrix &,
                          const PressureMatrix        *schur,
                          const LA::MPI::SparseMatrix *augmentation)
  {
    AssertThrow(schur == nullptr && augmentation == nullptr,
                dealii::ExcInternalError("matrix-free: mixed system"));
    Impl     &m  = *impl;
    Operator &op = m.tangent->implementation();

    // The smoother: Chebyshev with the inverse diagonal (bulk term).
    typename Smoother::AdditionalData data;
    data.preconditioner = std::make_shared<dealii::DiagonalMatrix<Vector>>();
    op.compute_inverse_diagonal(data.preconditioner->get_vector());
    data.degree              = smoothing_degree;
    data.smoothing_range     = smoothing_range;
    data.eig_cg_n_iterations = 15;
    m.smoother.initialize(op, data);

    // The Q1 level: the stored tangent on the Q1 shape functions.
    m.coarse_matrix = 0.0;
    op.add_coarse_matrix(m.coarse_matrix);
    Mat A = m.coarse_matrix;
    if (m.coarse_ksp == nullptr)
      {
        const MPI_Comm comm = m.q1.get_communicator();
        check_petsc(KSPCreate(comm, &m.coarse_ksp), "KSPCreate");
        check_petsc(KSPSetType(m.coarse_ksp, KSPPREONLY), "KSPSetType");
        PC pc;
        check_petsc(KSPGetPC(m.coarse_ksp, &pc), "KSPGetPC");
        // LDL^T: the Q1 matrix is symmetric (the stored tangents are, the
        // face term is left out); half the work and memory of LU.
        check_petsc(PCSetType(pc, PCCHOLESKY), "PCSetType");
        check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS),
                    "PCFactorSetMatSolverType");
        set_near_null_space(A, m.coarse_modes);
        check_petsc(KSPSetOptionsPrefix(m.coarse_ksp, "mechanics_mf_coarse_"),
                    "KSPSetOptionsPrefix");
        check_petsc(KSPSetFromOptions(m.coarse_ksp), "KSPSetFromOptions");
      }
    check_petsc(KSPSetOperators(m.coarse_ksp, A, A), "KSPSetOperators");
    check_petsc(KSPSetUp(m.coarse_ksp),
                "KSPSetUp (matrix-free p-multigrid, Q1 level)");
    m.ready = true;
  }


  unsigned int
  MatrixFreeSolver::solve(LA::MPI::Vector &x, const LA::MPI::Vector &b)
  {
    Impl &m = *impl;
    Assert(m.ready, dealii::ExcMessage("setup() first"));
    const Operator &op = m.tangent->implementation();
    copy_owned(b, m.b_mf);
    m.x_mf = 0.0;
    dealii::SolverControl control(2000, m.tolerance * m.b_mf.l2_norm());
    try
      {
        if (!m.symmetric && m.tangent->has_follower_pressure())
          {
            dealii::SolverGMRES<Vector> gmres(
              control,
              dealii::SolverGMRES<Vector>::AdditionalData(100, true));
            gmres.solve(op, m.x_mf, m.b_mf, m);
          }
        else
          {
            dealii::SolverCG<Vector> cg(control);
            cg.solve(op, m.x_mf, m.b_mf, m);
          }
      }
    catch (const dealii::SolverControl::NoConvergence &e)
      {
        throw_no_convergence("matrix-free", e.last_step, e.last_residual);
      }
    copy_owned(m.x_mf, x);
    x.compress(dealii::VectorOperation::insert);
    return control.last_step();
  }


  void
  MatrixFreeSolver::precondition(Vector &dst, const Vector &src) const
  {
    Assert(impl->ready, dealii::ExcMessage("setup() first"));
    impl->vmult(dst, src);
  }


  void
  MatrixFreeSolver::set_tolerance(const double tolerance)
  {
    impl->tolerance = tolerance;
  }


  std::string
  MatrixFreeSolver::name() const
  {
    return std::string("matrix-free (") + (impl->symmetric ? "CG" : "GMRES") +
           " + p-multigrid Q2 -> Q1: Chebyshev(" +
           std::to_string(smoothing_degree) +
           ") with the matrix-free diagonal, Q1 from the cached tangent by "
           "MUMPS LDL^T)";
  }


  std::size_t
  MatrixFreeSolver::memory_consumption() const
  {
    return impl->tangent->memory_consumption() + impl->q1.memory_consumption() +
           impl->q1_constraints.memory_consumption() +
           impl->residual.memory_consumption() * 3;
  }
} // namespace systole::Mechanics
