#include "electrophysiology/arkode_adapter.h"

#include <deal.II/sundials/arkode.h>
#include <deal.II/sundials/n_vector.h>

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_butcher.h>
#include <petscvec.h>
#include <sundials/sundials_linearsolver.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <vector>

// deal.II 9.4's ARKode wrapper calls std::function objects that return int
// (0 ok, > 0 recoverable, < 0 fatal) from inside SUNDIALS' C code, where an
// exception must not pass. Every callback below is wrapped in guarded(),
// which turns our typed exceptions into those codes and keeps the exception
// for evolve() to rethrow.
//
// The 9.4 wrapper checks ARKStepEvolve's return flag with Assert (debug
// builds only) and, in a release build, calls ARKStepEvolve again and again
// after a failure. Its output_step hook runs in plain C++ after every
// ARKStepEvolve: there we throw when ARKode stopped short of the end time.

// The after_step callback is ARKStep's post-processing hook, which ARKode
// calls with the user data of the ARKStep memory: the wrapper sets it to the
// wrapper object itself (checked in custom_setup), which is a Wrapper here,
// a derived class that knows its Impl. So does ARKode's error-weight
// function (error_weights below).

namespace systole::Electrophysiology
{
  namespace
  {
    using Vector = LA::MPI::Vector;
    using ARKode = dealii::SUNDIALS::ARKode<Vector>;

    void
    check(const int flag, const char *function)
    {
      AssertThrow(flag >= 0,
                  dealii::ExcMessage(std::string("ARKode: ") + function +
                                     " failed with flag " +
                                     std::to_string(flag) + "."));
    }


    /// |R(z)| of the explicit Runge-Kutta method of @p table at real z.
    double
    stability_function(const ARKodeButcherTable table, const double z)
    {
      // y' = lambda y from y = 1: stage values Y_i = 1 + z sum_j a_ij Y_j
      // (explicit: j < i), R = 1 + z sum_i b_i Y_i.
      std::vector<double> Y(table->stages);
      double              R = 1;
      for (int i = 0; i < table->stages; ++i)
        {
          Y[i] = 1;
          for (int j = 0; j < i; ++j)
            Y[i] += z * table->A[i][j] * Y[j];
          R += z * table->b[i] * Y[i];
        }
      return std::abs(R);
    }


    /// beta of the explicit method of @p table: [-beta, 0] is the part of
    /// the negative real axis around 0 where |R(z)| <= 1.
    double
    real_stability_interval(const ARKodeButcherTable table)
    {
      AssertThrow(table != nullptr, dealii::ExcInternalError());
      double inside = 0, outside = 0;
      for (double z = -0.01; z > -100; z -= 0.01)
        if (stability_function(table, z) > 1 + 1e-12)
          {
            outside = z;
            break;
          }
        else
          inside = z;
      AssertThrow(outside < 0,
                  dealii::ExcMessage("ImexIntegrator: the explicit method is "
                                     "stable on [-100, 0]; not an explicit "
                                     "Runge-Kutta table?"));
      while (inside - outside > 1e-10)
        {
          const double middle = 0.5 * (inside + outside);
          (stability_function(table, middle) > 1 + 1e-12 ? outside : inside) =
            middle;
        }
      return -inside;
    }
  } // namespace


  struct ImexIntegrator::Impl
  {
    /// The wrapper, so that the post-processing hook can find its Impl.
    struct Wrapper : public ARKode
    {
      Wrapper(const AdditionalData &data, const MPI_Comm comm, Impl &owner)
        : ARKode(data, comm)
        , owner(owner)
      {}
      Impl &owner;
    };

    Impl(const Settings  &settings,
         const Callbacks &callbacks,
         const double     t0,
         const MPI_Comm   comm)
      : settings(settings)
      , callbacks(callbacks)
      , comm(comm)
      , t(t0)
    {}

