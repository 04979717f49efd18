#pragma once

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include "base/linear_algebra.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace systole::Electrophysiology
{
  /// A failure inside an ODE callback that a smaller step may cure (a linear
  /// solver that did not converge). Throw it from an ImexIntegrator callback;
  /// with adaptive steps ARKode then retries with a smaller step, with fixed
  /// steps evolve() rethrows it.
  DeclException1(ExcRecoverableStepFailure,
                 std::string,
                 << "Recoverable failure in an ODE step: " << arg1);

  /// The project's ARKode adapter: additive Runge-Kutta integration of
  /// @f[ \frac{dy}{dt} = f_E(t, y) + f_I(t, y) @f]
  /// with SUNDIALS ARKode (ARKStep) through its C interface, on SUNDIALS'
  /// PETSc N_Vector. Its uses:
  /// - IMEX (the electrophysiology): f_E explicit, f_I = J y linear and
  ///   time independent (ARKode is told so: one Newton iteration per stage,
  ///   no Jacobian), or no implicit part at all (the explicit table alone).
  ///   The stage systems (I - gamma J) x = b are solved by the caller's
  ///   solve(), which gets ARKode's current gamma (a matrix-embedded
  ///   SUNLinearSolver).
  /// - Implicit (the 0D circulation, Circulation::Integrator): no f_E, a
  ///   nonlinear f_I(t, y) whose stages Newton's method solves (at most 5
  ///   iterations) with the caller's newton_solve(), which gets the Newton
  ///   iterate and gamma; per-entry absolute tolerances; ARKode's root
  ///   finding on functions g(t, y), each root reported with its state.
  ///
  /// This is the only file that knows ARKode: the callbacks here are plain
  /// functions on deal.II's PETSc vectors that throw;
  /// ExcRecoverableStepFailure maps to SUNDIALS' recoverable codes, any
  /// other exception to -1 and is rethrown by evolve() once ARKode returns.
  /// Not deal.II 9.4's SUNDIALS::ARKode wrapper: its N_Vector of PETSc
  /// vectors copies the vector in every weighted RMS norm (two reductions
  /// each) and was most of a reaction-eikonal step on 2 ranks.
  class ImexIntegrator
  {
  public:
    struct Settings
    {
      /// Order of the ARK method, 3 to 5 (2 to 5 without an explicit part:
      /// ARKode's default DIRK table of the order).
      unsigned int order              = 3;
      bool         adaptive           = false; ///< adaptive steps (else fixed)
      double       relative_tolerance = 1e-4;  ///< adaptive steps [-]
      double       absolute_tolerance = 1e-5;  ///< adaptive steps
      double       max_step           = 0.1;   ///< adaptive steps [ms]
      /// ARKode deduces f_I at the end of an implicit stage from the stage
      /// solve, (z - a)/(h A_ii), instead of calling implicit_rhs again (the
      /// solve's tolerance then bounds the error of f_I): for an implicit
      /// part that costs a solve itself (a consistent mass).
      bool deduce_implicit_rhs = false;
      /// The first step of adaptive steps [ms] (0: max_step); the explicit
      /// stability bound caps it.
      double initial_step = 0.0;
      /// The smallest step ARKode may take [ms] (ARKStepSetMinStep).
      double min_step = 1e-10;
      /// The most steps of one evolve() (ARKStepSetMaxNumSteps).
      long max_steps = 100000;
      /// Adaptive steps: the absolute tolerance of every locally owned
      /// entry of the state, instead of absolute_tolerance (empty: that one
      /// for all).
      std::vector<double> absolute_tolerances;

      /// The defaults with order, adaptive, the two tolerances and max_step
      /// from a caller's parameters @p p (members order, adaptive,
      /// relative_tolerance, absolute_tolerance and time_step, the largest
      /// step).
      template <class StepParameters>
      static Settings
      of(const StepParameters &p)
      {
        Settings s;
        s.order              = p.order;
        s.adaptive           = p.adaptive;
        s.relative_tolerance = p.relative_tolerance;
        s.absolute_tolerance = p.absolute_tolerance;
        s.max_step           = p.time_step;
        return s;
      }
    };

    struct Callbacks
    {
      /// f = f_E(t, y).
      std::function<
        void(const double t, const LA::MPI::Vector &y, LA::MPI::Vector &f)>
        explicit_rhs;
      /// f = J y. Empty: no implicit part (J = 0; then solve is unused). The
      /// explicit table of the ARK method of the order then runs alone: the
      /// same method and error estimate, without the implicit stages (their
      /// right-hand sides, solves and norms).
      std::function<void(const LA::MPI::Vector &y, LA::MPI::Vector &f)>
        implicit_rhs;
      /// x = (I - gamma J)^-1 b to the caller's own tolerance.
      std::function<
        void(const double gamma, const LA::MPI::Vector &b, LA::MPI::Vector &x)>
        solve;
      /// Optional: called after every accepted step, from t - h to @p t, with
      /// the new state @p y, which it may change (a split step: the
      /// Rush-Larsen update of the gates). ARKode then evaluates the right
      /// hand sides afresh at the changed state (ARKStep's post-processing
      /// hook, ARKStepSetPostprocessStepFn). Must not fail.
      std::function<void(const double t, const double h, LA::MPI::Vector &y)>
        after_step;
      /// Optional, adaptive steps: the stiffness rho [1/ms] of the explicit
      /// part at @p y, the largest -lambda over the negative real
      /// eigenvalues lambda of its Jacobian (0 if none). Collective. Every
      /// step is then kept within the explicit method's stability interval
      /// on the negative real axis, h <= stability_fraction * beta / rho
      /// (ARKode's explicit stability function, and the initial step after
      /// construction or reset()): the error estimate alone
      /// does not keep it there when a few components are stiffer than the
      /// rest, since its RMS norm over all components dilutes an instability
      /// that is local to them (docs/architecture.md, Electrophysiology).
      std::function<double(const LA::MPI::Vector &y)> explicit_stiffness;

      /// A nonlinear implicit part f = f_I(t, y), instead of implicit_rhs
      /// (set one at most; explicit_rhs may then be empty: a DIRK method).
      /// Its stages are solved by Newton's method with newton_solve.
      std::function<
        void(const double t, const LA::MPI::Vector &y, LA::MPI::Vector &f)>
        nonlinear_implicit_rhs;
      /// x = (I - gamma J)^-1 b exactly, J = df_I/dy at the Newton iterate
      /// (@p t, @p y): called at every Newton iteration, so the Jacobian is
      /// always that of the iterate.
      std::function<void(const double           t,
                         const LA::MPI::Vector &y,
                         const double           gamma,
                         const LA::MPI::Vector &b,
                         LA::MPI::Vector       &x)>
        newton_solve;

      /// Optional: the number of root functions g_i(t, y) and g = their
      /// values; ARKode locates their sign changes (both directions) within
      /// the steps.
      unsigned int n_roots = 0;
      std::function<
        void(const double t, const LA::MPI::Vector &y, std::vector<double> &g)>
        roots;
      /// Called at every located root (a time inside evolve()'s interval)
      /// with the state there and, per root function, +1 (g rises through
      /// 0), -1 (falls) or 0; evolve() then goes on to its end time.
      std::function<void(const double            t,
                         const LA::MPI::Vector  &y,
                         const std::vector<int> &found)>
        at_root;
    };

    /// Fraction of the explicit stability bound beta / rho that a step may
    /// take (ARKStepSetCFLFraction).
    static constexpr double stability_fraction = 0.9;

    /// @param[in] t0 initial time [ms]
    ImexIntegrator(const Settings  &settings,
                   const Callbacks &callbacks,
                   const double     t0,
                   const MPI_Comm   comm);
    ~ImexIntegrator();

    /// Advance @p y (the state at the current time on entry; the caller must
    /// not change it between calls unless it calls reset()) to @p t_end.
    /// Fixed steps: one step of t_end - t. Adaptive: as many steps as the
    /// tolerances need, none beyond t_end (ARKode's stop time).
    void
    evolve(LA::MPI::Vector &y, const double t_end);

    /// Restart at time @p t from @p y at the next evolve() (after the
    /// caller restored a saved state).
    void
    reset(const double t);

    /// Current time [ms].
    double
    time() const;

    /// ARKode steps taken since construction (over resets).
    unsigned long
    n_steps() const;

    /// Explicit and implicit right-hand side evaluations since construction.
    unsigned long
    n_explicit_evaluations() const;
    unsigned long
    n_implicit_evaluations() const;

    /// Steps rejected by the error test, and nonlinear solves that did not
    /// converge, since construction (over resets).
    unsigned long
    n_error_test_failures() const;
    unsigned long
    n_nonlinear_convergence_failures() const;

    /// Steps whose size the explicit stability bound set (rather than the
    /// error estimate) since construction (over resets); 0 without
    /// Callbacks::explicit_stiffness.
    unsigned long
    n_stability_limited_steps() const;

    /// beta of the explicit method: [-beta, 0] is the interval of the
    /// negative real axis within its stability region, |R(z)| <= 1 (of the
    /// table in use once ARKode has stepped, of ARKStep's default table of
    /// the order before; 0 without Callbacks::explicit_stiffness).
    double
    explicit_stability_interval() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Electrophysiology
