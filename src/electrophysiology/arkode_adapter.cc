#include "electrophysiology/arkode_adapter.h"

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_butcher.h>
#include <nvector/nvector_petsc.h>
#include <petscvec.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <vector>

// ARKStep through SUNDIALS' own C interface (for the electrophysiology and
// the 0D circulation alike), on SUNDIALS' PETSc N_Vector
// (nvector_petsc): its operations are PETSc's (VecAXPBYPCZ, one
// MPI_Allreduce per norm). deal.II 9.4's ARKode wrapper did the same
// steps on its own N_Vector of PETSc vectors, whose weighted RMS norm copies
// the vector (a new MPI vector and two reductions per norm, twice a step)
// and whose other operations go through deal.II's vector interface: on 2
// ranks of the reaction-eikonal model that was most of the time of a step
// (docs/verification.md, "Electrophysiology: the ARKode adapter").
//
// The callbacks see LA::MPI::Vector (deal.II's PETSc vectors): views whose
// storage is ARKode's vector's for the duration of a call (VecPlaceArray).
// SUNDIALS' C code must not see an exception: every callback goes through
// guarded(), which maps our typed exceptions to SUNDIALS' return codes and
// keeps them for evolve() to rethrow.

namespace systole::Electrophysiology
{
  namespace
  {
    void
    check(const int flag, const char *function)
    {
      AssertThrow(flag >= 0,
                  dealii::ExcMessage(std::string("ARKode: ") + function +
                                     " failed with flag " +
                                     std::to_string(flag) + "."));
    }


    /// @p before plus ARKode's counter @p get (@p name, for the message) of
    /// the ARKStep memory @p memory (nothing when it is null).
    unsigned long
    total(void *memory,
          int (*get)(void *, long int *),
          const char         *name,
          const unsigned long before)
    {
      long int n = 0;
      if (memory != nullptr)
        check(get(memory, &n), name);
      return before + n;
    }


