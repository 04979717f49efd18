// Elastodynamics of Mechanics::Problem: the mass matrix, the generalized-alpha
// state and the energies. The inertia term of the assembly is in assembly.cc.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>

#include "materials/active_stress.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem_impl.h"

#include <algorithm>

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
    // The pressure of a mixed formulation is a multiplier, not a state with
    // rates: its differences would only feed the recursion above.
    // (size(): the global DoF count, the same on every rank, so that the
    // collective compress() is called by all or none.)
    if (pressure_dofs.size() > 0)
      {
        for (const auto i : pressure_dofs)
          {
            a(i) = 0.0;
            v(i) = 0.0;
          }
        a.compress(dealii::VectorOperation::insert);
        v.compress(dealii::VectorOperation::insert);
      }
  }

  double
  Dynamics::effective_mass_coefficient() const
  {
    const double dt = time_step;
    return (1.0 - alpha_m) / (beta * dt * dt) +
           mass_damping * (1.0 - alpha_f) * gamma / (beta * dt);
  }

  double
  Dynamics::velocity_coefficient() const
  {
    return gamma / (beta * time_step);
  }

  namespace
  {
    /// What the integrals over the cells below need.
    const dealii::UpdateFlags cell_flags = dealii::update_values |
                                           dealii::update_gradients |
                                           dealii::update_JxW_values;
  } // namespace

  void
  Problem::Impl::setup_dynamics()
  {
    Impl     &m = *this;
    Dynamics &d = m.dynamics;
    AssertThrow(m.params.density > 0.0,
                dealii::ExcMessage("Mechanics / Density must be positive for "
                                   "a time integration with inertia."));
    const double rho = m.params.spectral_radius;
    d.alpha_m        = (2.0 * rho - 1.0) / (rho + 1.0);
    d.alpha_f        = rho / (rho + 1.0);
    d.gamma          = 0.5 - d.alpha_m + d.alpha_f;
    d.beta =
      0.25 * (1.0 - d.alpha_m + d.alpha_f) * (1.0 - d.alpha_m + d.alpha_f);
    d.mass_damping = m.params.rayleigh_mass_damping;

    // The consistent mass matrix of the displacement, condensed like the
    // tangent (constant: the reference configuration does not move).
    if (d.u_n.size() == 0)
      {
        if (m.discretization.layout.mixed())
          d.pressure_dofs = m.discretization.layout.owned(1);
        dealii::DynamicSparsityPattern dsp(m.discretization.relevant);
        dealii::DoFTools::make_sparsity_pattern(m.discretization.dof_handler,
                                                dsp,
                                                m.discretization.constraints,
                                                false);
        dealii::SparsityTools::distribute_sparsity_pattern(
          dsp,
          m.discretization.owned,
          m.comm,
          m.discretization.relevant);
        d.mass.reinit(m.discretization.owned,
                      m.discretization.owned,
                      dsp,
                      m.comm);
        const unsigned int         n = m.discretization.fe->n_dofs_per_cell();
        dealii::FullMatrix<double> cell_mass(n, n);
        std::vector<dealii::types::global_dof_index> dofs(n);
        const double                                 density = m.params.density;
        m.discretization.for_each_owned_cell(
          m.discretization.n_q_1d,
          cell_flags,
          [&](const auto &cell, const auto &fe_values) {
            cell_mass = 0;
            for (const unsigned int q : fe_values.quadrature_point_indices())
              for (unsigned int i = 0; i < n; ++i)
                {
                  const auto ci =
                    m.discretization.fe->system_to_component_index(i).first;
                  if (ci == 3) // the pressure: a positive diagonal only
                    {
                      cell_mass(i, i) += density * fe_values.JxW(q);
                      continue;
                    }
                  const double wi =
                    density * fe_values.shape_value(i, q) * fe_values.JxW(q);
                  for (unsigned int j = 0; j < n; ++j)
                    if (m.discretization.fe->system_to_component_index(j)
                          .first == ci)
                      cell_mass(i, j) += wi * fe_values.shape_value(j, q);
                }
            cell->get_dof_indices(dofs);
            m.discretization.constraints.distribute_local_to_global(cell_mass,
                                                                    dofs,
                                                                    d.mass);
          });
        d.mass.compress(dealii::VectorOperation::add);
        d.u_n.reinit(m.discretization.owned, m.comm);
        d.v_n.reinit(m.discretization.owned, m.comm);
        d.a_n.reinit(m.discretization.owned, m.comm);
        d.residual_n.reinit(m.discretization.owned, m.comm);
        d.effective_acceleration.reinit(m.discretization.owned,
                                        m.discretization.relevant,
                                        m.comm);
        d.velocity.reinit(m.discretization.owned,
                          m.discretization.relevant,
                          m.comm);
        for (auto *v :
             {&d.factorized_u_n, &d.factorized_v_n, &d.factorized_a_n})
          v->reinit(m.discretization.owned, m.comm);
      }
  }

  void
  Problem::start_dynamics(const dealii::Vector<double> &pressures,
                          const double                  active_tension,
                          const double                  elapsed)
  {
    Impl     &m = *impl;
    Dynamics &d = m.dynamics;
    AssertThrow(elapsed >= 0.0,
                dealii::ExcMessage("Mechanics: start_dynamics() needs a "
                                   "positive elapsed time (0: at rest)."));
    AssertThrow(elapsed == 0.0 || m.history.n_saves > 0,
                dealii::ExcMessage("Mechanics: start_dynamics() in motion "
                                   "needs a save() before."));
    m.setup_dynamics();

    // At the current displacement, at rest or with the velocity of the
    // motion from the last save; the acceleration of the equation of motion
    // under the given loads, M a_0 = -(R(u_0, v_0) + c_M M v_0).
    d.started   = true;
    d.time_step = 0.0;
    d.u_n       = m.u_owned;
    d.v_n       = 0;
    if (elapsed > 0.0)
      {
        d.v_n = m.u_owned;
        d.v_n -= m.history.u_saved;
        d.v_n *= 1.0 / elapsed;
        m.discretization.constraints.set_zero(d.v_n);
      }
    d.velocity  = d.v_n;
    d.accepting = elapsed > 0.0; // the rate terms at v_0
    try
      {
        m.assemble(pressures, active_tension, false);
      }
    catch (...)
      {
        d.accepting = false;
        throw;
      }
    d.accepting  = false;
    d.residual_n = m.system.residual;
    LA::MPI::Vector rhs(d.residual_n);
    if (d.mass_damping != 0.0 && elapsed > 0.0)
      {
        LA::MPI::Vector damping(d.v_n);
        d.mass.vmult(damping, d.v_n);
        rhs.add(d.mass_damping, damping);
      }
    rhs *= -1.0;
    for (const auto i : d.pressure_dofs)
      rhs(i) = 0.0;
    rhs.compress(dealii::VectorOperation::insert);
    d.a_n = 0;
    dealii::SolverControl                     control(1000,
                                  1e-12 * std::max(rhs.l2_norm(), 1e-300));
    dealii::PETScWrappers::SolverCG           cg(control, m.comm);
    dealii::PETScWrappers::PreconditionJacobi jacobi(d.mass);
    if (rhs.l2_norm() > 0.0)
      cg.solve(d.mass, d.a_n, rhs, jacobi);
    m.discretization.constraints.distribute(d.a_n);
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
    LA::MPI::Vector a(m.discretization.owned, m.comm),
      v(m.discretization.owned, m.comm);
    d.rates(m.u_owned, a, v);
    m.discretization.constraints.distribute(a);
    m.discretization.constraints.distribute(v);
    // The residual of the new state under its loads, with the rate terms
    // (viscosity, dashpots) of its velocity: R(u_{n+1}, v_{n+1}).
    const double dt = d.time_step;
    d.time_step     = 0.0;
    d.velocity      = v;
    d.accepting     = true;
    try
      {
        m.assemble(pressures, active_tension, false);
      }
    catch (...)
      {
        d.accepting = false;
        d.time_step = dt;
        throw;
      }
    d.accepting  = false;
    d.time_step  = dt;
    d.residual_n = m.system.residual;
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
    LA::MPI::Vector v(m.discretization.owned,
                      m.discretization.relevant,
                      m.comm);
    v = m.dynamics.v_n;
    std::vector<dealii::Tensor<1, 3>> values;
    double                            energy = 0.0;
    m.discretization.for_each_owned_cell(
      m.discretization.n_q_1d,
      cell_flags,
      [&](const auto &, const auto &fe_values) {
        values.resize(fe_values.n_quadrature_points);
        fe_values[m.discretization.layout.displacement]
          .get_function_values(v, values);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          energy +=
            0.5 * m.params.density * values[q].norm_square() * fe_values.JxW(q);
      });
    return dealii::Utilities::MPI::sum(energy, m.comm);
  }

  double
  Problem::support_energy() const
  {
    const Impl                       &m = *impl;
    std::vector<dealii::Tensor<1, 3>> u_at, reference_at;
    double                            energy   = 0.0;
    const auto                       &supports = m.boundaries.robin_supports;
    m.discretization.for_each_owned_boundary_face(
      dealii::update_values | dealii::update_quadrature_points |
        dealii::update_normal_vectors | dealii::update_JxW_values,
      [&](const dealii::types::boundary_id id) {
        const auto support = supports.find(id);
        return support != supports.end() && support->second.stiffness != 0.0;
      },
      [&](const auto &face, const auto &fe_face) {
        const auto &support = supports.at(face->boundary_id());
        m.boundaries.support_stretch(fe_face,
                                     m.discretization.layout.displacement,
                                     m.u,
                                     support,
                                     u_at,
                                     reference_at);
        for (const unsigned int q : fe_face.quadrature_point_indices())
          {
            const double u2 =
              u_at[q] *
              (support.projection(fe_face.normal_vector(q)) * u_at[q]);
            energy += 0.5 * support.stiffness * u2 *
                      support.scale(fe_face.quadrature_point(q)) *
                      fe_face.JxW(q);
          }
      });
    return dealii::Utilities::MPI::sum(energy, m.comm);
  }

  void
  Problem::refer_supports_to_end_diastole(const double time)
  {
    Impl &m = *impl;
    if (!m.boundaries.any_from_end_diastole())
      return;
    auto &release = m.boundaries.release;
    if (release.time > 0)
      release.from = m.boundaries.support_reference; // where it is now
    release.to      = m.u_owned;
    release.start   = time;
    release.applied = -1;
    set_support_time(time);
  }

  void
  Problem::set_support_time(const double time)
  {
    Impl &m = *impl;
    if (!m.boundaries.any_from_end_diastole())
      return;
    auto        &release = m.boundaries.release;
    const double xi =
      release.time > 0
        ? std::clamp((time - release.start) / release.time, 0.0, 1.0)
        : 1.0;
    const double s = xi * xi * (3 - 2 * xi); // smooth step, 0 to 1
    if (s == release.applied)
      return; // (outside a release: every solve)
    release.applied = s;
    LA::MPI::Vector r(release.to);
    if (s < 1)
      r.sadd(s, 1 - s, release.from);
    m.boundaries.support_reference = r;
  }

  namespace
  {
    /// Adds the power of the dashpots of the Robin supports (to
    /// @p dissipation) and of the cavity pressures (to @p loads) on the
    /// boundary faces of @p cell, at displacement @p u and velocity @p v.
    void
    add_boundary_powers(const Discretization         &discretization,
                        const BoundaryConditions     &boundaries,
                        const CavityLoads            &cavity_loads,
                        const dealii::Vector<double> &pressures,
                        const dealii::DoFHandler<3>::active_cell_iterator &cell,
                        const LA::MPI::Vector                             &u,
                        const LA::MPI::Vector                             &v,
                        dealii::FEFaceValues<3> &fe_face,
                        double                  &dissipation,
                        double                  &loads)
    {
      const unsigned int                n_q = fe_face.get_quadrature().size();
      std::vector<dealii::Tensor<2, 3>> face_grad_u(n_q);
      std::vector<dealii::Tensor<1, 3>> face_v(n_q);
      for (const auto &face : cell->face_iterators())
        {
          if (!face->at_boundary())
            continue;
          const auto id      = face->boundary_id();
          const auto support = boundaries.robin_supports.find(id);
          const auto part    = std::find(cavity_loads.pressure_ids.begin(),
                                      cavity_loads.pressure_ids.end(),
                                      id) -
                            cavity_loads.pressure_ids.begin();
          const bool on_part = part < static_cast<std::ptrdiff_t>(
                                        cavity_loads.pressure_ids.size()) &&
                               pressures[part] != 0.0;
          const bool damped = support != boundaries.robin_supports.end() &&
                              support->second.damping != 0.0;
          if (!on_part && !damped)
            continue;
          fe_face.reinit(cell, face);
          fe_face[discretization.layout.displacement]
            .get_function_values(v, face_v);
          fe_face[discretization.layout.displacement]
            .get_function_gradients(u, face_grad_u);
          for (const unsigned int q : fe_face.quadrature_point_indices())
            {
              const dealii::Tensor<1, 3> &N = fe_face.normal_vector(q);
              if (damped)
                {
                  dissipation +=
                    support->second.damping *
                    (face_v[q] * (support->second.projection(N) * face_v[q])) *
                    support->second.scale(fe_face.quadrature_point(q)) *
                    fe_face.JxW(q);
                }
              if (on_part)
                {
                  const dealii::Tensor<2, 3> F =
                    dealii::unit_symmetric_tensor<3>() + face_grad_u[q];
                  loads -= pressures[part] *
                           (face_v[q] * (dealii::cofactor(F) * N)) *
                           fe_face.JxW(q);
                }
            }
        }
    }
  } // namespace

  PowerReport
  Problem::accepted_powers(const dealii::Vector<double> &pressures,
                           const double                  active_tension) const
  {
    const Impl     &m = *impl;
    const Dynamics &d = m.dynamics;
    PowerReport     report;
    if (!d.started)
      return report;
    AssertThrow(pressures.size() == m.loads.pressure_ids.size(),
                dealii::ExcMessage("Mechanics: one pressure per pressure "
                                   "part."));
    LA::MPI::Vector u(m.discretization.owned,
                      m.discretization.relevant,
                      m.comm),
      v(m.discretization.owned, m.discretization.relevant, m.comm);
    u = d.u_n;
    v = d.v_n;
    const dealii::Quadrature<3> quadrature =
      m.discretization.cell_quadrature(m.discretization.n_q_1d);
    const dealii::Quadrature<2> face_quadrature =
      m.discretization.face_quadrature(m.discretization.n_q_face_1d);
    dealii::FEValues<3>               fe_values(m.discretization.mapping,
                                  *m.discretization.fe,
                                  quadrature,
                                  dealii::update_values |
                                    dealii::update_gradients |
                                    dealii::update_JxW_values);
    dealii::FEFaceValues<3>           fe_face(m.discretization.mapping,
                                    *m.discretization.fe,
                                    face_quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_quadrature_points |
                                      dealii::update_normal_vectors |
                                      dealii::update_JxW_values);
    std::vector<dealii::Tensor<2, 3>> grad_u(quadrature.size()),
      grad_v(quadrature.size());
    std::vector<dealii::Tensor<1, 3>> v_at(quadrature.size());
    double                            dissipation = 0.0, loads = 0.0;
    for (const auto &cell :
         m.discretization.dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        fe_values[m.discretization.layout.displacement]
          .get_function_gradients(u, grad_u);
        fe_values[m.discretization.layout.displacement]
          .get_function_gradients(v, grad_v);
        fe_values[m.discretization.layout.displacement]
          .get_function_values(v, v_at);
        const auto data = m.points.point_data.get_data(cell);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            const dealii::Tensor<2, 3> F =
              dealii::unit_symmetric_tensor<3>() + grad_u[q];
            const dealii::SymmetricTensor<2, 3> E_dot =
              dealii::symmetrize(dealii::transpose(F) * grad_v[q]);
            double tension = active_tension + data[q]->tension;
            if (m.points.tension_model != nullptr)
              tension += data[q]->model_tension;
            dealii::SymmetricTensor<2, 3> S_active;
            if (tension != 0.0)
              Materials::add_active_stress(tension,
                                           m.params.active_cross_fibre,
                                           data[q]->basis,
                                           S_active);
            const double JxW = fe_values.JxW(q);
            dissipation +=
              m.params.viscosity * (E_dot * E_dot) * JxW +
              d.mass_damping * m.params.density * v_at[q].norm_square() * JxW;
            loads -= (S_active * E_dot) * JxW;
          }
        if (cell->at_boundary())
          add_boundary_powers(m.discretization,
                              m.boundaries,
                              m.loads,
                              pressures,
                              cell,
                              u,
                              v,
                              fe_face,
                              dissipation,
                              loads);
      }
    report.dissipation = dealii::Utilities::MPI::sum(dissipation, m.comm);
    report.loads       = dealii::Utilities::MPI::sum(loads, m.comm);
    return report;
  }

  double
  Problem::strain_energy() const
  {
    const Impl &m      = *impl;
    double      energy = 0.0;
    impl->for_each_point([&](const unsigned int,
                             const unsigned int,
                             PointData                  &data,
                             const dealii::Tensor<2, 3> &F,
                             const double                JxW) {
      Materials::PassiveInput in;
      in.F            = F;
      in.basis        = data.basis;
      in.with_tangent = false;
      Materials::PassiveOutput out;
      m.material.passive_law.evaluate(in, out);
      const double U =
        m.discretization.reduced_volumetric || m.discretization.layout.mixed()
          ? 0.0
          : m.material.volumetric_law.energy(dealii::determinant(in.F));
      energy += (out.psi + U) * JxW;
    });
    std::vector<dealii::Tensor<2, 3>> grad_u;
    if (m.discretization.reduced_volumetric)
      m.discretization.for_each_owned_cell(
        m.discretization.n_q_1d - 1,
        cell_flags,
        [&](const auto &, const auto &fe_values) {
          grad_u.resize(fe_values.n_quadrature_points);
          fe_values[m.discretization.layout.displacement]
            .get_function_gradients(m.u, grad_u);
          for (const unsigned int q : fe_values.quadrature_point_indices())
            energy += m.material.volumetric_law.energy(dealii::determinant(
                        dealii::unit_symmetric_tensor<3>() + grad_u[q])) *
                      fe_values.JxW(q);
        });
    if (m.discretization.layout.mixed())
      energy += m.multiplier_energy();
    return dealii::Utilities::MPI::sum(energy, m.comm);
  }

  double
  Problem::Impl::multiplier_energy() const
  {
    // The mixed formulations' volumetric energy, -p (J - 1) - p^2 / (2
    // kappa): at a solution int p (J - 1) = -int p^2 / kappa (the pressure
    // rows), so it is int p^2 / (2 kappa), 0 when incompressible.
    const Impl                       &m      = *this;
    const auto                       &layout = m.discretization.layout;
    std::vector<dealii::Tensor<2, 3>> grad_u;
    std::vector<double>               p;
    double                            energy = 0.0;
    m.discretization.for_each_owned_cell(
      m.discretization.n_q_1d,
      cell_flags,
      [&](const auto &, const auto &fe_values) {
        grad_u.resize(fe_values.n_quadrature_points);
        p.resize(fe_values.n_quadrature_points);
        fe_values[layout.displacement].get_function_gradients(m.u, grad_u);
        fe_values[layout.pressure].get_function_values(m.u, p);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            const double J = dealii::determinant(
              dealii::unit_symmetric_tensor<3>() + grad_u[q]);
            energy += (-p[q] * (J - 1.0) -
                       0.5 * m.material.inverse_bulk_modulus * p[q] * p[q]) *
                      fe_values.JxW(q);
          }
      });
    return energy;
  }
} // namespace systole::Mechanics
