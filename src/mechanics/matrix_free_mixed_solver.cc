// Linear solver = matrix-free for the mixed Q2-P1disc formulations: the
// augmented saddle-point system applied cell by cell, FGMRES with the block
// preconditioner on the p-multigrid of MatrixFreeSolver (issue 40).
#include "mechanics/matrix_free_mixed_solver.h"

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/la_parallel_block_vector.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>

#include "mechanics/field_layout.h"
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/matrix_free_tangent_impl.h"
#include "mechanics/petsc_tools.h"

#include <petscvec.h>

#include <array>
#include <limits>
#include <map>
#include <utility>

namespace systole::Mechanics
{
  using internal::Operator;
  using BlockVector = dealii::LinearAlgebra::distributed::BlockVector<double>;

  namespace
  {
    using VA = internal::Lanes;
    constexpr unsigned int n_p =
      decltype(std::declval<Operator>().pressure)::n_p;
    constexpr unsigned int invalid = std::numeric_limits<unsigned int>::max();
    using Cell                     = std::array<VA, n_p>;
    /// Per cell batch: four pressures (or rows) vectorized over its lanes.
    using CellValues = dealii::AlignedVector<Cell>;
  } // namespace


  struct MatrixFreeMixedSolver::Impl
  {
    Impl(const dealii::DoFHandler<3> &mixed, const double tolerance)
      : mixed(mixed)
      , tolerance(tolerance)
      , fe_u(dealii::FE_Q<3>(2), 3)
      , displacement(mixed.get_triangulation())
    {}

    /// The maps between the mixed numbering and the displacement
    /// DoFHandler's, and the pressure DoFs of every lane.
    void
    build_maps(const FieldLayout &layout);

    const Operator &
    op() const
    {
      return block->tangent().implementation();
    }

    /// Per batch: the pressures of @p p (lanes without a cell: 0).
    void
    gather(const Vector &p, CellValues &cells) const;
    /// The pressures of @p cells into @p p (each DoF has one cell).
    void
    scatter(const CellValues &cells, Vector &p) const;

    /// dst_u += B^T y; with @p src_u also rows = B src_u (one pass).
    void
    pressure_pass(Vector           &dst_u,
                  const CellValues &y,
                  const Vector     *src_u,
                  CellValues       *rows) const;

    /// dst = T K_0 src.
    void
    vmult(BlockVector &dst, const BlockVector &src) const;

    /// The preconditioner: dst = P^-1 src (upper block-triangular).
    struct Preconditioner
    {
      const Impl &m;
      void
      vmult(BlockVector &dst, const BlockVector &src) const;
    };

    /// Size @p v: the displacement in the tangent's layout, the owned
    /// pressures.
    void
    initialize(BlockVector &v) const
    {
      v.reinit(2);
      op().initialize_dof_vector(v.block(0));
      v.block(1).reinit(owned_p, mixed.get_communicator());
      v.collect_sizes();
    }

    /// v_u += @p sign B^T Gamma v_p (T = [I, G; 0, I] applied: G = B^T
    /// Gamma).
    void
    add_gamma_columns(BlockVector &v, const double sign) const;

    void
    to_block(const LA::MPI::Vector &x, BlockVector &v) const;
    void
    from_block(const BlockVector &v, LA::MPI::Vector &x) const;

    const dealii::DoFHandler<3>      &mixed;
    double                            tolerance;
    dealii::FESystem<3>               fe_u;
    dealii::DoFHandler<3>             displacement;
    dealii::AffineConstraints<double> constraints;
    std::unique_ptr<MatrixFreeSolver> block;
    /// Owned displacement DoF i of the mixed numbering (from its first):
    /// the local index of the displacement DoFHandler's vectors.
    std::vector<unsigned int> u_local;
    /// (batch, lane, k) -> the owned pressure DoF (from the first; invalid
    /// for an empty lane).
    std::vector<unsigned int> p_local;
    dealii::IndexSet          owned_p;
    /// Work arrays.
    mutable CellValues p_cells, rows, y;
    mutable Vector     u_work;
  };


