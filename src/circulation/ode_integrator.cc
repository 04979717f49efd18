#include "circulation/ode_integrator.h"

#include <deal.II/lac/full_matrix.h>
#include <deal.II/sundials/arkode.h>
#include <deal.II/sundials/n_vector.h>

#include <arkode/arkode_arkstep.h>
#include <sundials/sundials_linearsolver.h>

#include <cmath>
#include <exception>
#include <limits>
#include <sstream>

// deal.II 9.4's ARKode wrapper calls std::function objects that return int
// (0 ok, > 0 recoverable, < 0 fatal) from inside SUNDIALS' C code, where an
// exception must not pass: every callback is wrapped in guarded(), which
// keeps the exception for advance() to rethrow. The wrapper checks
// ARKStepEvolve's flag with Assert only (debug builds) and, in a release
// build, goes on calling it after a failure; its output_step hook runs in
// plain C++ after every ARKStepEvolve, so that is where a failure (reported
// by ARKode's error handler) is turned into an exception.
//
// Root finding is not part of the 9.4 wrapper: custom_setup installs it with
// ARKStepRootInit. ARKode hands the root function the user data of the
// ARKStep memory, which the wrapper sets to the wrapper object itself
// (checked with ARKStepGetUserData in custom_setup); the wrapper object is a
// Solver, a derived class that knows its Impl. A root return ends one
// ARKStepEvolve early; the wrapper then calls output_step at the root time
// and continues to the end time, so the events are collected there.

namespace systole::Circulation
{
  namespace
  {
    using Vector  = dealii::Vector<double>;
    using Wrapper = dealii::SUNDIALS::ARKode<Vector>;

    void
    check(const int flag, const char *function)
    {
      AssertThrow(flag >= 0,
                  dealii::ExcMessage(std::string("ARKode: ") + function +
                                     " failed with flag " +
                                     std::to_string(flag) + "."));
    }

    std::string
    str(const double x)
    {
      std::ostringstream s;
      s.precision(12);
      s << x;
      return s.str();
    }
  } // namespace

  struct Integrator::Impl
  {
    /// The wrapper, so that the root function can find its Impl.
    struct Solver : Wrapper
    {
      Solver(const AdditionalData &data, Impl *owner)
        : Wrapper(data, MPI_COMM_SELF)
        , owner(owner)
      {}
      Impl *owner;
    };

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
    {}

    template <class Function>
    int
    guarded(const Function &f, const int failure_code = -1) noexcept
    {
      try
        {
          f();
          return 0;
        }
      catch (...)
        {
          if (!fatal)
            fatal = std::current_exception();
          return failure_code;
        }
    }

    void
    create();

    /// custom_setup: tolerances, step limits, stop time, root finding.
    void
    configure(void *arkode_memory);

    /// output_step: after every ARKStepEvolve (and once after the set-up).
    void
    on_output(const double time, const Vector &state);

    void
    pressures(const double time, Vector &p_ext) const
    {
      p_ext.reinit(model.n_cavities());
      if (external)
        external(time, p_ext);
    }

    static int
    root_function(realtype t, N_Vector y, realtype *g, void *user_data);

    static void
    error_handler(int         code,
                  const char *module,
                  const char *function,
                  char       *message,
                  void       *data);

    const Model      &model;
    Settings          settings;
    ExternalPressures external;
    double            t;      ///< current time
    double            target; ///< end time of the advance() in progress
    Vector            y;      ///< state at t
    Vector            absolute_tolerances;
    std::vector<bool> open;

    std::unique_ptr<Solver>    solver;
    bool                       initial_output = false;
    dealii::FullMatrix<double> jacobian, jacobian_p, system;
    Vector                     p_ext_work;
    std::vector<Event>         events;

    std::exception_ptr fatal;
    bool               arkode_failed = false;
    std::string        arkode_message;

    unsigned long jacobian_evaluations = 0, linear_solves = 0;
  };


