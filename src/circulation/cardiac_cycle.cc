#include "circulation/cardiac_cycle.h"

#include <deal.II/base/exceptions.h>

#include "base/errors.h"
#include "base/units.h"

#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <sstream>
#include <string>

namespace systole::Circulation
{
  namespace
  {
    /// Components of the ODE state.
    enum Component : unsigned int
    {
      volume_component            = 0, ///< V [mm^3]
      arterial_pressure_component = 1, ///< p_ar [kPa]
      aortic_outflow_component    = 2, ///< int Q_ao dt [mm^3]
      mitral_inflow_component     = 3, ///< int Q_mv dt [mm^3]
      n_components                = 4
    };

    /// Accepted steps after a step cut before the maximum step is restored.
    constexpr unsigned int n_steps_before_restoring_max_step = 5;

    std::string
    str(const double x)
    {
      std::ostringstream s;
      s.precision(10);
      s << x;
      return s.str();
    }

    const Parameters &
    validated(const Parameters &parameters)
    {
      parameters.validate();
      return parameters;
    }

    std::string
    flag_name(const int flag)
    {
      char             *name = ERKStepGetReturnFlagName(flag);
      const std::string result(name != nullptr ? name : "unknown");
      std::free(name);
      return result;
    }
  } // namespace

  struct CardiacCycle::Impl
  {
    Impl(const Parameters &parameters,
         Ventricle        &ventricle,
         const double      initial_volume,
         const double      contraction_onset);
    ~Impl();

    Statistics
    run(Observer &observer);

    // ARKode callbacks; `data` is the Impl. They never let an exception
    // through the C code: recoverable ventricle failures set
    // recoverable_failure and return 1, anything else is stored in
    // fatal_error and returns -1.
    static int
    rhs_callback(realtype t, N_Vector y, N_Vector ydot, void *data);
    static int
    root_callback(realtype t, N_Vector y, realtype *g, void *data);
    static void
    error_handler(int         code,
                  const char *module,
                  const char *function,
                  char       *message,
                  void       *data);
    template <class F>
    int
    guarded(const F &f) noexcept;

    /// P(t, V) from the ventricle, or from the cache of recent evaluations.
    double
    pressure(const double t, const double volume);
    double
    mitral_inflow(const double p) const;
    double
    aortic_outflow(const double p, const double p_ar) const;
    void
    rhs(const double t, const double *y, double *ydot);
    void
    roots(const double t, const double *y, double *g);
    unsigned int
    n_roots() const;

    /// Accept the state (t, y) reached by a step of length h.
    void
    accept(const double h, Observer &observer);
    void
    transition(const Phase to, Observer &observer);
    /// The contraction onset of the current beat is reached.
    void
    arm(Observer &observer);
    /// Restart the integrator at (t, y) with the root functions of the
    /// current phase, up to the next stop time.
    void
    start_segment(const bool reset_step_size);
    /// tstop reached; returns true when the run is complete.
    bool
    reach_stop(Observer &observer);
    bool
    finish_beat(Observer &observer);
    void
    handle_failure(const int flag);
    void
    check(const int flag, const char *call) const;
    /// Create the SUNDIALS context, vectors and ERKStep memory.
    void
    setup_integrator();
    void
    free_integrator();

    const Parameters params;
    const Windkessel windkessel;
    Ventricle       &ventricle;
    const double     initial_volume;
    const double     contraction_onset;
    /// Stop times closer than this to t are taken as reached [ms].
    const double time_tolerance;

    SUNContext context = nullptr;
    N_Vector   y       = nullptr; ///< last accepted state
    N_Vector   y_out   = nullptr; ///< output of ERKStepEvolve
    N_Vector   abstol  = nullptr;
    void      *arkode  = nullptr;