  void
  MatrixFreeMixedSolver::Impl::build_maps(const FieldLayout &layout)
  {
    const auto &fe = mixed.get_fe();
    // Local DoF of the displacement element with the same (component,
    // index) as each displacement DoF of the mixed element.
    std::map<std::pair<unsigned int, unsigned int>, unsigned int> same;
    for (unsigned int j = 0; j < fe_u.n_dofs_per_cell(); ++j)
      same[fe_u.system_to_component_index(j)] = j;
    const dealii::IndexSet &u_owned = layout.owned(0);
    const dealii::IndexSet &p_owned = layout.owned(1);
    const dealii::IndexSet &d_owned = displacement.locally_owned_dofs();
    AssertThrow(u_owned.n_elements() == d_owned.n_elements(),
                dealii::ExcInternalError("displacement ownership"));
    const auto first_u = u_owned.n_elements() ? *u_owned.begin() : 0;
    const auto first_p = p_owned.n_elements() ? *p_owned.begin() : 0;
    const auto first_d = d_owned.n_elements() ? *d_owned.begin() : 0;
    u_local.assign(u_owned.n_elements(), invalid);
    std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell()),
      d_dofs(fe_u.n_dofs_per_cell());
    const auto &mf = op().matrix_free;
    p_local.assign(mf.n_cell_batches() * VA::size() * n_p, invalid);
    for (unsigned int batch = 0; batch < mf.n_cell_batches(); ++batch)
      for (unsigned int l = 0; l < mf.n_active_entries_per_cell_batch(batch);
           ++l)
        {
          const auto d_cell = mf.get_cell_iterator(batch, l);
          const dealii::DoFHandler<3>::active_cell_iterator cell(
            &mixed.get_triangulation(),
            d_cell->level(),
            d_cell->index(),
            &mixed);
          cell->get_dof_indices(dofs);
          d_cell->get_dof_indices(d_dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              const auto ci = fe.system_to_component_index(i);
              if (ci.first < 3)
                {
                  if (!u_owned.is_element(dofs[i]))
                    continue;
                  const auto d = d_dofs[same.at(ci)];
                  AssertThrow(d_owned.is_element(d),
                              dealii::ExcInternalError("displacement owner"));
                  u_local[dofs[i] - first_u] = d - first_d;
                }
              else
                {
                  AssertThrow(ci.second < n_p && p_owned.is_element(dofs[i]),
                              dealii::ExcInternalError("pressure DoF"));
                  p_local[(batch * VA::size() + l) * n_p + ci.second] =
                    dofs[i] - first_p;
                }
            }
        }
    for (const unsigned int i : u_local)
      AssertThrow(i != invalid, dealii::ExcInternalError("unmapped DoF"));
    // The pressure vector: the owned pressure DoFs, numbered rank by rank.
    const MPI_Comm           comm   = mixed.get_communicator();
    const unsigned long long n_mine = p_owned.n_elements();
    unsigned long long       first  = 0;
    MPI_Exscan(&n_mine, &first, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      first = 0; // (MPI_Exscan leaves rank 0's undefined)
    owned_p = dealii::IndexSet(dealii::Utilities::MPI::sum(n_mine, comm));
    owned_p.add_range(first, first + n_mine);
    p_cells.resize(mf.n_cell_batches());
    rows.resize(mf.n_cell_batches());
    y.resize(mf.n_cell_batches());
    op().initialize_dof_vector(u_work);
  }


  void
  MatrixFreeMixedSolver::Impl::gather(const Vector &p, CellValues &cells) const
  {
    for (unsigned int batch = 0; batch < cells.size(); ++batch)
      for (unsigned int k = 0; k < n_p; ++k)
        for (unsigned int l = 0; l < VA::size(); ++l)
          {
            const unsigned int i = p_local[(batch * VA::size() + l) * n_p + k];
            cells[batch][k][l]   = i == invalid ? 0.0 : p.local_element(i);
          }
  }


  void
  MatrixFreeMixedSolver::Impl::scatter(const CellValues &cells, Vector &p) const
  {
    for (unsigned int batch = 0; batch < cells.size(); ++batch)
      for (unsigned int k = 0; k < n_p; ++k)
        for (unsigned int l = 0; l < VA::size(); ++l)
          {
            const unsigned int i = p_local[(batch * VA::size() + l) * n_p + k];
            if (i != invalid)
              p.local_element(i) = cells[batch][k][l];
          }
  }


  void
  MatrixFreeMixedSolver::Impl::pressure_pass(Vector           &dst_u,
                                             const CellValues &y,
                                             const Vector     *src_u,
                                             CellValues       *rows) const
  {
    const Operator &o = op();
    if (src_u != nullptr)
      src_u->update_ghost_values();
    dst_u.zero_out_ghost_values();
    Operator::Eval         phi(o.matrix_free);
    constexpr unsigned int n = 9 * Operator::Eval::static_n_q_points;
    for (unsigned int batch = 0; batch < o.matrix_free.n_cell_batches();
         ++batch)
      {
        phi.reinit(batch);
        VA *g = phi.begin_gradients();
        if (src_u != nullptr)
          {
            phi.read_dof_values(*src_u);
            phi.evaluate(dealii::EvaluationFlags::gradients);
            (*rows)[batch] = o.pressure.rows(batch, g);
          }
        for (unsigned int a = 0; a < n; ++a)
          g[a] = 0.0;
        o.pressure.add_columns(batch, y[batch], g);
        phi.integrate(dealii::EvaluationFlags::gradients);
        phi.distribute_local_to_global(dst_u);
      }
    dst_u.compress(dealii::VectorOperation::add);
    if (src_u != nullptr)
      src_u->zero_out_ghost_values();
  }