  void
  Integrator::Impl::create()
  {
    const unsigned int n = model.n_states();
    absolute_tolerances.reinit(n);
    for (unsigned int i = 0; i < n; ++i)
      absolute_tolerances[i] =
        settings.absolute_volume_tolerance / model.states()[i].volume_scale;

    // Output period longer than any advance(): one ARKStepEvolve per
    // advance() unless a root ends it early. The minimum step is left to
    // ARKode (0); the stop time is set in configure().
    const Wrapper::AdditionalData data(t,
                                       t,
                                       settings.initial_step,
                                       std::numeric_limits<double>::max(),
                                       0.0,
                                       settings.order,
                                       5,
                                       false,
                                       false,
                                       false,
                                       3,
                                       settings.absolute_volume_tolerance,
                                       settings.relative_tolerance);
    solver = std::make_unique<Solver>(data, this);

    solver->implicit_function =
      [this](const double time, const Vector &state, Vector &f) -> int {
      return guarded([&]() {
        pressures(time, p_ext_work);
        model.rhs(time, state, p_ext_work, f);
      });
    };
    solver->jacobian_times_setup =
      [this](const double time, const Vector &state, const Vector &) -> int {
      return guarded([&]() {
        pressures(time, p_ext_work);
        model.jacobian(time, state, p_ext_work, jacobian, jacobian_p);
        ++jacobian_evaluations;
      });
    };
    solver->jacobian_times_vector = [this](const Vector &v,
                                           Vector       &Jv,
                                           const double,
                                           const Vector &,
                                           const Vector &) -> int {
      return guarded([&]() { jacobian.vmult(Jv, v); });
    };
    // (I - gamma J) x = b with ARKode's current gamma and the Jacobian of
    // the last set-up (every step, see configure()).
    solver->solve_linearized_system =
      [this](dealii::SUNDIALS::SundialsOperator<Vector> &,
             dealii::SUNDIALS::SundialsPreconditioner<Vector> &,
             Vector       &x,
             const Vector &b,
             const double) -> int {
      return guarded(
        [&]() {
          double gamma = 0;
          check(ARKStepGetCurrentGamma(solver->get_arkode_memory(), &gamma),
                "ARKStepGetCurrentGamma");
          const unsigned int m = jacobian.m();
          system.reinit(m, m);
          for (unsigned int i = 0; i < m; ++i)
            for (unsigned int j = 0; j < m; ++j)
              system(i, j) = (i == j ? 1.0 : 0.0) - gamma * jacobian(i, j);
          system.gauss_jordan();
          system.vmult(x, b);
          ++linear_solves;
        },
        // Handed to ARKode's linear solver interface, which knows SUNLS_*
        // codes only.
        SUNLS_PACKAGE_FAIL_UNREC);
    };
    solver->get_local_tolerances = [this]() -> Vector & {
      return absolute_tolerances;
    };
    solver->custom_setup = [this](void *memory) {
      configure(memory);
      initial_output = true;
    };
    solver->output_step =
      [this](const double time, const Vector &state, const unsigned int) {
        on_output(time, state);
      };
  }


  void
  Integrator::Impl::configure(void *memory)
  {
    void *user_data = nullptr;
    check(ARKStepGetUserData(memory, &user_data), "ARKStepGetUserData");
    AssertThrow(user_data == static_cast<Wrapper *>(solver.get()),
                dealii::ExcMessage(
                  "Circulation::Integrator: deal.II's ARKode wrapper does "
                  "not pass itself as ARKode's user data; the valve root "
                  "function cannot find its integrator."));
    check(ARKStepSetErrHandlerFn(memory, &error_handler, this),
          "ARKStepSetErrHandlerFn");
    check(ARKStepSetMaxNumSteps(memory, 1000000), "ARKStepSetMaxNumSteps");
    check(ARKStepSetMaxStep(memory, settings.max_step), "ARKStepSetMaxStep");
    // A fresh Jacobian every step: it changes at every valve switch, and
    // the state is small.
    check(ARKStepSetLSetupFrequency(memory, 1), "ARKStepSetLSetupFrequency");
    check(ARKStepSetStopTime(memory, target), "ARKStepSetStopTime");
    if (model.n_valves() > 0)
      {
        check(ARKStepRootInit(memory, model.n_valves(), &root_function),
              "ARKStepRootInit");
        check(ARKStepSetNoInactiveRootWarn(memory),
              "ARKStepSetNoInactiveRootWarn");
      }
  }