    /// Run @p f; map a recoverable failure to @p recoverable_code and any
    /// other exception to -1, keeping it for evolve().
    template <class Function>
    int
    guarded(const Function &f, const int recoverable_code = 1)
    {
      try
        {
          f();
          return 0;
        }
      catch (const ExcRecoverableStepFailure &)
        {
          recoverable = std::current_exception();
          return recoverable_code;
        }
      catch (...)
        {
          if (!fatal)
            fatal = std::current_exception();
          return -1;
        }
    }

    /// A new ARKode object starting at time t (the wrapper restarts ARKStep
    /// at its first solve_ode_incrementally()).
    void
    create();

    /// Fixed step / stop time for the step to t_end; called by custom_setup
    /// on a (re)start and before every later evolve.
    void
    configure(void *arkode_memory) const;

    /// Add the counters of the current ARKStep memory to the totals.
    void
    accumulate_counters();

    /// ARKode's error handler: keep the last message.
    static void
    error_handler(int         error_code,
                  const char *module,
                  const char *function,
                  char       *message,
                  void       *data);

    /// ARKStep's post-processing hook: calls callbacks.after_step.
    static int
    postprocess_step(realtype time, N_Vector y, void *user_data);

    /// ARKode's error weights (ARKEwtFn) w_i = 1/(rtol |y_i| + atol) of
    /// @p y, computed as ARKode's own scalar-tolerance weights (arkEwtSetSS:
    /// N_VAbs, N_VScale, N_VAddConst, N_VInv, the same operations in the
    /// same order, so the same weights) but on PETSc's local arrays: deal.II
    /// 9.4's N_Vector abs and inverse of PETSc vectors go element by element
    /// through VecGetValues and VecSetValues, which cost a quarter of the
    /// monodomain's time with ten Tusscher-Panfilov's 19 values per node
    /// (ARKode sets the weights at every step, fixed steps too).
    static int
    error_weights(N_Vector y, N_Vector weights, void *user_data);

    /// ARKode's explicit stability function (ARKExpStabFn): the largest
    /// stable step beta / rho at @p y, or -1 (no bound) when rho = 0.
    static int
    explicit_stability(N_Vector y, realtype t, realtype *h_stable, void *data);

    Settings                settings;
    Callbacks               callbacks;
    MPI_Comm                comm;
    double                  t;         ///< current time
    double                  t_end = 0; ///< end of the evolve() in progress
    std::unique_ptr<ARKode> ode;
    double t_accepted     = 0;     ///< end of the last accepted ARKode step
    bool   started        = false; ///< ARKStep memory exists
    bool   initial_output = false; ///< next output_step is the initial one

    std::exception_ptr fatal, recoverable;
    std::string        arkode_message; ///< last ARKode error message

    unsigned long steps = 0, explicit_evaluations = 0, implicit_evaluations = 0;
    /// Steps set by the stability bound before the last create().
    unsigned long stability_limited = 0;
    /// beta of the explicit table: of ARKode's default table of the order
    /// until the first step, then of the table in use.
    double beta                 = 0;
    bool   beta_of_table_in_use = false;
    /// The first step after create() (ARKode's initial step is not subject
    /// to the stability function): Settings::max_step, or less (evolve()).
    double initial_step = 0;
  };