  void
  MatrixFreeMixedSolver::Impl::vmult(BlockVector       &dst,
                                     const BlockVector &src) const
  {
    using Coupling    = decltype(op().pressure);
    const Operator &o = op();
    o.vmult(dst.block(0), src.block(0)); // A_gamma u (constrained: identity)
    gather(src.block(1), p_cells);
    // y = p + Gamma C p (independent of u); the rows B u in the same pass.
    for (unsigned int batch = 0; batch < p_cells.size(); ++batch)
      {
        const Cell Cp =
          o.pressure.multiply(batch, Coupling::pressure_block, p_cells[batch]);
        const Cell GCp =
          o.pressure.multiply(batch, Coupling::gamma_inverse_weight, Cp);
        for (unsigned int k = 0; k < n_p; ++k)
          y[batch][k] = p_cells[batch][k] + GCp[k];
      }
    pressure_pass(dst.block(0), y, &src.block(0), &rows);
    for (unsigned int batch = 0; batch < p_cells.size(); ++batch)
      {
        const Cell Cp =
          o.pressure.multiply(batch, Coupling::pressure_block, p_cells[batch]);
        for (unsigned int k = 0; k < n_p; ++k)
          rows[batch][k] += Cp[k];
      }
    scatter(rows, dst.block(1));
  }


  void
  MatrixFreeMixedSolver::Impl::Preconditioner::vmult(
    BlockVector       &dst,
    const BlockVector &src) const
  {
    using Coupling       = decltype(m.op().pressure);
    const auto &coupling = m.op().pressure;
    // z_p = S^-1 r_p, then A_gamma z_u = r_u - (B^T + G C) z_p.
    m.gather(src.block(1), m.p_cells);
    for (unsigned int batch = 0; batch < m.p_cells.size(); ++batch)
      {
        const Cell z =
          coupling.multiply(batch, Coupling::inverse_schur, m.p_cells[batch]);
        const Cell GCz = coupling.multiply(
          batch,
          Coupling::gamma_inverse_weight,
          coupling.multiply(batch, Coupling::pressure_block, z));
        m.p_cells[batch] = z;
        for (unsigned int k = 0; k < n_p; ++k)
          m.y[batch][k] = -(z[k] + GCz[k]);
      }
    m.scatter(m.p_cells, dst.block(1));
    m.u_work = src.block(0);
    m.pressure_pass(m.u_work, m.y, nullptr, nullptr);
    m.block->precondition(dst.block(0), m.u_work);
  }


  void
  MatrixFreeMixedSolver::Impl::add_gamma_columns(BlockVector &v,
                                                 const double sign) const
  {
    using Coupling = decltype(op().pressure);
    gather(v.block(1), p_cells);
    for (unsigned int batch = 0; batch < p_cells.size(); ++batch)
      {
        y[batch] = op().pressure.multiply(batch,
                                          Coupling::gamma_inverse_weight,
                                          p_cells[batch]);
        for (auto &value : y[batch])
          value *= sign;
      }
    pressure_pass(v.block(0), y, nullptr, nullptr);
  }


  void
  MatrixFreeMixedSolver::Impl::to_block(const LA::MPI::Vector &x,
                                        BlockVector           &v) const
  {
    const PetscScalar *a;
    check_petsc(VecGetArrayRead(x, &a), "VecGetArrayRead");
    for (unsigned int i = 0; i < u_local.size(); ++i)
      v.block(0).local_element(u_local[i]) = a[i];
    for (unsigned int i = 0; i < v.block(1).locally_owned_size(); ++i)
      v.block(1).local_element(i) = a[u_local.size() + i];
    check_petsc(VecRestoreArrayRead(x, &a), "VecRestoreArrayRead");
  }


  void
  MatrixFreeMixedSolver::Impl::from_block(const BlockVector &v,
                                          LA::MPI::Vector   &x) const
  {
    PetscScalar *a;
    check_petsc(VecGetArray(x, &a), "VecGetArray");
    for (unsigned int i = 0; i < u_local.size(); ++i)
      a[i] = v.block(0).local_element(u_local[i]);
    for (unsigned int i = 0; i < v.block(1).locally_owned_size(); ++i)
      a[u_local.size() + i] = v.block(1).local_element(i);
    check_petsc(VecRestoreArray(x, &a), "VecRestoreArray");
  }


