// Elastodynamics of Mechanics::Problem: the mass matrix, the generalized-alpha
// state and the energies. The inertia term of the assembly is in assembly.cc.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>

#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem_impl.h"

namespace systole::Mechanics
{
  void
  Dynamics::rates(const LA::MPI::Vector &u,
                  LA::MPI::Vector       &a,
                  LA::MPI::Vector       &v) const
  {
    const double dt = time_step;
    // a = (u - u_n - dt v_n) / (beta dt^2) - (1/(2 beta) - 1) a_n
    a = u;
    a -= u_n;
    a.add(-dt, v_n);
    a *= 1.0 / (beta * dt * dt);
    a.add(-(0.5 / beta - 1.0), a_n);
    // v = v_n + dt ((1 - gamma) a_n + gamma a)
    v = v_n;
    v.add(dt * (1.0 - gamma), a_n);
    v.add(dt * gamma, a);
  }

  double
  Dynamics::effective_mass_coefficient() const
  {
    const double dt = time_step;
    return (1.0 - alpha_m) / (beta * dt * dt) +
           mass_damping * (1.0 - alpha_f) * gamma / (beta * dt);
  }

  namespace
  {
    /// Integrates @p f(cell, fe_values) over the locally owned cells with the
    /// full Gauss rule of the problem, values and weights updated.
    template <typename Function>
    void
    for_each_cell(const dealii::Mapping<3>       &mapping,
                  const dealii::FiniteElement<3> &fe,
                  const dealii::DoFHandler<3>    &dof_handler,
                  const unsigned int              n_q_1d,
                  const Function                 &f)
    {
      const dealii::QGauss<3> quadrature(n_q_1d);
      dealii::FEValues<3>     fe_values(mapping,
                                    fe,
                                    quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_JxW_values);
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            f(cell, fe_values);
          }
    }
  } // namespace

  void
  Problem::start_dynamics(const dealii::Vector<double> &pressures,
                          const double                  active_tension)
  {
    Impl     &m = *impl;
    Dynamics &d = m.dynamics;
    AssertThrow(m.params.density > 0.0,
                dealii::ExcMessage("Mechanics / Density must be positive for "
                                   "a time integration with inertia."));
    AssertThrow(!m.layout.mixed(),
                dealii::ExcMessage(
                  "Mechanics: the inertia is implemented for Material / "
                  "Incompressibility = penalty only."));
    const double rho = m.params.spectral_radius;
    d.alpha_m        = (2.0 * rho - 1.0) / (rho + 1.0);
    d.alpha_f        = rho / (rho + 1.0);
    d.gamma          = 0.5 - d.alpha_m + d.alpha_f;
    d.beta =
      0.25 * (1.0 - d.alpha_m + d.alpha_f) * (1.0 - d.alpha_m + d.alpha_f);
    d.mass_damping = m.params.rayleigh_mass_damping;

    // The consistent mass matrix of the displacement, condensed like the
    // tangent (constant: the reference configuration does not move).
    if (!d.started)
      {
        dealii::DynamicSparsityPattern dsp(m.relevant);
        dealii::DoFTools::make_sparsity_pattern(m.dof_handler,
                                                dsp,
                                                m.constraints,
                                                false);
        dealii::SparsityTools::distribute_sparsity_pattern(dsp,
                                                           m.owned,
                                                           m.comm,
                                                           m.relevant);
        d.mass.reinit(m.owned, m.owned, dsp, m.comm);
        const unsigned int         n = m.fe->n_dofs_per_cell();
        dealii::FullMatrix<double> cell_mass(n, n);
        std::vector<dealii::types::global_dof_index> dofs(n);
        const double                                 density = m.params.density;
        for_each_cell(
          m.mapping,
          *m.fe,
          m.dof_handler,
          m.n_q_1d,
          [&](const auto &cell, const auto &fe_values) {
            cell_mass = 0;
            for (const unsigned int q : fe_values.quadrature_point_indices())
              for (unsigned int i = 0; i < n; ++i)
                {
                  const auto   ci = m.fe->system_to_component_index(i).first;
                  const double wi =
                    density * fe_values.shape_value(i, q) * fe_values.JxW(q);
                  for (unsigned int j = 0; j < n; ++j)
                    if (m.fe->system_to_component_index(j).first == ci)
                      cell_mass(i, j) += wi * fe_values.shape_value(j, q);
                }
            cell->get_dof_indices(dofs);
            m.constraints.distribute_local_to_global(cell_mass, dofs, d.mass);
          });
        d.mass.compress(dealii::VectorOperation::add);
        d.u_n.reinit(m.owned, m.comm);
        d.v_n.reinit(m.owned, m.comm);
        d.a_n.reinit(m.owned, m.comm);
        d.residual_n.reinit(m.owned, m.comm);
        d.effective_acceleration.reinit(m.owned, m.relevant, m.comm);
      }

    // At rest at the current displacement; the acceleration of the equation
    // of motion under the given loads, M a_0 = -R(u_0).
    d.started   = true;
    d.time_step = 0.0;
    d.u_n       = m.u_owned;
    d.v_n       = 0;
    m.assemble(pressures, active_tension, false);
    d.residual_n = m.residual;
    LA::MPI::Vector rhs(d.residual_n);
    rhs *= -1.0;
    d.a_n = 0;
    dealii::SolverControl                     control(1000,
                                  1e-12 * std::max(rhs.l2_norm(), 1e-300));
    dealii::PETScWrappers::SolverCG           cg(control, m.comm);
    dealii::PETScWrappers::PreconditionJacobi jacobi(d.mass);
    if (rhs.l2_norm() > 0.0)
      cg.solve(d.mass, d.a_n, rhs, jacobi);
    m.constraints.distribute(d.a_n);
  }

  void
  Problem::start_dynamics(const double pressure, const double active_tension)
  {
    start_dynamics(impl->uniform_pressures(pressure), active_tension);
  }

  void
  Problem::set_time_step(const double time_step)
  {
    AssertThrow(impl->dynamics.started,
                dealii::ExcMessage("Mechanics: start_dynamics() before "
                                   "set_time_step()."));
    AssertThrow(time_step >= 0.0,
                dealii::ExcMessage("Mechanics: the time step must not be "
                                   "negative."));
    impl->dynamics.time_step = time_step;
  }

  void
  Problem::accept_time_step(const dealii::Vector<double> &pressures,
                            const double                  active_tension)
  {
    Impl     &m = *impl;
    Dynamics &d = m.dynamics;
    AssertThrow(d.started && d.time_step > 0.0,
                dealii::ExcMessage("Mechanics: accept_time_step() needs a time "
                                   "step (set_time_step())."));
    LA::MPI::Vector a(m.owned, m.comm), v(m.owned, m.comm);
    d.rates(m.u_owned, a, v);
    m.constraints.distribute(a);
    m.constraints.distribute(v);
    // The quasi-static residual of the new state under its loads.
    const double dt = d.time_step;
    d.time_step     = 0.0;
    m.assemble(pressures, active_tension, false);
    d.time_step  = dt;
    d.residual_n = m.residual;
    d.u_n        = m.u_owned;
    d.v_n        = v;
    d.a_n        = a;
  }

  void
  Problem::accept_time_step(const double pressure, const double active_tension)
  {
    accept_time_step(impl->uniform_pressures(pressure), active_tension);
  }

  double
  Problem::kinetic_energy() const
  {
    const Impl &m = *impl;
    if (!m.dynamics.started)
      return 0.0;
    LA::MPI::Vector v(m.owned, m.relevant, m.comm);
    v = m.dynamics.v_n;
    std::vector<dealii::Tensor<1, 3>> values(
      dealii::Utilities::fixed_power<3>(m.n_q_1d));
    double energy = 0.0;
    for_each_cell(
      m.mapping,
      *m.fe,
      m.dof_handler,
      m.n_q_1d,
      [&](const auto &, const auto &fe_values) {
        values.resize(fe_values.n_quadrature_points);
        fe_values[m.layout.displacement].get_function_values(v, values);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          energy +=
            0.5 * m.params.density * values[q].norm_square() * fe_values.JxW(q);
      });
    return dealii::Utilities::MPI::sum(energy, m.comm);
  }

  double
  Problem::strain_energy() const
  {
    const Impl                       &m = *impl;
    std::vector<dealii::Tensor<2, 3>> grad_u(
      dealii::Utilities::fixed_power<3>(m.n_q_1d));
    double energy = 0.0;
    for_each_cell(
      m.mapping,
      *m.fe,
      m.dof_handler,
      m.n_q_1d,
      [&](const auto &cell, const auto &fe_values) {
        grad_u.resize(fe_values.n_quadrature_points);
        fe_values[m.layout.displacement].get_function_gradients(m.u, grad_u);
        const auto data = m.point_data.get_data(cell);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            Materials::PassiveInput in;
            in.F            = dealii::unit_symmetric_tensor<3>() + grad_u[q];
            in.basis        = data[q]->basis;
            in.with_tangent = false;
            Materials::PassiveOutput out;
            m.passive_law.evaluate(in, out);
            const double U =
              m.reduced_volumetric
                ? 0.0
                : m.volumetric_law.energy(dealii::determinant(in.F));
            energy += (out.psi + U) * fe_values.JxW(q);
          }
      });
    if (m.reduced_volumetric)
      for_each_cell(
        m.mapping,
        *m.fe,
        m.dof_handler,
        m.n_q_1d - 1,
        [&](const auto &, const auto &fe_values) {
          grad_u.resize(fe_values.n_quadrature_points);
          fe_values[m.layout.displacement].get_function_gradients(m.u, grad_u);
          for (const unsigned int q : fe_values.quadrature_point_indices())
            energy += m.volumetric_law.energy(dealii::determinant(
                        dealii::unit_symmetric_tensor<3>() + grad_u[q])) *
                      fe_values.JxW(q);
        });
    return dealii::Utilities::MPI::sum(energy, m.comm);
  }
} // namespace systole::Mechanics