  void
  ImexIntegrator::Impl::create()
  {
    // Output period: longer than any evolve(), so the wrapper calls
    // ARKStepEvolve once per evolve(). Tolerances matter for adaptive steps
    // only.
    const ARKode::AdditionalData data(
      t,
      t,
      settings.max_step,
      std::numeric_limits<double>::max(),
      1e-10,
      settings.order,
      3,
      /*implicit_function_is_linear=*/true,
      /*implicit_function_is_time_independent=*/true,
      /*mass_is_time_independent=*/true,
      3,
      settings.absolute_tolerance,
      settings.relative_tolerance);
    ode        = std::make_unique<Wrapper>(data, comm, *this);
    started    = false;
    t_accepted = t;

    ode->explicit_function =
      [this](const double time, const Vector &y, Vector &f) -> int {
      return guarded([&]() {
        callbacks.explicit_rhs(time, y, f);
        ++explicit_evaluations;
      });
    };
    ode->implicit_function =
      [this](const double, const Vector &y, Vector &f) -> int {
      return guarded([&]() {
        callbacks.implicit_rhs(y, f);
        ++implicit_evaluations;
      });
    };
    // J v: only ARKode's operator (unused by our solver) applies it, but the
    // wrapper needs it to install solve_linearized_system.
    ode->jacobian_times_vector = [this](const Vector &v,
                                        Vector       &Jv,
                                        const double,
                                        const Vector &,
                                        const Vector &) -> int {
      return guarded([&]() { callbacks.implicit_rhs(v, Jv); });
    };
    // (I - gamma J) x = b with ARKode's current gamma: the implicit part is
    // linear, so one exact solve per stage is the whole Newton iteration.
    ode->solve_linearized_system =
      [this](dealii::SUNDIALS::SundialsOperator<Vector> &,
             dealii::SUNDIALS::SundialsPreconditioner<Vector> &,
             Vector       &x,
             const Vector &b,
             const double) -> int {
      return guarded(
        [&]() {
          double gamma = 0;
          check(ARKStepGetCurrentGamma(ode->get_arkode_memory(), &gamma),
                "ARKStepGetCurrentGamma");
          callbacks.solve(gamma, b, x);
        },
        // The wrapper hands this code to ARKode's linear solver interface
        // unchanged, which knows SUNLS_* codes only (1 would pass as success).
        SUNLS_CONV_FAIL);
    };
    ode->custom_setup = [this](void *arkode_memory) {
      check(ARKStepSetErrHandlerFn(arkode_memory, &error_handler, this),
            "ARKStepSetErrHandlerFn");
      void *user_data = nullptr;
      check(ARKStepGetUserData(arkode_memory, &user_data),
            "ARKStepGetUserData");
      AssertThrow(user_data == static_cast<ARKode *>(ode.get()),
                  dealii::ExcMessage(
                    "ImexIntegrator: deal.II's ARKode wrapper does not "
                    "pass itself as ARKode's user data; the after-step "
                    "callback and the error weights cannot find their "
                    "integrator."));
      // Instead of the wrapper's scalar tolerances (the same weights).
      check(ARKStepWFtolerances(arkode_memory, &error_weights),
            "ARKStepWFtolerances");
      if (callbacks.after_step)
        check(ARKStepSetPostprocessStepFn(arkode_memory, &postprocess_step),
              "ARKStepSetPostprocessStepFn");
      if (callbacks.explicit_stiffness && settings.adaptive)
        {
          check(ARKStepSetStabilityFn(arkode_memory, &explicit_stability, this),
                "ARKStepSetStabilityFn");
          check(ARKStepSetCFLFraction(arkode_memory, stability_fraction),
                "ARKStepSetCFLFraction");
          check(ARKStepSetInitStep(arkode_memory, initial_step),
                "ARKStepSetInitStep");
        }
      configure(arkode_memory);
      started = true;
      // The wrapper calls output_step once right after this set-up, at the
      // start time: that call is not the end of an ARKStepEvolve.
      initial_output = true;
    };
    // Called (in C++, outside SUNDIALS) after every ARKStepEvolve: a return
    // before the end time is a failure.
    ode->output_step = [this](const double time, const Vector &, unsigned int) {
      if (fatal)
        std::rethrow_exception(fatal);
      if (initial_output)
        {
          initial_output = false;
          return;
        }
      if (std::abs(time - t_end) > 1e-12 * std::max(1.0, std::abs(t_end)))
        {
          if (recoverable)
            std::rethrow_exception(recoverable);
          AssertThrow(false,
                      dealii::ExcMessage(
                        "ARKode stopped at t = " + std::to_string(time) +
                        " ms: " + arkode_message));
        }
    };
  }


  void
  ImexIntegrator::Impl::error_handler(int,
                                      const char *module,
                                      const char *function,
                                      char       *message,
                                      void       *data)
  {
    static_cast<Impl *>(data)->arkode_message =
      std::string(module) + " " + function + ": " + message;
  }