    // Cycle state.
    double       t     = 0;
    Phase        phase = Phase::filling;
    unsigned int beat  = 0;
    /// The contraction onset of the current beat has been reached.
    bool onset_passed = false;
    /// The mitral closure (filling -> isovolumetric contraction) is armed.
    bool          armed            = false;
    double        tstop            = 0;
    bool          stop_is_beat_end = true;
    StepRecord    last_record;
    BeatRecorder  recorder{0, 0.0, nullptr};
    double        previous_edv = std::numeric_limits<double>::quiet_NaN();
    unsigned long calls_at_beat_start = 0;
    unsigned int  cuts_in_beat        = 0;
    bool          has_run             = false;

    // Step cutting after ventricle failures.
    double       max_step;
    unsigned int consecutive_cuts = 0;
    bool         step_cut_active  = false;
    unsigned int steps_since_cut  = 0;

    // Cache of recent ventricle evaluations.
    struct Evaluation
    {
      double t, volume, pressure;
    };
    std::array<Evaluation, 16> cache;
    unsigned int               cache_size = 0;
    unsigned int               cache_next = 0;

    // Errors raised inside callbacks.
    std::exception_ptr fatal_error;
    bool               recoverable_failure = false;
    std::string        recoverable_message;
    std::string        arkode_message;

    Statistics stats;
  };

  CardiacCycle::Impl::Impl(const Parameters &parameters,
                           Ventricle        &ventricle,
                           const double      initial_volume,
                           const double      contraction_onset)
    : params(validated(parameters))
    , windkessel(parameters.windkessel)
    , ventricle(ventricle)
    , initial_volume(initial_volume)
    , contraction_onset(contraction_onset)
    , time_tolerance(1e-12 * parameters.period)
    , max_step(parameters.max_time_step)
  {
    AssertThrow(initial_volume > 0,
                dealii::ExcMessage("CardiacCycle: the initial volume (" +
                                   str(initial_volume) +
                                   " mm^3) must be positive."));
    AssertThrow(contraction_onset >= 0 && contraction_onset < params.period,
                dealii::ExcMessage(
                  "CardiacCycle: the contraction onset (" +
                  str(contraction_onset) +
                  " ms) must lie within the beat, [0, Circulation / Period)."));

    try
      {
        setup_integrator();
      }
    catch (...)
      {
        free_integrator();
        throw;
      }
  }

  CardiacCycle::Impl::~Impl()
  {
    free_integrator();
  }

  void
  CardiacCycle::Impl::setup_integrator()
  {
    // A context without a communicator: every rank integrates the same
    // small system on its own.
    check(SUNContext_Create(nullptr, &context), "SUNContext_Create");
    y      = N_VNew_Serial(n_components, context);
    y_out  = N_VNew_Serial(n_components, context);
    abstol = N_VNew_Serial(n_components, context);
    AssertThrow(y != nullptr && y_out != nullptr && abstol != nullptr,
                dealii::ExcMessage("CardiacCycle: N_VNew_Serial failed."));
    double *const y0                = NV_DATA_S(y);
    y0[volume_component]            = initial_volume;
    y0[arterial_pressure_component] = params.initial_arterial_pressure;
    y0[aortic_outflow_component]    = 0;
    y0[mitral_inflow_component]     = 0;

    arkode = ERKStepCreate(&rhs_callback, 0.0, y, context);
    AssertThrow(arkode != nullptr,
                dealii::ExcMessage("CardiacCycle: ERKStepCreate failed."));
    check(ERKStepSetUserData(arkode, this), "ERKStepSetUserData");
    check(ERKStepSetErrHandlerFn(arkode, &error_handler, this),
          "ERKStepSetErrHandlerFn");
    check(ERKStepSetTableNum(arkode, ARKODE_BOGACKI_SHAMPINE_4_2_3),
          "ERKStepSetTableNum");
    // Volumes share one absolute tolerance; p_ar gets the pressure that
    // this volume would add to the compliance.
    double *const atol     = NV_DATA_S(abstol);
    atol[volume_component] = params.absolute_volume_tolerance;
    atol[arterial_pressure_component] =
      params.absolute_volume_tolerance / params.windkessel.compliance;
    atol[aortic_outflow_component] = params.absolute_volume_tolerance;
    atol[mitral_inflow_component]  = params.absolute_volume_tolerance;
    check(ERKStepSVtolerances(arkode, params.relative_tolerance, abstol),
          "ERKStepSVtolerances");
    check(ERKStepSetMaxStep(arkode, max_step), "ERKStepSetMaxStep");
  }