  MatrixFreeMixedSolver::MatrixFreeMixedSolver(
    const dealii::Mapping<3>                &mapping,
    const dealii::DoFHandler<3>             &dof_handler,
    const FieldLayout                       &layout,
    const MatrixFreeSolver::MakeConstraints &make_constraints,
    const double                             tolerance)
    : impl(std::make_unique<Impl>(dof_handler, tolerance))
  {
    const auto &fe = dof_handler.get_fe();
    AssertThrow(
      fe.n_components() == 4 && fe.n_base_elements() == 2 &&
        fe.base_element(0).degree == 2 &&
        fe.base_element(1).n_dofs_per_cell() == n_p &&
        fe.reference_cell() == dealii::ReferenceCells::Hexahedron,
      dealii::ExcMessage(
        "Mechanics / Linear solver = matrix-free with a pressure field needs "
        "Q2-P1disc on hexahedra (Polynomial degree = 2, Pressure element = "
        "discontinuous); got " +
        fe.get_name() + ". Use Linear solver = iterative (or direct)."));
    Impl &m = *impl;
    m.displacement.distribute_dofs(m.fe_u);
    make_constraints(m.displacement, m.constraints);
    m.block = std::make_unique<MatrixFreeSolver>(mapping,
                                                 m.displacement,
                                                 m.constraints,
                                                 make_constraints,
                                                 tolerance,
                                                 true);
    m.build_maps(layout);
  }


  MatrixFreeMixedSolver::~MatrixFreeMixedSolver() = default;


  void
  MatrixFreeMixedSolver::setup(const LA::MPI::SparseMatrix &K,
                               const PressureMatrix        *schur,
                               const LA::MPI::SparseMatrix *augmentation)
  {
    AssertThrow(schur == nullptr && augmentation == nullptr,
                dealii::ExcInternalError("matrix-free mixed: matrices given"));
    AssertThrow(impl->op().pressure.active(),
                dealii::ExcInternalError("matrix-free mixed: no coupling"));
    impl->block->setup(K);
  }


  unsigned int
  MatrixFreeMixedSolver::solve(LA::MPI::Vector &x, const LA::MPI::Vector &b)
  {
    Impl       &m = *impl;
    BlockVector rhs, solution;
    m.initialize(rhs);
    m.initialize(solution);
    m.to_block(b, rhs);
    m.add_gamma_columns(rhs, 1.0); // T b

    dealii::SolverControl control(1000, m.tolerance * rhs.l2_norm());
    dealii::SolverFGMRES<BlockVector> fgmres(
      control,
      dealii::SolverFGMRES<BlockVector>::AdditionalData(100));
    const Impl::Preconditioner preconditioner{m};
    try
      {
        fgmres.solve(m, solution, rhs, preconditioner);
      }
    catch (const dealii::SolverControl::NoConvergence &e)
      {
        throw_no_convergence("matrix-free mixed", e.last_step, e.last_residual);
      }
    m.from_block(solution, x);
    return control.last_step();
  }


  void
  MatrixFreeMixedSolver::vmult(LA::MPI::Vector       &dst,
                               const LA::MPI::Vector &src) const
  {
    const Impl &m = *impl;
    BlockVector x, y;
    m.initialize(x);
    m.initialize(y);
    m.to_block(src, x);
    m.vmult(y, x);                // T K_0 x
    m.add_gamma_columns(y, -1.0); // K_0 x = T K_0 x - G (K_0 x)_p
    m.from_block(y, dst);
  }


  void
  MatrixFreeMixedSolver::set_tolerance(const double tolerance)
  {
    impl->tolerance = tolerance;
  }


  MatrixFreeTangent *
  MatrixFreeMixedSolver::matrix_free_tangent()
  {
    return &impl->block->tangent();
  }


  const dealii::DoFHandler<3> &
  MatrixFreeMixedSolver::displacement_dof_handler() const
  {
    return impl->displacement;
  }


  void
  MatrixFreeMixedSolver::displacement_of(const LA::MPI::Vector &mixed,
                                         Vector                &u) const
  {
    const PetscScalar *a;
    check_petsc(VecGetArrayRead(mixed, &a), "VecGetArrayRead");
    for (unsigned int i = 0; i < impl->u_local.size(); ++i)
      u.local_element(impl->u_local[i]) = a[i];
    check_petsc(VecRestoreArrayRead(mixed, &a), "VecRestoreArrayRead");
  }


  std::string
  MatrixFreeMixedSolver::name() const
  {
    return "matrix-free mixed (FGMRES + block-triangular: for A + gamma B^T "
           "W^-1 B " +
           impl->block->name() +
           ", the scaled pressure mass matrix cell by cell)";
  }


  std::size_t
  MatrixFreeMixedSolver::memory_consumption() const
  {
    return impl->block->memory_consumption() +
           impl->displacement.memory_consumption() +
           impl->constraints.memory_consumption() +
           (impl->u_local.size() + impl->p_local.size()) * sizeof(unsigned int);
  }
} // namespace systole::Mechanics