    /// ARKStep's default explicit table of the IMEX method of @p order (3
    /// to 5): the explicit half of the ARK pair.
    int
    explicit_table_of_order(const unsigned int order)
    {
      return order == 3   ? ARKSTEP_DEFAULT_ARK_ETABLE_3
             : order == 4 ? ARKSTEP_DEFAULT_ARK_ETABLE_4
                          : ARKSTEP_DEFAULT_ARK_ETABLE_5;
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


    /// The weighted RMS norm, sqrt(sum_i (x_i w_i)^2 / N), the same on any
    /// partition: the squares are summed exactly, in fixed point (units of
    /// 2^-63, each clamped at 2^32: such an error is rejected whatever its
    /// size) in 128-bit integers, whose sum does not depend on the order;
    /// one MPI_Allgather of the ranks' sums. With a floating-point sum the
    /// last bits depended on the partition, and so, through ARKode's step
    /// decisions, did the adaptive steps (2 steps in 789 between 1 and 2
    /// ranks of a coarse heartbeat, ECG leads 1e-6 apart).
    realtype
    weighted_rms_norm(N_Vector x, N_Vector w)
    {
      __extension__ typedef unsigned __int128 Sum;
      constexpr double                        scale = 0x1p63;
      constexpr double                        clamp = 0x1p32;
      const Vec                               x_vec = N_VGetVector_Petsc(x);
      const Vec                               w_vec = N_VGetVector_Petsc(w);
      PetscInt                                n     = 0;
      const double                           *xd = nullptr, *wd = nullptr;
      VecGetLocalSize(x_vec, &n);
      VecGetArrayRead(x_vec, &xd);
      VecGetArrayRead(w_vec, &wd);
      Sum           local   = 0;
      std::uint64_t not_num = 0;
      for (PetscInt i = 0; i < n; ++i)
        {
          const double term = (xd[i] * wd[i]) * (xd[i] * wd[i]);
          if (term < 1.0) // most: the fraction alone, one conversion
            local += static_cast<std::uint64_t>(
              static_cast<std::int64_t>(term * scale));
          else if (term >= 1.0)
            {
              // Whole part and fraction (exact), each converted by the
              // processor's own double-to-int64 conversion.
              const double       v     = std::min(term, clamp);
              const std::int64_t whole = static_cast<std::int64_t>(v);
              const std::int64_t part  = static_cast<std::int64_t>(
                (v - static_cast<double>(whole)) * scale);
              local += (static_cast<Sum>(whole) << 63) +
                       static_cast<std::uint64_t>(part);
            }
          else
            not_num = 1;
        }
      VecRestoreArrayRead(w_vec, &wd);
      VecRestoreArrayRead(x_vec, &xd);
      MPI_Comm comm = MPI_COMM_NULL;
      PetscObjectGetComm(reinterpret_cast<PetscObject>(x_vec), &comm);
      int size = 1;
      MPI_Comm_size(comm, &size);
      const std::uint64_t mine[3] = {static_cast<std::uint64_t>(local >> 64),
                                     static_cast<std::uint64_t>(local),
                                     not_num};
      std::vector<std::uint64_t> all(3 * size);
      MPI_Allgather(mine, 3, MPI_UINT64_T, all.data(), 3, MPI_UINT64_T, comm);
      Sum global = 0;
      for (int r = 0; r < size; ++r)
        {
          if (all[3 * r + 2] != 0)
            return std::numeric_limits<double>::quiet_NaN();
          global += (static_cast<Sum>(all[3 * r]) << 64) + all[3 * r + 1];
        }
      return std::sqrt(static_cast<double>(global) / scale /
                       static_cast<double>(N_VGetLength(x)));
    }


    /// z = a x + b y on the local arrays, every entry by the same
    /// arithmetic wherever it lies (PETSc's VecAXPY is BLAS's daxpy, whose
    /// vector body and tail round differently: an entry's last bit then
    /// depended on its position in the rank's array, so on the partition).
    void
    linear_sum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z)
    {
      const Vec x_vec = N_VGetVector_Petsc(x), y_vec = N_VGetVector_Petsc(y),
                z_vec = N_VGetVector_Petsc(z);
      PetscInt n      = 0;
      VecGetLocalSize(z_vec, &n);
      const double *xd = nullptr, *yd = nullptr;
      double       *zd = nullptr;
      VecGetArray(z_vec, &zd); // first: z may be x or y
      x_vec == z_vec ? void(xd = zd) : void(VecGetArrayRead(x_vec, &xd));
      y_vec == z_vec ? void(yd = zd) : void(VecGetArrayRead(y_vec, &yd));
#pragma omp simd
      for (PetscInt i = 0; i < n; ++i)
        zd[i] = a * xd[i] + b * yd[i];
      if (y_vec != z_vec)
        VecRestoreArrayRead(y_vec, &yd);
      if (x_vec != z_vec)
        VecRestoreArrayRead(x_vec, &xd);
      VecRestoreArray(z_vec, &zd);
    }


    /// z = c x on the local arrays (as linear_sum()).
    void
    scale(realtype c, N_Vector x, N_Vector z)
    {
      const Vec x_vec = N_VGetVector_Petsc(x), z_vec = N_VGetVector_Petsc(z);
      PetscInt  n = 0;
      VecGetLocalSize(z_vec, &n);
      const double *xd = nullptr;
      double       *zd = nullptr;
      VecGetArray(z_vec, &zd);
      x_vec == z_vec ? void(xd = zd) : void(VecGetArrayRead(x_vec, &xd));
#pragma omp simd
      for (PetscInt i = 0; i < n; ++i)
        zd[i] = c * xd[i];
      if (x_vec != z_vec)
        VecRestoreArrayRead(x_vec, &xd);
      VecRestoreArray(z_vec, &zd);
    }