  int
  ImexIntegrator::Impl::postprocess_step(const realtype time,
                                         N_Vector       y,
                                         void          *user_data)
  {
    Impl &self =
      static_cast<Wrapper *>(static_cast<ARKode *>(user_data))->owner;
    return self.guarded([&]() {
      Vector &state = *dealii::SUNDIALS::internal::unwrap_nvector<Vector>(y);
      self.callbacks.after_step(time, time - self.t_accepted, state);
      self.t_accepted = time;
    });
  }


  int
  ImexIntegrator::Impl::error_weights(N_Vector y,
                                      N_Vector weights,
                                      void    *user_data)
  {
    Impl &self =
      static_cast<Wrapper *>(static_cast<ARKode *>(user_data))->owner;
    return self.guarded([&]() {
      const Vec y_vec = static_cast<const Vec &>(
        *dealii::SUNDIALS::internal::unwrap_nvector_const<Vector>(y));
      const Vec w_vec = static_cast<const Vec &>(
        *dealii::SUNDIALS::internal::unwrap_nvector<Vector>(weights));
      PetscInt       n = 0, n_w = 0;
      PetscErrorCode ierr = VecGetLocalSize(y_vec, &n);
      AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      ierr = VecGetLocalSize(w_vec, &n_w);
      AssertThrow(ierr == 0 && n_w == n, dealii::ExcInternalError());
      const double *y_values = nullptr;
      double       *w_values = nullptr;
      ierr                   = VecGetArrayRead(y_vec, &y_values);
      AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      ierr = VecGetArray(w_vec, &w_values);
      AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      const double rtol     = self.settings.relative_tolerance;
      const double atol     = self.settings.absolute_tolerance;
      bool         positive = true;
      for (PetscInt i = 0; i < n; ++i)
        {
          const double tolerance = rtol * std::abs(y_values[i]) + atol;
          positive               = positive && tolerance > 0;
          w_values[i]            = 1.0 / tolerance;
        }
      VecRestoreArray(w_vec, &w_values);
      VecRestoreArrayRead(y_vec, &y_values);
      AssertThrow(positive,
                  dealii::ExcMessage("ImexIntegrator: an error weight is "
                                     "infinite (absolute tolerance 0 at a "
                                     "zero component)."));
    });
  }


  int
  ImexIntegrator::Impl::explicit_stability(N_Vector y,
                                           realtype,
                                           realtype *h_stable,
                                           void     *data)
  {
    Impl &self = *static_cast<Impl *>(data);
    return self.guarded([&]() {
      if (!self.beta_of_table_in_use)
        {
          // ARKode picks its tables at the first step.
          ARKodeButcherTable implicit_table = nullptr, explicit_table = nullptr;
          check(ARKStepGetCurrentButcherTables(self.ode->get_arkode_memory(),
                                               &implicit_table,
                                               &explicit_table),
                "ARKStepGetCurrentButcherTables");
          self.beta                 = real_stability_interval(explicit_table);
          self.beta_of_table_in_use = true;
        }
      const double rho = self.callbacks.explicit_stiffness(
        *dealii::SUNDIALS::internal::unwrap_nvector_const<Vector>(y));
      *h_stable = rho > 0 ? self.beta / rho : -1.0;
    });
  }


  void
  ImexIntegrator::Impl::configure(void *arkode_memory) const
  {
    check(ARKStepSetMaxNumSteps(arkode_memory, 100000),
          "ARKStepSetMaxNumSteps");
    if (settings.adaptive)
      check(ARKStepSetMaxStep(arkode_memory, settings.max_step),
            "ARKStepSetMaxStep");
    else
      check(ARKStepSetFixedStep(arkode_memory, t_end - t),
            "ARKStepSetFixedStep");
    check(ARKStepSetStopTime(arkode_memory, t_end), "ARKStepSetStopTime");
    check(ARKStepSetDeduceImplicitRhs(arkode_memory,
                                      settings.deduce_implicit_rhs ? SUNTRUE
                                                                   : SUNFALSE),
          "ARKStepSetDeduceImplicitRhs");
  }


