// The two-way coupling of the mechanics with a tension model: the states
// at the quadrature points, the step and its acceptance.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include "materials/tension_model.h"
#include "mechanics/problem_impl.h"

namespace systole::Mechanics
{
  void
  Problem::set_tension_model(const Materials::TensionModel *model)
  {
    Impl &m = *impl;
    AssertThrow(model == nullptr ||
                  model->drive() == Materials::TensionDrive::calcium,
                dealii::ExcMessage(
                  "Mechanics: only calcium-driven tension models are coupled "
                  "two-way (" +
                  model->name() +
                  " is driven by activation times: use set_active_tension)."));
    // dT/dlambda with a cross-fibre part, dT/dE x (eta_s s0 x s0 + eta_n
    // n0 x n0), is not major symmetric: the solver must not assume it.
    if (model != nullptr && m.params.active_cross_fibre.any() &&
        m.system.symmetric_tangent)
      m.create_linear_solver(false);
    m.points.tension_model = model;
    for (const auto &cell : m.tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &data : m.points.point_data.get_data(cell))
          {
            data->tension_state.assign(model ? model->n_states() : 0, 0.0);
            if (model)
              model->initial_state(data->tension_state.data());
            data->stretch_n     = 1.0;
            data->model_tension = 0.0;
          }
  }

  void
  Problem::set_tension_step(const double time, const double time_step)
  {
    AssertThrow(time_step > 0.0,
                dealii::ExcMessage("Mechanics: the tension model's time step "
                                   "must be positive."));
    impl->points.tension_time      = time;
    impl->points.tension_time_step = time_step;
  }

  void
  Problem::set_calcium(const std::vector<std::vector<double>> &calcium)
  {
    impl->set_point_values(calcium, &PointData::calcium, false, "set_calcium");
  }

  void
  Problem::set_calcium(const double uniform)
  {
    Impl &m = *impl;
    for (const auto &cell : m.tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &data : m.points.point_data.get_data(cell))
          data->calcium = uniform;
  }

  void
  Problem::Impl::for_each_point(
    const std::function<void(const unsigned int,
                             const unsigned int,
                             PointData &,
                             const dealii::Tensor<2, 3> &,
                             const double)> &f)
  {
    Impl                             &m = *this;
    std::vector<dealii::Tensor<2, 3>> grad_u;
    m.discretization.for_each_owned_cell(
      m.discretization.n_q_1d,
      dealii::update_gradients | dealii::update_JxW_values,
      [&](const auto &cell, const auto &fe_values) {
        grad_u.resize(fe_values.n_quadrature_points);
        fe_values[m.discretization.layout.displacement]
          .get_function_gradients(m.u, grad_u);
        const auto data = m.points.point_data.get_data(cell);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          f(cell->active_cell_index(),
            q,
            *data[q],
            dealii::unit_symmetric_tensor<3>() + grad_u[q],
            fe_values.JxW(q));
      });
  }

  namespace
  {
    /// The tension model's step at @p data (with deformation gradient @p F)
    /// over the step set by set_tension_step(); sets @p stretch.
    double
    step_at_point(const QuadraturePoints     &points,
                  const PointData            &data,
                  const dealii::Tensor<2, 3> &F,
                  std::vector<double>        &trial,
                  double                     &stretch)
    {
      double dT_dstretch;
      return step_tension_model(*points.tension_model,
                                data,
                                F,
                                points.tension_time,
                                points.tension_time_step,
                                trial.data(),
                                dT_dstretch,
                                stretch);
    }
  } // namespace

  void
  Problem::accept_tension_step()
  {
    Impl &m = *impl;
    AssertThrow(m.points.tension_model != nullptr,
                dealii::ExcMessage("accept_tension_step: no tension model."));
    AssertThrow(m.points.tension_time_step > 0.0,
                dealii::ExcMessage("accept_tension_step: set_tension_step() "
                                   "first."));
    std::vector<double> trial(m.points.tension_model->n_states());
    m.for_each_point([&](const unsigned int,
                         const unsigned int,
                         PointData                  &data,
                         const dealii::Tensor<2, 3> &F,
                         const double) {
      double stretch;
      data.model_tension = step_at_point(m.points, data, F, trial, stretch);
      data.tension_state = trial;
      data.stretch_n     = stretch;
    });
  }

  std::vector<std::vector<double>>
  Problem::model_tensions() const
  {
    Impl                            &m = *impl;
    std::vector<std::vector<double>> tensions(m.tria.n_active_cells());
    if (m.points.tension_model == nullptr)
      return tensions;
    std::vector<double> trial(m.points.tension_model->n_states());
    m.for_each_point([&](const unsigned int          c,
                         const unsigned int          q,
                         PointData                  &data,
                         const dealii::Tensor<2, 3> &F,
                         const double) {
      double stretch;
      tensions[c].resize(q + 1);
      tensions[c][q] = step_at_point(m.points, data, F, trial, stretch);
    });
    return tensions;
  }
} // namespace systole::Mechanics
