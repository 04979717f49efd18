// Geometric multigrid on the matrix-free tangent (step-37's set-up on the
// operator of matrix_free_tangent_impl.h).
#include "mechanics/matrix_free_multigrid.h"

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/diagonal_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/multigrid/mg_coarse.h>
#include <deal.II/multigrid/mg_constrained_dofs.h>
#include <deal.II/multigrid/mg_matrix.h>
#include <deal.II/multigrid/mg_smoother.h>
#include <deal.II/multigrid/mg_tools.h>
#include <deal.II/multigrid/mg_transfer_matrix_free.h>
#include <deal.II/multigrid/multigrid.h>
#include <deal.II/numerics/vector_tools.h>

#include "mechanics/matrix_free_tangent_impl.h"

namespace systole::Mechanics
{
  using internal::Operator;
  using internal::Smoother;


  struct MatrixFreeMultigrid::Impl
  {
    Impl(const dealii::Mapping<3>                   &mapping,
         const dealii::DoFHandler<3>                &dof_handler,
         const std::set<dealii::types::boundary_id> &fixed,
         const NeoHookeanPenalty                    &law,
         const Settings                             &settings);

    const dealii::DoFHandler<3>      &dof_handler;
    const Settings                    settings;
    dealii::AffineConstraints<double> constraints; ///< active level
    std::unique_ptr<Operator>         fine;
    dealii::MGConstrainedDoFs         mg_constrained;
    dealii::MGLevelObject<std::shared_ptr<Operator>>           levels;
    dealii::MGTransferMatrixFree<3, double>                    transfer;
    dealii::MGLevelObject<typename Smoother::AdditionalData>   smoother_data;
    dealii::MGSmootherPrecondition<Operator, Smoother, Vector> smoother;
  };


  MatrixFreeMultigrid::Impl::Impl(
    const dealii::Mapping<3>                   &mapping,
    const dealii::DoFHandler<3>                &dof_handler,
    const std::set<dealii::types::boundary_id> &fixed,
    const NeoHookeanPenalty                    &law,
    const Settings                             &settings)
    : dof_handler(dof_handler)
    , settings(settings)
  {
    const auto       variant = MatrixFreeTangent::Variant::cached;
    dealii::IndexSet relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    constraints.reinit(relevant);
    dealii::DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    for (const auto id : fixed)
      dealii::VectorTools::interpolate_boundary_values(
        mapping,
        dof_handler,
        id,
        dealii::Functions::ZeroFunction<3>(3),
        constraints);
    constraints.close();
    fine = std::make_unique<Operator>(mapping,
                                      dof_handler,
                                      constraints,
                                      law,
                                      variant);

    mg_constrained.initialize(dof_handler);
    mg_constrained.make_zero_boundary_constraints(dof_handler, fixed);
    const unsigned int n_levels =
      dof_handler.get_triangulation().n_global_levels();
    levels.resize(0, n_levels - 1);
    std::vector<std::shared_ptr<const dealii::Utilities::MPI::Partitioner>>
      partitioners(n_levels);
    for (unsigned int level = 0; level < n_levels; ++level)
      {
        dealii::IndexSet level_relevant;
        dealii::DoFTools::extract_locally_relevant_level_dofs(dof_handler,
                                                              level,
                                                              level_relevant);
        dealii::AffineConstraints<double> level_constraints;
        level_constraints.reinit(level_relevant);
        level_constraints.add_lines(mg_constrained.get_boundary_indices(level));
        level_constraints.close();
        levels[level] = std::make_shared<Operator>(
          mapping,
          dof_handler,
          level_constraints,
          law,
          settings.single_precision_levels
            ? MatrixFreeTangent::Variant::cached_single
            : variant,
          level);
        partitioners[level] =
          levels[level]->matrix_free.get_vector_partitioner();
      }
    transfer.initialize_constraints(mg_constrained);
    transfer.build(dof_handler, partitioners);
  }


  MatrixFreeMultigrid::MatrixFreeMultigrid(
    const dealii::Mapping<3>                   &mapping,
    const dealii::DoFHandler<3>                &dof_handler,
    const std::set<dealii::types::boundary_id> &fixed,
    const NeoHookeanPenalty                    &law,
    const Settings                             &settings)
    : impl(std::make_unique<Impl>(mapping, dof_handler, fixed, law, settings))
  {}


  MatrixFreeMultigrid::~MatrixFreeMultigrid() = default;


  void
  MatrixFreeMultigrid::initialize_dof_vector(Vector &v) const
  {
    impl->fine->initialize_dof_vector(v);
  }


  void
  MatrixFreeMultigrid::update(const Vector &u)
  {
    impl->fine->update(u);
    const unsigned int            n_levels = impl->levels.max_level() + 1;
    dealii::MGLevelObject<Vector> u_levels(0, n_levels - 1);
    for (unsigned int level = 0; level < n_levels; ++level)
      impl->levels[level]->initialize_dof_vector(u_levels[level]);
    Vector u_ghosted;
    impl->fine->initialize_dof_vector(u_ghosted);
    u_ghosted.copy_locally_owned_data_from(u);
    u_ghosted.update_ghost_values();
    impl->transfer.interpolate_to_mg(impl->dof_handler, u_levels, u_ghosted);

    impl->smoother_data.resize(0, n_levels - 1);
    for (unsigned int level = 0; level < n_levels; ++level)
      {
        Operator &op = *impl->levels[level];
        op.update(u_levels[level]);
        auto &data = impl->smoother_data[level];
        data.preconditioner =
          std::make_shared<dealii::DiagonalMatrix<Vector>>();
        op.compute_inverse_diagonal(data.preconditioner->get_vector());
        if (level > 0)
          {
            data.smoothing_range     = impl->settings.smoothing_range;
            data.degree              = impl->settings.smoothing_degree;
            data.eig_cg_n_iterations = impl->settings.eigenvalue_iterations;
          }
        else
          {
            // The coarsest level: Chebyshev iterations to a residual of
            // 1e-3 (step-37's coarse solver).
            data.smoothing_range     = 1e-3;
            data.degree              = dealii::numbers::invalid_unsigned_int;
            data.eig_cg_n_iterations = op.m();
          }
      }
    impl->smoother.initialize(impl->levels, impl->smoother_data);
  }


  void
  MatrixFreeMultigrid::vmult(Vector &dst, const Vector &src) const
  {
    impl->fine->vmult(dst, src);
  }


  unsigned int
  MatrixFreeMultigrid::solve(Vector       &x,
                             const Vector &b,
                             const double  relative_tolerance) const
  {
    dealii::MGCoarseGridApplySmoother<Vector> coarse(impl->smoother);
    dealii::mg::Matrix<Vector>                matrices(impl->levels);
    dealii::Multigrid<Vector>                 mg(matrices,
                                 coarse,
                                 impl->transfer,
                                 impl->smoother,
                                 impl->smoother);
    dealii::PreconditionMG<3, Vector, dealii::MGTransferMatrixFree<3, double>>
                          preconditioner(impl->dof_handler, mg, impl->transfer);
    dealii::SolverControl control(500, relative_tolerance * b.l2_norm());
    dealii::SolverCG<Vector> cg(control);
    x = 0;
    cg.solve(*impl->fine, x, b, preconditioner);
    return control.last_step();
  }


  unsigned int
  MatrixFreeMultigrid::n_levels() const
  {
    return impl->levels.max_level() + 1;
  }
} // namespace systole::Mechanics