    /// A deal.II vector whose storage is an N_Vector's for its lifetime.
    class View
    {
    public:
      View(LA::MPI::Vector &view, N_Vector v)
        : view(static_cast<const Vec &>(view))
        , source(N_VGetVector_Petsc(v))
      {
        PetscErrorCode ierr = VecGetArray(source, &values);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
        ierr = VecPlaceArray(this->view, values);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      }
      ~View()
      {
        VecResetArray(view);
        VecRestoreArray(source, &values);
      }

    private:
      Vec     view, source;
      double *values = nullptr;
    };
  } // namespace


  struct ImexIntegrator::Impl
  {
    Impl(const Settings  &settings,
         const Callbacks &callbacks,
         const double     t0,
         const MPI_Comm   comm)
      : settings(settings)
      , callbacks(callbacks)
      , comm(comm)
      , t(t0)
    {
      check(SUNContext_Create(&this->comm, &context), "SUNContext_Create");
    }

    ~Impl()
    {
      free_memory();
      SUNContext_Free(&context);
    }

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

    bool
    has_implicit_part() const
    {
      return callbacks.implicit_rhs || callbacks.nonlinear_implicit_rhs;
    }

    /// The implicit part is J y (linear, time independent).
    bool
    linear_implicit_part() const
    {
      return static_cast<bool>(callbacks.implicit_rhs);
    }

    /// ARKStep's memory for the state @p y at time t, set up as configured.
    void
    start(LA::MPI::Vector &y);

    /// The implicit stages' solver: (I - gamma J) x = b by callbacks.solve.
    SUNLinearSolver
    create_linear_solver();

    /// Fixed step / stop time for the step to t_end.
    void
    configure() const;

    /// Add the counters of the current ARKStep memory to the totals, free it.
    void
    free_memory();

    /// ARKode's right-hand sides: f = f_E(t, y) (@p implicit false) and
    /// f = f_I(t, y).
    template <bool implicit>
    static int
    rhs(realtype time, N_Vector y, N_Vector f, void *data);
    static int
    solve(SUNLinearSolver solver, SUNMatrix, N_Vector x, N_Vector b, realtype);
    static int
    root_function(realtype time, N_Vector y, realtype *g, void *data);
    static SUNLinearSolver_Type
    solver_type(SUNLinearSolver)
    {
      return SUNLINEARSOLVER_MATRIX_EMBEDDED;
    }

    /// ARKode's error handler: keep the last message.
    static void
    error_handler(int         error_code,
                  const char *module,
                  const char *function,
                  char       *message,
                  void       *data);

    /// ARKStep's post-processing hook: calls callbacks.after_step.
    static int
    postprocess_step(realtype time, N_Vector y, void *data);

    /// ARKode's error weights (ARKEwtFn) w_i = 1/(rtol |y_i| + atol) of
    /// @p y, as ARKode's own scalar-tolerance weights (arkEwtSetSS), on
    /// PETSc's local arrays, with a clear error for a zero tolerance.
    static int
    error_weights(N_Vector y, N_Vector weights, void *data);

    /// ARKode's explicit stability function (ARKExpStabFn): the largest
    /// stable step beta / rho at @p y, or -1 (no bound) when rho = 0.
    static int
    explicit_stability(N_Vector y, realtype t, realtype *h_stable, void *data);

    Settings        settings;
    Callbacks       callbacks;
    MPI_Comm        comm;
    double          t;             ///< current time
    double          t_end     = 0; ///< end of the evolve() in progress
    SUNContext      context   = nullptr;
    void           *memory    = nullptr; ///< ARKStep's
    N_Vector        state     = nullptr; ///< the caller's state, wrapped
    Vec             state_vec = nullptr;
    SUNLinearSolver solver    = nullptr;
    /// Views of ARKode's vectors for the callbacks (same layout as the
    /// state); iterate_view: the Newton iterate of newton_solve.
    LA::MPI::Vector in_view, out_view, iterate_view;
    double          t_accepted = 0; ///< end of the last accepted step

    std::exception_ptr fatal, recoverable;
    std::string        arkode_message; ///< last ARKode error message