  void
  ImexIntegrator::Impl::accumulate_counters()
  {
    if (!started)
      return;
    long int n = 0;
    check(ARKStepGetNumSteps(ode->get_arkode_memory(), &n),
          "ARKStepGetNumSteps");
    steps += n;
    check(ARKStepGetNumExpSteps(ode->get_arkode_memory(), &n),
          "ARKStepGetNumExpSteps");
    if (callbacks.explicit_stiffness && settings.adaptive)
      stability_limited += n;
  }


  ImexIntegrator::ImexIntegrator(const Settings  &settings,
                                 const Callbacks &callbacks,
                                 const double     t0,
                                 const MPI_Comm   comm)
    : impl(std::make_unique<Impl>(settings, callbacks, t0, comm))
  {
    AssertThrow(settings.order >= 3 && settings.order <= 5,
                dealii::ExcMessage("ARKode order must be 3, 4 or 5."));
    if (callbacks.explicit_stiffness && settings.adaptive)
      {
        // ARKStep's default IMEX table of the order, for the first step
        // (its stability function takes the table in use after it).
        const int id = settings.order == 3   ? ARKSTEP_DEFAULT_ARK_ETABLE_3
                       : settings.order == 4 ? ARKSTEP_DEFAULT_ARK_ETABLE_4
                                             : ARKSTEP_DEFAULT_ARK_ETABLE_5;
        ARKodeButcherTable table =
          ARKodeButcherTable_LoadERK(static_cast<ARKODE_ERKTableID>(id));
        impl->beta = real_stability_interval(table);
        ARKodeButcherTable_Free(table);
      }
    impl->create();
  }

  ImexIntegrator::~ImexIntegrator() = default;


  void
  ImexIntegrator::evolve(LA::MPI::Vector &y, const double t_end)
  {
    Impl &m = *impl;
    AssertThrow(t_end > m.t,
                dealii::ExcMessage("ImexIntegrator::evolve: the end time must "
                                   "lie after the current time."));
    m.t_end = t_end;
    if (m.started)
      m.configure(m.ode->get_arkode_memory());
    m.fatal       = nullptr;
    m.recoverable = nullptr;
    m.arkode_message.clear();
    if (!m.started && m.settings.adaptive && m.callbacks.explicit_stiffness)
      {
        // ARKode starts (after create()) with this step, which its
        // stability function does not see: keep it within the bound too.
        const double rho = m.callbacks.explicit_stiffness(y);
        m.initial_step   = std::min(m.settings.max_step,
                                  rho > 0 ? stability_fraction * m.beta / rho
                                            : m.settings.max_step);
      }
    // Throws (from output_step) when ARKode stops short of t_end; a
    // recoverable failure that ARKode cured by a smaller step is no error.
    m.ode->solve_ode_incrementally(y, t_end);
    m.t = t_end;
  }


  void
  ImexIntegrator::reset(const double t)
  {
    impl->accumulate_counters();
    impl->t = t;
    impl->create();
  }


  double
  ImexIntegrator::time() const
  {
    return impl->t;
  }


  unsigned long
  ImexIntegrator::n_steps() const
  {
    long int n = 0;
    if (impl->started)
      check(ARKStepGetNumSteps(impl->ode->get_arkode_memory(), &n),
            "ARKStepGetNumSteps");
    return impl->steps + n;
  }


  unsigned long
  ImexIntegrator::n_explicit_evaluations() const
  {
    return impl->explicit_evaluations;
  }


  unsigned long
  ImexIntegrator::n_implicit_evaluations() const
  {
    return impl->implicit_evaluations;
  }


  unsigned long
  ImexIntegrator::n_stability_limited_steps() const
  {
    long int n = 0;
    if (impl->started && impl->callbacks.explicit_stiffness &&
        impl->settings.adaptive)
      check(ARKStepGetNumExpSteps(impl->ode->get_arkode_memory(), &n),
            "ARKStepGetNumExpSteps");
    return impl->stability_limited + n;
  }


  double
  ImexIntegrator::explicit_stability_interval() const
  {
    return impl->beta;
  }
} // namespace systole::Electrophysiology