  void
  CardiacCycle::Impl::free_integrator()
  {
    // All of these accept null pointers.
    ERKStepFree(&arkode);
    N_VDestroy(abstol);
    N_VDestroy(y_out);
    N_VDestroy(y);
    SUNContext_Free(&context);
    abstol = y_out = y = nullptr;
  }

  void
  CardiacCycle::Impl::check(const int flag, const char *call) const
  {
    AssertThrow(flag >= 0,
                dealii::ExcMessage(std::string("CardiacCycle: ") + call +
                                   " failed (" + flag_name(flag) + ")" +
                                   (arkode_message.empty()
                                      ? std::string()
                                      : ": " + arkode_message)));
  }

  // ---------------------------------------------------------------------
  // Callbacks

  template <class F>
  int
  CardiacCycle::Impl::guarded(const F &f) noexcept
  {
    try
      {
        f();
        return 0;
      }
    catch (const ExcNewtonDidNotConverge &e)
      {
        recoverable_failure = true;
        recoverable_message = one_line_message(e);
        return 1;
      }
    catch (const ExcInvertedElement &e)
      {
        recoverable_failure = true;
        recoverable_message = one_line_message(e);
        return 1;
      }
    catch (...)
      {
        fatal_error = std::current_exception();
        return -1;
      }
  }

  int
  CardiacCycle::Impl::rhs_callback(realtype t,
                                   N_Vector y,
                                   N_Vector ydot,
                                   void    *data)
  {
    auto &self = *static_cast<Impl *>(data);
    return self.guarded([&]() { self.rhs(t, NV_DATA_S(y), NV_DATA_S(ydot)); });
  }

  int
  CardiacCycle::Impl::root_callback(realtype  t,
                                    N_Vector  y,
                                    realtype *g,
                                    void     *data)
  {
    auto &self = *static_cast<Impl *>(data);
    return self.guarded([&]() { self.roots(t, NV_DATA_S(y), g); });
  }

  void
  CardiacCycle::Impl::error_handler(int         code,
                                    const char *module,
                                    const char *function,
                                    char       *message,
                                    void       *data)
  {
    // Keep ARKode's messages out of the console (every rank would print
    // them); errors are reported through the exception of run().
    (void)module;
    if (code < 0)
      static_cast<Impl *>(data)->arkode_message =
        std::string(function) + ": " + message;
  }

  // ---------------------------------------------------------------------
  // The ODE system

  double
  CardiacCycle::Impl::pressure(const double t, const double volume)
  {
    for (unsigned int i = 0; i < cache_size; ++i)
      if (cache[i].t == t && cache[i].volume == volume)
        return cache[i].pressure;
    const double p = ventricle.pressure(t, volume);
    ++stats.n_ventricle_calls;
    AssertThrow(std::isfinite(p),
                dealii::ExcMessage("The ventricle returned the pressure " +
                                   str(p) + " kPa at t = " + str(t) +
                                   " ms, V = " + str(volume) + " mm^3."));
    cache[cache_next] = {t, volume, p};
    cache_next        = (cache_next + 1) % cache.size();
    cache_size        = std::min<unsigned int>(cache_size + 1, cache.size());
    return p;
  }

  double
  CardiacCycle::Impl::mitral_inflow(const double p) const
  {
    return phase == Phase::filling
             ? (params.atrial_pressure - p) / params.mitral_valve_resistance
             : 0.0;
  }

  double
  CardiacCycle::Impl::aortic_outflow(const double p, const double p_ar) const
  {
    return phase == Phase::ejection ? windkessel.outflow(p, p_ar) : 0.0;
  }