    unsigned long steps = 0, explicit_evaluations = 0, implicit_evaluations = 0;
    /// Error test and nonlinear solver failures before the last
    /// free_memory().
    unsigned long error_test_failures = 0, nonlinear_failures = 0;
    /// Steps set by the stability bound before the last free_memory().
    unsigned long stability_limited = 0;
    /// beta of the explicit table: of ARKode's default table of the order
    /// until the first step, then of the table in use.
    double beta                 = 0;
    bool   beta_of_table_in_use = false;
  };


  SUNLinearSolver
  ImexIntegrator::Impl::create_linear_solver()
  {
    SUNLinearSolver s = SUNLinSolNewEmpty(context);
    AssertThrow(s != nullptr, dealii::ExcMessage("SUNLinSolNewEmpty failed."));
    s->content      = this;
    s->ops->gettype = &solver_type;
    s->ops->solve   = &Impl::solve;
    return s;
  }


  void
  ImexIntegrator::Impl::start(LA::MPI::Vector &y)
  {
    state_vec = static_cast<const Vec &>(y);
    state     = N_VMake_Petsc(state_vec, context);
    AssertThrow(state != nullptr, dealii::ExcMessage("N_VMake_Petsc failed."));
    // Operations of our own, so that the steps do not depend on the
    // partition (ARKode's clones copy them).
    state->ops->nvwrmsnorm  = &weighted_rms_norm;
    state->ops->nvlinearsum = &linear_sum;
    state->ops->nvscale     = &scale;
    in_view.reinit(y);
    out_view.reinit(y);
    iterate_view.reinit(y);
    memory = ARKStepCreate(callbacks.explicit_rhs ? &rhs<false> : nullptr,
                           has_implicit_part() ? &rhs<true> : nullptr,
                           t,
                           state,
                           context);
    AssertThrow(memory != nullptr, dealii::ExcMessage("ARKStepCreate failed."));
    t_accepted = t;
    check(ARKStepSetUserData(memory, this), "ARKStepSetUserData");
    check(ARKStepSetErrHandlerFn(memory, &error_handler, this),
          "ARKStepSetErrHandlerFn");
    check(ARKStepWFtolerances(memory, &error_weights), "ARKStepWFtolerances");
    check(ARKStepSetMinStep(memory, settings.min_step), "ARKStepSetMinStep");
    check(ARKStepSetOrder(memory, settings.order), "ARKStepSetOrder");
    if (has_implicit_part())
      {
        solver = create_linear_solver();
        check(ARKStepSetLinearSolver(memory, solver, nullptr),
              "ARKStepSetLinearSolver");
        // Linear and time independent: one Newton iteration per stage, one
        // solve; no Jacobian (the solver knows J). Nonlinear: Newton's
        // method, the Jacobian of every iterate in newton_solve.
        if (linear_implicit_part())
          check(ARKStepSetLinear(memory, 0), "ARKStepSetLinear");
        check(ARKStepSetMaxNonlinIters(memory, linear_implicit_part() ? 3 : 5),
              "ARKStepSetMaxNonlinIters");
      }
    else if (callbacks.explicit_rhs)
      // The explicit table of the ARK method alone: the same method with J
      // = 0, without implicit stages.
      check(ARKStepSetTableNum(memory,
                               ARKODE_DIRK_NONE,
                               static_cast<ARKODE_ERKTableID>(
                                 explicit_table_of_order(settings.order))),
            "ARKStepSetTableNum");
    if (callbacks.after_step)
      check(ARKStepSetPostprocessStepFn(memory, &postprocess_step),
            "ARKStepSetPostprocessStepFn");
    if (callbacks.n_roots > 0)
      {
        check(ARKStepRootInit(memory, callbacks.n_roots, &root_function),
              "ARKStepRootInit");
        check(ARKStepSetNoInactiveRootWarn(memory),
              "ARKStepSetNoInactiveRootWarn");
      }
    double initial_step =
      settings.initial_step > 0 ? settings.initial_step : settings.max_step;
    if (callbacks.explicit_stiffness && settings.adaptive)
      {
        check(ARKStepSetStabilityFn(memory, &explicit_stability, this),
              "ARKStepSetStabilityFn");
        check(ARKStepSetCFLFraction(memory, stability_fraction),
              "ARKStepSetCFLFraction");
        // ARKode's initial step is not subject to the stability function:
        // keep it within the bound too.
        const double rho = callbacks.explicit_stiffness(y);
        if (rho > 0)
          initial_step =
            std::min(initial_step, stability_fraction * beta / rho);
      }
    check(ARKStepSetInitStep(memory, initial_step), "ARKStepSetInitStep");
  }


