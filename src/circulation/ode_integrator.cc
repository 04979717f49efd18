#include "circulation/ode_integrator.h"

#include <deal.II/lac/full_matrix.h>

#include "base/format.h"
#include "electrophysiology/arkode_adapter.h"

#include <petscvec.h>

#include <cmath>

// The model's ODE y' = f(t, y) as the implicit part of the project's ARKode
// adapter (no explicit part: ARKode's default DIRK table of the order). The
// adapter works on PETSc vectors; here they live on MPI_COMM_SELF and are
// copied to and from the Model's dealii::Vector in every callback (the state
// is small).

namespace systole::Circulation
{
  namespace
  {
    using Vector = dealii::Vector<double>;

    /// to = from, entry by entry (both of the same size, one rank).
    void
    copy(const LA::MPI::Vector &from, Vector &to)
    {
      const Vec     vec    = static_cast<const Vec &>(from);
      const double *values = nullptr;
      PetscInt      n      = 0;
      VecGetLocalSize(vec, &n);
      AssertThrow(std::size_t(n) == to.size(), dealii::ExcInternalError());
      VecGetArrayRead(vec, &values);
      std::copy(values, values + n, to.begin());
      VecRestoreArrayRead(vec, &values);
    }

    void
    copy(const Vector &from, LA::MPI::Vector &to)
    {
      const Vec vec    = static_cast<const Vec &>(to);
      double   *values = nullptr;
      PetscInt  n      = 0;
      VecGetLocalSize(vec, &n);
      AssertThrow(std::size_t(n) == from.size(), dealii::ExcInternalError());
      VecGetArray(vec, &values);
      std::copy(from.begin(), from.end(), values);
      VecRestoreArray(vec, &values);
    }
  } // namespace

  struct Integrator::Impl
  {
    Impl(const Model             &model,
         const Settings          &settings,
         const double             t0,
         const Vector            &y0,
         const ExternalPressures &external)
      : model(model)
      , settings(settings)
      , external(external)
      , t(t0)
      , y(y0)
      , state(dealii::complete_index_set(y0.size()), MPI_COMM_SELF)
      , y_work(y0.size())
      , f_work(y0.size())
    {}

    /// The adapter, with the model's right-hand side, Newton solve and
    /// valve roots.
    void
    create();

    /// (I - gamma J) x = b with J = df/dy at (@p time, @p y_work).
    void
    newton_solve(const double  time,
                 const double  gamma,
                 const Vector &b,
                 Vector       &x);

    void
    pressures(const double time, Vector &p_ext) const
    {
      p_ext.reinit(model.n_cavities());
      if (external)
        external(time, p_ext);
    }

    const Model      &model;
    Settings          settings;
    ExternalPressures external;
    double            t; ///< current time
    Vector            y; ///< state at t
    std::vector<bool> open;

    /// The state as the adapter's vector, and the adapter.
    LA::MPI::Vector                                    state;
    std::unique_ptr<Electrophysiology::ImexIntegrator> integrator;
    Vector                     y_work, f_work, b_work, x_work, p_ext_work;
    dealii::FullMatrix<double> jacobian, jacobian_p, system;
    std::vector<Event>         events;

    unsigned long jacobian_evaluations = 0, linear_solves = 0;
  };