  void
  CardiacCycle::Impl::rhs(const double t, const double *y, double *ydot)
  {
    const double p_ar = y[arterial_pressure_component];
    const double p    = pressure(t, y[volume_component]);
    const double q_mv = mitral_inflow(p);
    const double q_ao = aortic_outflow(p, p_ar);
    // Both flows are exactly 0 in the isovolumetric phases, so V stays
    // exactly constant there.
    ydot[volume_component]            = q_mv - q_ao;
    ydot[arterial_pressure_component] = windkessel.pressure_rate(p_ar, q_ao);
    ydot[aortic_outflow_component]    = q_ao;
    ydot[mitral_inflow_component]     = q_mv;
  }

  unsigned int
  CardiacCycle::Impl::n_roots() const
  {
    switch (phase)
      {
        case Phase::filling:
          return armed ? 1 : 0;
        case Phase::isovolumetric_contraction:
          return 2;
        case Phase::ejection:
        case Phase::isovolumetric_relaxation:
          return 1;
      }
    return 0;
  }

  void
  CardiacCycle::Impl::roots(const double t, const double *y, double *g)
  {
    const double p    = pressure(t, y[volume_component]);
    const double p_ar = y[arterial_pressure_component];
    switch (phase)
      {
        case Phase::filling: // upwards: the mitral valve closes
          g[0] = p - params.atrial_pressure;
          break;
        case Phase::isovolumetric_contraction:
          g[0] = p - p_ar;                   // upwards: aortic valve opens
          g[1] = p - params.atrial_pressure; // downwards: mitral reopens
          break;
        case Phase::ejection: // downwards: Q_ao = (p - p_ar) / R_s < 0
          g[0] = p - p_ar;
          break;
        case Phase::isovolumetric_relaxation: // downwards: mitral opens
          g[0] = p - params.atrial_pressure;
          break;
      }
  }

  // ---------------------------------------------------------------------
  // The cycle

  void
  CardiacCycle::Impl::accept(const double h, Observer &observer)
  {
    const double *const state = NV_DATA_S(y);
    StepRecord          r;
    r.time              = t;
    r.beat              = beat;
    r.phase             = phase;
    r.volume            = state[volume_component];
    r.arterial_pressure = state[arterial_pressure_component];
    r.pressure          = pressure(t, r.volume);
    r.aortic_outflow    = aortic_outflow(r.pressure, r.arterial_pressure);
    r.mitral_inflow     = mitral_inflow(r.pressure);
    r.flow              = r.aortic_outflow - r.mitral_inflow;
    r.aortic_pressure =
      windkessel.root_pressure(r.arterial_pressure, r.aortic_outflow);
    r.step_size                 = h;
    r.cumulative_aortic_outflow = state[aortic_outflow_component];
    r.cumulative_mitral_inflow  = state[mitral_inflow_component];
    last_record                 = r;

    ventricle.accept_step(t, r.volume);
    recorder.add_step(r);
    if (h > 0)
      ++stats.n_steps;
    observer.on_step(r);
  }

  void
  CardiacCycle::Impl::transition(const Phase to, Observer &observer)
  {
    Transition event;
    event.time              = t;
    event.beat              = beat;
    event.from              = phase;
    event.to                = to;
    event.pressure          = last_record.pressure;
    event.volume            = last_record.volume;
    event.arterial_pressure = last_record.arterial_pressure;
    recorder.add_transition(event);
    ++stats.n_transitions;
    observer.on_transition(event);

    if (phase == Phase::filling)
      armed = false; // until the next contraction onset
    phase = to;

    // A state that already satisfies the exit condition of the new phase
    // would not produce a sign change for the root finder.
    const double p = event.pressure;
    if (phase == Phase::isovolumetric_contraction &&
        p > event.arterial_pressure)
      transition(Phase::ejection, observer);
    else if (phase == Phase::isovolumetric_relaxation &&
             p < params.atrial_pressure)
      transition(Phase::filling, observer);
  }