  void
  ImexIntegrator::Impl::configure() const
  {
    check(ARKStepSetMaxNumSteps(memory, settings.max_steps),
          "ARKStepSetMaxNumSteps");
    if (settings.adaptive)
      check(ARKStepSetMaxStep(memory, settings.max_step), "ARKStepSetMaxStep");
    else
      check(ARKStepSetFixedStep(memory, t_end - t), "ARKStepSetFixedStep");
    check(ARKStepSetStopTime(memory, t_end), "ARKStepSetStopTime");
    if (linear_implicit_part())
      check(ARKStepSetDeduceImplicitRhs(memory,
                                        settings.deduce_implicit_rhs
                                          ? SUNTRUE
                                          : SUNFALSE),
            "ARKStepSetDeduceImplicitRhs");
  }


  void
  ImexIntegrator::Impl::free_memory()
  {
    if (memory != nullptr)
      {
        long int n = 0;
        if (ARKStepGetNumSteps(memory, &n) >= 0)
          steps += n;
        if (callbacks.explicit_stiffness && settings.adaptive &&
            ARKStepGetNumExpSteps(memory, &n) >= 0)
          stability_limited += n;
        if (ARKStepGetNumErrTestFails(memory, &n) >= 0)
          error_test_failures += n;
        if (has_implicit_part() &&
            ARKStepGetNumNonlinSolvConvFails(memory, &n) >= 0)
          nonlinear_failures += n;
        ARKStepFree(&memory);
      }
    if (state != nullptr)
      N_VDestroy(state); // not the caller's Vec (N_VMake_Petsc)
    if (solver != nullptr)
      SUNLinSolFreeEmpty(solver);
    memory = nullptr;
    state  = nullptr;
    solver = nullptr;
  }


  template <bool implicit>
  int
  ImexIntegrator::Impl::rhs(const realtype time,
                            N_Vector       y,
                            N_Vector       f,
                            void          *data)
  {
    Impl &self = *static_cast<Impl *>(data);
    return self.guarded([&]() {
      const View in(self.in_view, y), out(self.out_view, f);
      if (!implicit)
        {
          self.callbacks.explicit_rhs(time, self.in_view, self.out_view);
          ++self.explicit_evaluations;
          return;
        }
      if (self.linear_implicit_part())
        self.callbacks.implicit_rhs(self.in_view, self.out_view);
      else
        self.callbacks.nonlinear_implicit_rhs(time,
                                              self.in_view,
                                              self.out_view);
      ++self.implicit_evaluations;
    });
  }


  int
  ImexIntegrator::Impl::solve(SUNLinearSolver solver,
                              SUNMatrix,
                              N_Vector x,
                              N_Vector b,
                              realtype)
  {
    Impl &self = *static_cast<Impl *>(solver->content);
    return self.guarded(
      [&]() {
        double gamma = 0;
        check(ARKStepGetCurrentGamma(self.memory, &gamma),
              "ARKStepGetCurrentGamma");
        const View in(self.in_view, b), out(self.out_view, x);
        if (self.linear_implicit_part())
          {
            self.callbacks.solve(gamma, self.in_view, self.out_view);
            return;
          }
        // The Newton iterate: ARKode's ycur, where the stage residual was
        // just evaluated.
        realtype time = 0, nonlinear_gamma = 0;
        N_Vector predicted = nullptr, iterate = nullptr, f_i = nullptr,
                 stage_data = nullptr;
        void *user_data     = nullptr;
        check(ARKStepGetNonlinearSystemData(self.memory,
                                            &time,
                                            &predicted,
                                            &iterate,
                                            &f_i,
                                            &nonlinear_gamma,
                                            &stage_data,
                                            &user_data),
              "ARKStepGetNonlinearSystemData");
        const View z(self.iterate_view, iterate);
        self.callbacks.newton_solve(time,
                                    self.iterate_view,
                                    gamma,
                                    self.in_view,
                                    self.out_view);
      },
      // ARKode's linear solver interface knows SUNLS_* codes only.
      SUNLS_CONV_FAIL);
  }