  void
  Integrator::Impl::newton_solve(const double  time,
                                 const double  gamma,
                                 const Vector &b,
                                 Vector       &x)
  {
    pressures(time, p_ext_work);
    model.jacobian({time, y_work, p_ext_work}, jacobian, jacobian_p);
    ++jacobian_evaluations;
    const unsigned int m = jacobian.m();
    system.reinit(m, m);
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int j = 0; j < m; ++j)
        system(i, j) = (i == j ? 1.0 : 0.0) - gamma * jacobian(i, j);
    system.gauss_jordan();
    system.vmult(x, b);
    ++linear_solves;
  }


  void
  Integrator::Impl::create()
  {
    Electrophysiology::ImexIntegrator::Settings s;
    s.order              = settings.order;
    s.adaptive           = true;
    s.relative_tolerance = settings.relative_tolerance;
    s.max_step           = settings.max_step;
    s.initial_step       = settings.initial_step;
    s.min_step           = 0.0; // ARKode's own limit
    s.max_steps          = 1000000;
    for (unsigned int i = 0; i < model.n_states(); ++i)
      s.absolute_tolerances.push_back(settings.absolute_volume_tolerance /
                                      model.states()[i].volume_scale);

    Electrophysiology::ImexIntegrator::Callbacks callbacks;
    callbacks.nonlinear_implicit_rhs =
      [this](const double time, const LA::MPI::Vector &u, LA::MPI::Vector &f) {
        copy(u, y_work);
        pressures(time, p_ext_work);
        model.rhs({time, y_work, p_ext_work}, f_work);
        copy(f_work, f);
      };
    callbacks.newton_solve = [this](const double           time,
                                    const LA::MPI::Vector &u,
                                    const double           gamma,
                                    const LA::MPI::Vector &b,
                                    LA::MPI::Vector       &x) {
      copy(u, y_work);
      b_work.reinit(y_work.size());
      x_work.reinit(y_work.size());
      copy(b, b_work);
      newton_solve(time, gamma, b_work, x_work);
      copy(x_work, x);
    };
    callbacks.n_roots = model.n_valves();
    callbacks.roots   = [this](const double           time,
                             const LA::MPI::Vector &u,
                             std::vector<double>   &g) {
      copy(u, y_work);
      Vector indicators;
      pressures(time, p_ext_work);
      model.valve_indicators({time, y_work, p_ext_work}, indicators);
      g.assign(indicators.begin(), indicators.end());
    };
    callbacks.at_root = [this](const double            time,
                               const LA::MPI::Vector  &u,
                               const std::vector<int> &found) {
      Vector at_event(y.size());
      copy(u, at_event);
      for (unsigned int i = 0; i < found.size(); ++i)
        if (found[i] != 0)
          {
            events.push_back({time, i, found[i] > 0, at_event});
            open[i] = found[i] > 0;
          }
    };
    integrator =
      std::make_unique<Electrophysiology::ImexIntegrator>(s,
                                                          callbacks,
                                                          t,
                                                          MPI_COMM_SELF);
    copy(y, state);
  }


  Integrator::Integrator(const Model             &model,
                         const Settings          &settings,
                         const double             t0,
                         const Vector            &y0,
                         const ExternalPressures &external_pressures)
    : impl(std::make_unique<Impl>(model, settings, t0, y0, external_pressures))
  {
    AssertThrow(y0.size() == model.n_states(),
                dealii::ExcMessage("Circulation::Integrator: the initial "
                                   "state has the wrong size."));
    AssertThrow(settings.order >= 2 && settings.order <= 5,
                dealii::ExcMessage("Circulation::Integrator: the order must "
                                   "be 2, 3, 4 or 5."));
    AssertThrow(settings.relative_tolerance > 0 &&
                  settings.absolute_volume_tolerance > 0 &&
                  settings.max_step > 0 && settings.initial_step > 0,
                dealii::ExcMessage("Circulation::Integrator: tolerances and "
                                   "step sizes must be positive."));
    bool any_external = false;
    for (const auto &c : model.cavities())
      any_external = any_external || c.kind == CavityKind::external;
    AssertThrow(!any_external || external_pressures,
                dealii::ExcMessage(
                  "Circulation::Integrator: the model has external cavities, "
                  "so it needs their pressures (ExternalPressures)."));

    Vector p_ext, g;
    impl->pressures(t0, p_ext);
    model.valve_indicators({t0, y0, p_ext}, g);
    impl->open.resize(g.size());
    for (unsigned int i = 0; i < g.size(); ++i)
      impl->open[i] = g[i] > 0;
    impl->create();
  }

  Integrator::~Integrator() = default;


  std::vector<Integrator::Event>
  Integrator::advance(const double t_end)
  {
    Impl &m = *impl;
    AssertThrow(t_end > m.t,
                dealii::ExcMessage("Circulation::Integrator::advance: the end "
                                   "time (" +
                                   format_number(t_end, 12) +
                                   " ms) must lie after the current time (" +
                                   format_number(m.t, 12) + " ms)."));
    m.events.clear();
    // ARKode's failures throw with its message and time (ImexIntegrator).
    m.integrator->evolve(m.state, t_end);
    copy(m.state, m.y);
    m.t = t_end;

    // A sign change that the root finder did not report (a root at t_end
    // itself) is an event at t_end.
    Vector p_ext, g;
    m.pressures(t_end, p_ext);
    m.model.valve_indicators({t_end, m.y, p_ext}, g);
    for (unsigned int i = 0; i < g.size(); ++i)
      if ((g[i] > 0) != m.open[i])
        {
          m.open[i] = g[i] > 0;
          m.events.push_back({t_end, i, m.open[i], m.y});
        }
    return m.events;
  }


  double
  Integrator::time() const
  {
    return impl->t;
  }


  const dealii::Vector<double> &
  Integrator::state() const
  {
    return impl->y;
  }


  const std::vector<bool> &
  Integrator::valves_open() const
  {
    return impl->open;
  }


  void
  Integrator::external_pressures(const double t, Vector &p_ext) const
  {
    impl->pressures(t, p_ext);
  }


  Integrator::Statistics
  Integrator::statistics() const
  {
    const auto &arkode = *impl->integrator;
    Statistics  s;
    s.jacobian_evaluations = impl->jacobian_evaluations;
    s.linear_solves        = impl->linear_solves;
    s.steps                = arkode.n_steps();
    s.rhs_evaluations      = arkode.n_implicit_evaluations();
    s.error_test_failures  = arkode.n_error_test_failures();
    s.nonlinear_convergence_failures =
      arkode.n_nonlinear_convergence_failures();
    return s;
  }
} // namespace systole::Circulation