  void
  CardiacCycle::Impl::arm(Observer &observer)
  {
    onset_passed = true;
    armed        = true;
    // Pressure already above the atrial one (backflow through the mitral
    // valve): it closes now.
    if (phase == Phase::filling &&
        last_record.pressure >= params.atrial_pressure)
      transition(Phase::isovolumetric_contraction, observer);
  }

  void
  CardiacCycle::Impl::start_segment(const bool reset_step_size)
  {
    const double beat_start = beat * params.period;
    const double onset_time = beat_start + contraction_onset;
    if (!onset_passed && onset_time > t + time_tolerance)
      {
        tstop            = onset_time;
        stop_is_beat_end = false;
      }
    else
      {
        tstop            = beat_start + params.period;
        stop_is_beat_end = true;
      }

    // ERKStepReset keeps the current step size; SetInitStep makes the next
    // step start from the given one (after events and step cuts).
    if (reset_step_size)
      check(ERKStepSetInitStep(arkode,
                               std::min(params.initial_time_step, max_step)),
            "ERKStepSetInitStep");
    check(ERKStepReset(arkode, t, y), "ERKStepReset");
    check(ERKStepSetStopTime(arkode, tstop), "ERKStepSetStopTime");
    const unsigned int n = n_roots();
    check(ERKStepRootInit(arkode, n, n > 0 ? &root_callback : nullptr),
          "ERKStepRootInit");
    if (n > 0)
      {
        std::array<int, 2> direction = {{0, 0}};
        switch (phase)
          {
            case Phase::filling:
              direction[0] = +1;
              break;
            case Phase::isovolumetric_contraction:
              direction = {{+1, -1}};
              break;
            case Phase::ejection:
            case Phase::isovolumetric_relaxation:
              direction[0] = -1;
              break;
          }
        check(ERKStepSetRootDirection(arkode, direction.data()),
              "ERKStepSetRootDirection");
        check(ERKStepSetNoInactiveRootWarn(arkode),
              "ERKStepSetNoInactiveRootWarn");
      }
  }

  bool
  CardiacCycle::Impl::finish_beat(Observer &observer)
  {
    const BeatSummary summary =
      recorder.finish(t,
                      previous_edv,
                      stats.n_ventricle_calls - calls_at_beat_start,
                      cuts_in_beat);
    ++stats.n_beats;
    observer.on_beat(summary);
    previous_edv = summary.end_diastolic_volume;

    // NaN (no EDV in one of the beats) never counts as periodic.
    if (beat >= 1 && params.periodicity_tolerance > 0 &&
        summary.periodicity < params.periodicity_tolerance)
      {
        stats.periodic = true;
        return true;
      }
    if (stats.n_beats >= params.n_max_beats)
      return true;

    ++beat;
    onset_passed        = false;
    recorder            = BeatRecorder(beat, t, &last_record);
    calls_at_beat_start = stats.n_ventricle_calls;
    cuts_in_beat        = 0;
    if (contraction_onset <= 0)
      arm(observer);
    return false;
  }

  bool
  CardiacCycle::Impl::reach_stop(Observer &observer)
  {
    if (stop_is_beat_end)
      {
        if (finish_beat(observer))
          return true;
      }
    else
      arm(observer);
    start_segment(false);
    return false;
  }

  void
  CardiacCycle::Impl::handle_failure(const int flag)
  {
    if (recoverable_failure && consecutive_cuts < params.max_step_cuts)
      {
        // Redo the step from the last accepted state with half the step
        // that failed (ARKode's current step size is the attempted one).
        realtype h_failed = max_step;
        ERKStepGetCurrentStep(arkode, &h_failed);
        max_step = 0.5 * std::min<double>(std::abs(h_failed), max_step);
        check(ERKStepSetMaxStep(arkode, max_step), "ERKStepSetMaxStep");
        ++consecutive_cuts;
        ++cuts_in_beat;
        ++stats.n_step_cuts;
        step_cut_active     = true;
        steps_since_cut     = 0;
        recoverable_failure = false;
        start_segment(true);
        return;
      }
    const std::string where = "at t = " + str(t) + " ms (beat " +
                              std::to_string(beat) + ", phase " + name(phase) +
                              ")";
    if (recoverable_failure)
      AssertThrow(false,
                  dealii::ExcMessage(
                    "Circulation: the ventricle failed " +
                    std::to_string(consecutive_cuts + 1) + " times in a row " +
                    where + ", even with the time step cut to " +
                    str(max_step) + " ms: " + recoverable_message));
    AssertThrow(false,
                dealii::ExcMessage("Circulation: the ODE integrator failed " +
                                   where + " (" + flag_name(flag) +
                                   "): " + arkode_message));
  }