  int
  ImexIntegrator::Impl::root_function(const realtype time,
                                      N_Vector       y,
                                      realtype      *g,
                                      void          *data)
  {
    Impl &self = *static_cast<Impl *>(data);
    return self.guarded([&]() {
      const View          in(self.in_view, y);
      std::vector<double> values(self.callbacks.n_roots);
      self.callbacks.roots(time, self.in_view, values);
      AssertThrow(values.size() == self.callbacks.n_roots,
                  dealii::ExcMessage("ImexIntegrator: the root callback "
                                     "returned the wrong number of values."));
      std::copy(values.begin(), values.end(), g);
    });
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
                                         void          *data)
  {
    Impl &self = *static_cast<Impl *>(data);
    return self.guarded([&]() {
      const View view(self.in_view, y);
      self.callbacks.after_step(time, time - self.t_accepted, self.in_view);
      self.t_accepted = time;
    });
  }


  int
  ImexIntegrator::Impl::error_weights(N_Vector y, N_Vector weights, void *data)
  {
    Impl &self = *static_cast<Impl *>(data);
    return self.guarded([&]() {
      const Vec      y_vec = N_VGetVector_Petsc(y);
      const Vec      w_vec = N_VGetVector_Petsc(weights);
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
      const double               rtol  = self.settings.relative_tolerance;
      const std::vector<double> &atols = self.settings.absolute_tolerances;
      AssertThrow(atols.empty() || atols.size() == std::size_t(n),
                  dealii::ExcMessage("ImexIntegrator: the absolute "
                                     "tolerances do not match the state."));
      bool positive = true;
      for (PetscInt i = 0; i < n; ++i)
        {
          const double atol =
            atols.empty() ? self.settings.absolute_tolerance : atols[i];
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
          check(ARKStepGetCurrentButcherTables(self.memory,
                                               &implicit_table,
                                               &explicit_table),
                "ARKStepGetCurrentButcherTables");
          self.beta                 = real_stability_interval(explicit_table);
          self.beta_of_table_in_use = true;
        }
      const View   view(self.in_view, y);
      const double rho = self.callbacks.explicit_stiffness(self.in_view);
      *h_stable        = rho > 0 ? self.beta / rho : -1.0;
    });
  }