  int
  Integrator::Impl::root_function(realtype  time,
                                  N_Vector  state,
                                  realtype *g,
                                  void     *user_data)
  {
    Impl &self =
      *static_cast<Solver *>(static_cast<Wrapper *>(user_data))->owner;
    return self.guarded([&]() {
      const Vector &y =
        *dealii::SUNDIALS::internal::unwrap_nvector_const<Vector>(state);
      Vector p_ext, indicators;
      self.pressures(time, p_ext);
      self.model.valve_indicators(time, y, p_ext, indicators);
      for (unsigned int i = 0; i < indicators.size(); ++i)
        g[i] = indicators[i];
    });
  }


  void
  Integrator::Impl::error_handler(int         code,
                                  const char *module,
                                  const char *function,
                                  char       *message,
                                  void       *data)
  {
    // Keep ARKode's messages off the console (every rank would print
    // them); failures become the exception of advance().
    if (code < 0)
      {
        auto &self         = *static_cast<Impl *>(data);
        self.arkode_failed = true;
        self.arkode_message =
          std::string(module) + " " + function + ": " + message;
      }
  }


  void
  Integrator::Impl::on_output(const double time, const Vector &state)
  {
    if (fatal)
      std::rethrow_exception(fatal);
    AssertThrow(!arkode_failed,
                dealii::ExcMessage("Circulation: ARKode failed at t = " +
                                   str(time) + " ms: " + arkode_message));
    if (initial_output)
      {
        initial_output = false;
        return;
      }
    if (std::abs(time - target) <= 1e-14 * std::max(1.0, std::abs(target)))
      return;

    // Not at the end: ARKode returned at a root.
    std::vector<int> found(model.n_valves(), 0);
    check(ARKStepGetRootInfo(solver->get_arkode_memory(), found.data()),
          "ARKStepGetRootInfo");
    for (unsigned int i = 0; i < found.size(); ++i)
      if (found[i] != 0)
        {
          events.push_back({time, i, found[i] > 0, state});
          open[i] = found[i] > 0;
        }
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
    model.valve_indicators(t0, y0, p_ext, g);
    impl->open.resize(g.size());
    for (unsigned int i = 0; i < g.size(); ++i)
      impl->open[i] = g[i] > 0;
    impl->target = t0;
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
                                   str(t_end) +
                                   " ms) must lie after the current time (" +
                                   str(m.t) + " ms)."));
    m.target = t_end;
    m.events.clear();
    m.fatal         = nullptr;
    m.arkode_failed = false;
    // After the first call the wrapper only resets the stop time.
    m.solver->solve_ode_incrementally(m.y, t_end);
    if (m.fatal)
      std::rethrow_exception(m.fatal);
    m.t = t_end;

    // A sign change that the root finder did not report (a root at t_end
    // itself) is an event at t_end.
    Vector p_ext, g;
    m.pressures(t_end, p_ext);
    m.model.valve_indicators(t_end, m.y, p_ext, g);
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
    Statistics s;
    s.jacobian_evaluations = impl->jacobian_evaluations;
    s.linear_solves        = impl->linear_solves;
    void *memory           = impl->solver->get_arkode_memory();
    if (memory == nullptr) // before the first advance()
      return s;
    long int n = 0, n_explicit = 0;
    check(ARKStepGetNumSteps(memory, &n), "ARKStepGetNumSteps");
    s.steps = n;
    check(ARKStepGetNumRhsEvals(memory, &n_explicit, &n),
          "ARKStepGetNumRhsEvals");
    s.rhs_evaluations = n;
    check(ARKStepGetNumErrTestFails(memory, &n), "ARKStepGetNumErrTestFails");
    s.error_test_failures = n;
    check(ARKStepGetNumNonlinSolvConvFails(memory, &n),
          "ARKStepGetNumNonlinSolvConvFails");
    s.nonlinear_convergence_failures = n;
    return s;
  }
} // namespace systole::Circulation