  CardiacCycle::Statistics
  CardiacCycle::Impl::run(Observer &observer)
  {
    AssertThrow(!has_run,
                dealii::ExcMessage("CardiacCycle::run() may be called once."));
    has_run = true;

    t = 0;
    accept(0.0, observer);
    if (contraction_onset <= 0)
      arm(observer);
    start_segment(true);

    while (true)
      {
        if (tstop - t <= time_tolerance)
          {
            t = tstop;
            if (reach_stop(observer))
              break;
            continue;
          }

        realtype  t_reached = t;
        const int flag =
          ERKStepEvolve(arkode, tstop, y_out, &t_reached, ARK_ONE_STEP);
        if (fatal_error)
          {
            // The integrator stays at the last accepted state.
            std::exception_ptr error = fatal_error;
            fatal_error              = nullptr;
            std::rethrow_exception(error);
          }
        if (flag < 0)
          {
            handle_failure(flag);
            continue;
          }

        const double h = t_reached - t;
        // Steps end exactly at stop times.
        t = flag == ARK_TSTOP_RETURN ? tstop : t_reached;
        N_VScale(1.0, y_out, y);
        accept(h, observer);
        consecutive_cuts = 0;
        if (step_cut_active &&
            ++steps_since_cut >= n_steps_before_restoring_max_step)
          {
            max_step        = params.max_time_step;
            step_cut_active = false;
            check(ERKStepSetMaxStep(arkode, max_step), "ERKStepSetMaxStep");
          }
        if (observer.stop_requested())
          {
            stats.interrupted = true;
            break;
          }

        if (flag == ARK_ROOT_RETURN)
          {
            std::array<int, 2> found = {{0, 0}};
            check(ERKStepGetRootInfo(arkode, found.data()),
                  "ERKStepGetRootInfo");
            Phase to = phase;
            switch (phase)
              {
                case Phase::filling:
                  to = Phase::isovolumetric_contraction;
                  break;
                case Phase::isovolumetric_contraction:
                  to = found[0] != 0 ? Phase::ejection : Phase::filling;
                  break;
                case Phase::ejection:
                  to = Phase::isovolumetric_relaxation;
                  break;
                case Phase::isovolumetric_relaxation:
                  to = Phase::filling;
                  break;
              }
            transition(to, observer);
            start_segment(true);
          }
        else if (flag == ARK_TSTOP_RETURN)
          {
            if (reach_stop(observer))
              break;
          }
      }

    long int n = 0;
    ERKStepGetNumRhsEvals(arkode, &n);
    stats.n_rhs_evaluations = n;
    ERKStepGetNumErrTestFails(arkode, &n);
    stats.n_error_test_failures = n;
    stats.end_time              = t;
    return stats;
  }

  // ---------------------------------------------------------------------

  CardiacCycle::CardiacCycle(const Parameters &parameters,
                             Ventricle        &ventricle,
                             const double      initial_volume,
                             const double      contraction_onset)
    : impl(std::make_unique<Impl>(parameters,
                                  ventricle,
                                  initial_volume,
                                  contraction_onset))
  {}

  CardiacCycle::~CardiacCycle() = default;

  CardiacCycle::Statistics
  CardiacCycle::run(Observer &observer)
  {
    return impl->run(observer);
  }
} // namespace systole::Circulation