  ImexIntegrator::ImexIntegrator(const Settings  &settings,
                                 const Callbacks &callbacks,
                                 const double     t0,
                                 const MPI_Comm   comm)
    : impl(std::make_unique<Impl>(settings, callbacks, t0, comm))
  {
    AssertThrow(settings.order >= (callbacks.explicit_rhs ? 3u : 2u) &&
                  settings.order <= 5,
                dealii::ExcMessage("ARKode order must be 3, 4 or 5 (2 to 5 "
                                   "without an explicit part)."));
    AssertThrow(!callbacks.implicit_rhs || callbacks.solve,
                dealii::ExcMessage("ImexIntegrator: an implicit part needs "
                                   "its solve callback."));
    AssertThrow(!callbacks.nonlinear_implicit_rhs ||
                  (callbacks.newton_solve && !callbacks.implicit_rhs),
                dealii::ExcMessage("ImexIntegrator: a nonlinear implicit "
                                   "part needs its newton_solve callback "
                                   "(and no linear implicit_rhs)."));
    AssertThrow(callbacks.explicit_rhs || impl->has_implicit_part(),
                dealii::ExcMessage("ImexIntegrator: nothing to integrate "
                                   "(no right-hand side)."));
    AssertThrow(callbacks.n_roots == 0 ||
                  (callbacks.roots && callbacks.at_root),
                dealii::ExcMessage("ImexIntegrator: root functions need the "
                                   "roots and at_root callbacks."));
    if (callbacks.explicit_stiffness && settings.adaptive)
      {
        // ARKStep's default explicit table of the order, for the first step
        // (its stability function takes the table in use after it).
        ARKodeButcherTable table =
          ARKodeButcherTable_LoadERK(static_cast<ARKODE_ERKTableID>(
            explicit_table_of_order(settings.order)));
        impl->beta = real_stability_interval(table);
        ARKodeButcherTable_Free(table);
      }
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
    if (m.memory == nullptr)
      m.start(y);
    AssertThrow(static_cast<const Vec &>(y) == m.state_vec,
                dealii::ExcMessage("ImexIntegrator::evolve: the state is not "
                                   "the vector of the first evolve(); call "
                                   "reset() first."));
    m.configure();
    m.fatal       = nullptr;
    m.recoverable = nullptr;
    m.arkode_message.clear();
    realtype reached = m.t;
    int      flag    = ARK_ROOT_RETURN;
    while (flag == ARK_ROOT_RETURN)
      {
        flag = ARKStepEvolve(m.memory, t_end, m.state, &reached, ARK_NORMAL);
        if (m.fatal)
          std::rethrow_exception(m.fatal);
        if (flag == ARK_ROOT_RETURN)
          {
            // y is the state at the root; the next ARKStepEvolve goes on
            // from there.
            std::vector<int> found(m.callbacks.n_roots, 0);
            check(ARKStepGetRootInfo(m.memory, found.data()),
                  "ARKStepGetRootInfo");
            m.callbacks.at_root(reached, y, found);
          }
      }
    // A recoverable failure that ARKode cured by a smaller step is no error.
    if (flag < 0 ||
        std::abs(reached - t_end) > 1e-12 * std::max(1.0, std::abs(t_end)))
      {
        if (m.recoverable)
          std::rethrow_exception(m.recoverable);
        AssertThrow(false,
                    dealii::ExcMessage(
                      "ARKode stopped at t = " + std::to_string(reached) +
                      " ms: " + m.arkode_message));
      }
    m.t = t_end;
  }


  void
  ImexIntegrator::reset(const double t)
  {
    impl->free_memory();
    impl->t = t;
  }


  double
  ImexIntegrator::time() const
  {
    return impl->t;
  }


  unsigned long
  ImexIntegrator::n_steps() const
  {
    return total(impl->memory,
                 &ARKStepGetNumSteps,
                 "ARKStepGetNumSteps",
                 impl->steps);
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
  ImexIntegrator::n_error_test_failures() const
  {
    return total(impl->memory,
                 &ARKStepGetNumErrTestFails,
                 "ARKStepGetNumErrTestFails",
                 impl->error_test_failures);
  }


  unsigned long
  ImexIntegrator::n_nonlinear_convergence_failures() const
  {
    return total(impl->has_implicit_part() ? impl->memory : nullptr,
                 &ARKStepGetNumNonlinSolvConvFails,
                 "ARKStepGetNumNonlinSolvConvFails",
                 impl->nonlinear_failures);
  }


  unsigned long
  ImexIntegrator::n_stability_limited_steps() const
  {
    const bool limited =
      impl->callbacks.explicit_stiffness && impl->settings.adaptive;
    return total(limited ? impl->memory : nullptr,
                 &ARKStepGetNumExpSteps,
                 "ARKStepGetNumExpSteps",
                 impl->stability_limited);
  }


  double
  ImexIntegrator::explicit_stability_interval() const
  {
    return impl->beta;
  }
} // namespace systole::Electrophysiology
