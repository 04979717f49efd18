#include "simulation/heartbeat_stepper.h"

#include <deal.II/base/exceptions.h>

#include "base/errors.h"
#include "circulation/bdf_step.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/serialization/vector.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace systole
{
  using Vector = dealii::Vector<double>;

  struct HeartbeatStepper::Impl
  {
    Impl(const Circulation::Model &model,
         CoupledVentricles        &ventricles,
         const Settings           &settings,
         const Vector             &y0,
         const Vector             &p0)
      : model(model)
      , ventricles(ventricles)
      , settings(settings)
      , bdf(model,
            {settings.relative_tolerance,
             settings.absolute_volume_tolerance,
             settings.absolute_pressure_tolerance},
            0.0,
            y0,
            p0)
      , open(initial_valves(model, y0, p0))
      , recorder(model, open)
      , phases(std::make_unique<Circulation::CavityPhases>(model, open))
      , breakpoints(ventricles.breakpoints_in_beat())
    {
      model.valve_indicators({0.0, y0, p0}, indicators);
    }

    /// The valves open at (0, @p y0, @p p0): positive indicators.
    static std::vector<bool>
    initial_valves(const Circulation::Model &model,
                   const Vector             &y0,
                   const Vector             &p0)
    {
      Vector g;
      model.valve_indicators({0.0, y0, p0}, g);
      std::vector<bool> open;
      for (const double value : g)
        open.push_back(value > 0);
      return open;
    }

    /// The end of the next attempt: the step size (below the cap after a
    /// failure), clipped to the next breakpoint, beat end and known event
    /// bracket. Sets attempt.t_new and attempt.h_try.
    void
    next_end_time();

    /// One coupled solve to attempt.t_new from the last accepted state: false
    /// if the mechanics or the 0D step failed (the ventricles are back at the
    /// accepted state then).
    bool
    solve_coupled();

    /// After a failed solve: halve the step, cap the next ones; throws after
    /// Settings::max_step_cuts failures in a row.
    void
    cut_after_failure();

    /// Whether a valve indicator changed sign more than the event tolerance
    /// before attempt.t_new: then the attempt is rejected, its end and
    /// indicators bracket the crossing, and the next attempts aim just after
    /// it (next_end_time()).
    bool
    redo_for_valve_event();

    /// Whether the BDF error estimate exceeds the tolerance: then the attempt
    /// is rejected and the next one is shorter.
    bool
    redo_for_error();

    /// Accept the attempt: commit the 0D state and the mechanics, switch the
    /// valves that changed (restart the BDF then) and choose the next step.
    /// Returns the valves that switched.
    std::vector<unsigned int>
    accept();

    /// At a beat's end: its summary to @p observer; true when the run is
    /// done (periodic or the last beat).
    bool
    end_beat(Observer &observer);

    /// The earliest sign change of a valve indicator between the accepted
    /// state and @p g_new at @p t_new, as the fraction of that step
    /// (crossing_fraction(), quadratic through the accepted state before
    /// where there is one in the phase); 2 if none.
    double
    crossing(double t_new, const Vector &g_new) const;

    /// The factor by which the next step may grow after the accepted one
    /// for the displacement predictor (Settings::displacement_tolerance).
    double
    displacement_ratio() const;

    /// The factor the next step may have after the accepted one for the
    /// Newton iterations it took (Settings::newton_iterations_target).
    double
    newton_ratio() const;

    /// Record the accepted step; report it (and its events, its beat end).
    void
    record(Observer &observer, const std::vector<unsigned int> &switched);

    /// The state between two steps (save() and load()).
    template <class Archive>
    void
    serialize(Archive &archive)
    {
      archive &bdf &open &recorder &*phases &indicators;
      archive &stats.n_beats &stats.periodic &stats.interrupted &stats.n_steps;
      archive &stats.n_solves &stats.n_newton_iterations;
      archive &stats.n_error_rejections &stats.n_event_rejections;
      archive &stats.n_failures &stats.n_events           &stats.end_time;
      archive &beat &step_index &last_step &h &upper &cap &cuts;
      archive &state_times &previous_indicators           &upper_g;
    }

    bool resumed = false;

    const Circulation::Model                  &model;
    CoupledVentricles                         &ventricles;
    const Settings                             settings;
    Circulation::BdfStep                       bdf;
    std::vector<bool>                          open;
    Circulation::ModelBeatRecorder             recorder;
    std::unique_ptr<Circulation::CavityPhases> phases;
    /// Why the last attempt failed (one line), for the final message.
    std::string                     last_failure;
    std::vector<Circulation::Phase> phase_list;
    const std::vector<double>       breakpoints;
    Vector                          indicators; ///< at the accepted state
    /// At the accepted state before it (state_times[1], if there is one).
    Vector       previous_indicators;
    Statistics   stats;
    unsigned int beat = 0, step_index = 0;
    double       last_step = 0;
    /// The times of the accepted states the predictor extrapolates from,
    /// latest first: at most three, from the last valve event on.
    std::vector<double> state_times;
    /// The step being attempted (not saved: checkpoints are written
    /// between steps).
    struct Attempt
    {
      // Its counters.
      unsigned int step_iterations = 0, step_solves = 0, step_rejected = 0;
      unsigned int step_order = 1;
      // Its end, size, the next breakpoint, the error ratio and the valve
      // indicators there.
      double t_new = 0, h_try = 0, breakpoint = 0, ratio = 1;
      Vector g;
      /// The end of the last rejected attempt from the accepted state
      /// (infinity after an accepted step): a redo ends before it.
      double rejected_end = std::numeric_limits<double>::infinity();
      /// The displacement predictor's error of the last converged solve
      /// [mm] (set by every solve before the accept() that uses it).
      double predictor_error = 0;
      /// The Newton iterations with a new tangent of that solve.
      unsigned int tangent_iterations = 0;
    } attempt;
    // The next step size, the known bracket of a crossing, the cap after a
    // failure, and the failures in a row.
    double       h     = 0;
    double       upper = std::numeric_limits<double>::infinity();
    Vector       upper_g; ///< the valve indicators at upper
    double       cap  = std::numeric_limits<double>::infinity();
    unsigned int cuts = 0;
  };


  void
  HeartbeatStepper::Impl::next_end_time()
  {
    const double t        = bdf.time();
    const double period   = settings.period;
    const double beat_end = (beat + 1) * period;
    // The next breakpoint after t (the steps end there).
    attempt.breakpoint = beat_end;
    for (const double b : breakpoints)
      if (beat * period + b > t + settings.min_step)
        attempt.breakpoint = std::min(attempt.breakpoint, beat * period + b);
    attempt.t_new = std::min({t + std::min(h, cap), attempt.breakpoint, upper});
    // Inside a known bracket of a valve crossing, aim just after the
    // crossing interpolated from the accepted state and the bracket's end
    // (no solve at that end again).
    if (upper < std::numeric_limits<double>::infinity() && upper > t)
      attempt.t_new = std::min(attempt.t_new,
                               t + crossing(upper, upper_g) * (upper - t) +
                                 0.5 * settings.event_time_tolerance);
    if (attempt.breakpoint - attempt.t_new < settings.min_step)
      attempt.t_new = attempt.breakpoint; // no sliver before a breakpoint
    // A redo is shorter than the attempt it replaces. (The rule above, or
    // the minimum step, could otherwise give the rejected attempt again, and
    // the stepper would repeat it without end.)
    if (attempt.t_new >= attempt.rejected_end)
      attempt.t_new = t + 0.5 * (attempt.rejected_end - t);
    attempt.h_try      = attempt.t_new - t;
    attempt.step_order = bdf.order();
  }


  bool
  HeartbeatStepper::Impl::solve_coupled()
  {
    bdf.begin(attempt.t_new);
    ventricles.set_time(attempt.t_new);
    // The displacement is extrapolated from the last accepted states, but
    // not across a valve event (state_times restarts there): the last
    // step's motion belongs to the phase before it, and at a mitral closure
    // that re-refers the base springs it holds their release (1.4 mm in the
    // first beat of the incompressible BiV, doubled by the extrapolation to
    // |R_u| = 2e24: three failed solves).
    ventricles.predict(predictor_weights(attempt.t_new, state_times));
    Vector                   p = bdf.start_pressures();
    const CavityVolumeTarget target =
      [this](const Vector &p, Vector &W, dealii::FullMatrix<double> &dW_dp) {
        bdf.solve(p, W, dW_dp);
      };
    ++attempt.step_solves;
    ++stats.n_solves;
    try
      {
        const unsigned int its     = ventricles.solve(target, p);
        attempt.predictor_error    = ventricles.predictor_error();
        attempt.tangent_iterations = ventricles.last_tangent_iterations();
        attempt.step_iterations += its;
        stats.n_newton_iterations += its;
        // The 0D state of the converged pressures (the last target
        // evaluation of the solve may have been at another iterate).
        Vector                     W;
        dealii::FullMatrix<double> dW_dp;
        bdf.solve(p, W, dW_dp);
      }
    catch (const ExcNewtonDidNotConverge &e)
      {
        ventricles.reject();
        last_failure = one_line_message(e);
        return false;
      }
    catch (const ExcInvertedElement &e)
      {
        ventricles.reject();
        last_failure = one_line_message(e);
        return false;
      }
    model.valve_indicators({attempt.t_new,
                            bdf.solution(),
                            bdf.solution_pressures()},
                           attempt.g);
    return true;
  }


  void
  HeartbeatStepper::Impl::cut_after_failure()
  {
    ++stats.n_failures;
    ++attempt.step_rejected;
    ++cuts;
    if (cuts > settings.max_step_cuts || attempt.h_try <= settings.min_step)
      {
        // Where it stopped: time, beat, each cavity's phase, and the last
        // failure (the mechanics' residuals per block).
        std::ostringstream o;
        o << "The coupled mechanics and circulation step from t = "
          << bdf.time() << " ms (beat " << beat + 1 << "; phase";
        for (unsigned int c = 0; c < model.n_cavities(); ++c)
          o << (c == 0 ? " " : ", ") << model.cavities()[c].name << " "
            << Circulation::name(phases->phase(c));
        o << ") failed " << cuts
          << " times in a row, the last time with a step of " << attempt.h_try
          << " ms (the smallest is " << settings.min_step
          << " ms): " << last_failure
          << " See the Newton log (Output / Solver log = on).";
        throw ExcStepFailed(o.str(), step_index - 1);
      }
    attempt.rejected_end = attempt.t_new;
    h                    = 0.5 * attempt.h_try;
    cap                  = 0.75 * attempt.h_try;
  }


  bool
  HeartbeatStepper::Impl::redo_for_valve_event()
  {
    const double theta = crossing(attempt.t_new, attempt.g);
    if (theta <= 1 &&
        (1 - theta) * attempt.h_try > settings.event_time_tolerance)
      {
        ventricles.reject();
        ++stats.n_event_rejections;
        ++attempt.step_rejected;
        upper                = attempt.t_new; // (next_end_time() aims)
        upper_g              = attempt.g;
        attempt.rejected_end = attempt.t_new;
        h                    = std::max(h, settings.min_step);
        return true;
      }
    return false;
  }


  bool
  HeartbeatStepper::Impl::redo_for_error()
  {
    const auto e  = bdf.error_norms();
    attempt.ratio = bdf.step_ratio();
    if (std::max(e[0], e[1]) > 1 && attempt.h_try > settings.min_step)
      {
        ventricles.reject();
        ++stats.n_error_rejections;
        ++attempt.step_rejected;
        attempt.rejected_end = attempt.t_new;
        h = std::max(attempt.ratio * attempt.h_try, settings.min_step);
        return true;
      }
    return false;
  }


  std::vector<unsigned int>
  HeartbeatStepper::Impl::accept()
  {
    bdf.accept();
    ventricles.accept();
    last_step            = attempt.h_try;
    cuts                 = 0;
    attempt.rejected_end = std::numeric_limits<double>::infinity();
    ++stats.n_steps;
    std::vector<unsigned int> switched;
    for (unsigned int v = 0; v < attempt.g.size(); ++v)
      if ((attempt.g[v] > 0) != open[v])
        {
          open[v] = attempt.g[v] > 0;
          switched.push_back(v);
        }
    previous_indicators = indicators;
    indicators          = attempt.g;
    state_times.insert(state_times.begin(), attempt.t_new);
    state_times.resize(std::min<std::size_t>(state_times.size(), 3));
    if (!switched.empty())
      {
        state_times.resize(1);
        const unsigned int first = bdf.external_cavities()[0];
        const bool filled = phases->phase(first) == Circulation::Phase::filling;
        phases->update(open);
        if (filled && phases->phase(first) != Circulation::Phase::filling)
          ventricles.end_diastole();
        bdf.restart();
        stats.n_events += switched.size();
        h     = settings.initial_step;
        upper = std::numeric_limits<double>::infinity();
      }
    else if (attempt.t_new == attempt.breakpoint &&
             attempt.t_new < (beat + 1) * settings.period)
      h = settings.initial_step;
    else
      h = std::clamp(std::min(
                       {attempt.ratio, displacement_ratio(), newton_ratio()}) *
                       attempt.h_try,
                     settings.min_step,
                     settings.max_step);
    if (upper <= attempt.t_new)
      upper = std::numeric_limits<double>::infinity();
    cap *= 1.1;
    stats.end_time = attempt.t_new;
    return switched;
  }


  bool
  HeartbeatStepper::Impl::end_beat(Observer &observer)
  {
    const double beat_end = (beat + 1) * settings.period;
    observer.on_beat(beat, recorder.finish(beat_end));
    ++beat;
    ++stats.n_beats;
    if (beat >= 2 && settings.periodicity_tolerance > 0 &&
        recorder.periodicity() < settings.periodicity_tolerance)
      {
        stats.periodic = true;
        return true;
      }
    if (beat == settings.n_max_beats)
      return true;
    recorder.start(beat, beat_end);
    return false;
  }


  double
  HeartbeatStepper::Impl::displacement_ratio() const
  {
    // The secant predictor misses by O(h^2): the step whose miss is
    // expected at 0.9 of the tolerance, growing at most twofold. (The
    // quadratic predictor's miss is O(h^3), but its cube-root law grew the
    // steps more slowly for no fewer iterations: 139 against 136 steps in
    // the default's first beat, docs/verification.md.)
    const double tolerance = settings.displacement_tolerance;
    const double error     = attempt.predictor_error;
    if (!(tolerance > 0.0 && error > 0.0))
      return 2.0;
    return std::clamp(0.9 * std::sqrt(tolerance / error), 0.2, 2.0);
  }


  double
  HeartbeatStepper::Impl::newton_ratio() const
  {
    // Newton's iterations grow as the start moves out of its quadratic
    // range; sqrt as for the displacement predictor (its miss ~ h^2).
    const unsigned int target = settings.newton_iterations_target;
    const unsigned int n      = attempt.tangent_iterations;
    if (target == 0 || n <= target)
      return 2.0;
    return std::sqrt(static_cast<double>(target) / n);
  }


  double
  HeartbeatStepper::Impl::crossing(const double  t_new,
                                   const Vector &g_new) const
  {
    const bool   before = state_times.size() >= 2;
    const double t_before =
      before ? state_times[1] : std::numeric_limits<double>::quiet_NaN();
    double theta = 2;
    for (unsigned int v = 0; v < g_new.size(); ++v)
      if ((g_new[v] > 0) != open[v])
        theta =
          std::min(theta,
                   crossing_fraction({{t_before, state_times[0], t_new}},
                                     {{before ? previous_indicators[v] : 0.0,
                                       indicators[v],
                                       g_new[v]}}));
    return theta;
  }


  void
  HeartbeatStepper::Impl::record(Observer                        &observer,
                                 const std::vector<unsigned int> &switched)
  {
    phase_list.resize(model.n_cavities());
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      phase_list[c] = phases->phase(c);
    const Step step{step_index,
                    bdf.time(),
                    last_step,
                    beat,
                    bdf.state(),
                    bdf.pressures(),
                    phase_list,
                    attempt.step_iterations,
                    attempt.step_solves,
                    attempt.step_rejected,
                    attempt.step_order};
    Vector     outputs;
    model.evaluate_outputs({bdf.time(), bdf.state(), bdf.pressures()}, outputs);
    recorder.add(bdf.time(), bdf.state(), bdf.pressures(), outputs);
    observer.on_step(step);
    for (const unsigned int v : switched)
      {
        recorder.add_valve_event(v,
                                 open[v],
                                 bdf.time(),
                                 bdf.state(),
                                 bdf.pressures());
        observer.on_event(v, open[v], step);
      }
    ++step_index;
    attempt.step_iterations = attempt.step_solves = attempt.step_rejected = 0;
  }


  std::array<double, 3>
  predictor_weights(const double t_new, const std::vector<double> &times)
  {
    AssertThrow(!times.empty() && times.size() <= 3,
                dealii::ExcInternalError("predictor_weights(): 1-3 states"));
    const double h = t_new - times[0];
    if (times.size() == 3)
      {
        // Lagrange's basis at t_new through the three times.
        std::array<double, 3> w;
        for (unsigned int i = 0; i < 3; ++i)
          {
            w[i] = 1;
            for (unsigned int j = 0; j < 3; ++j)
              if (j != i)
                w[i] *= (t_new - times[j]) / (times[i] - times[j]);
          }
        if (std::abs(w[0]) <= 16 && std::abs(w[1]) <= 16 &&
            std::abs(w[2]) <= 16)
          return w;
      }
    if (times.size() == 1)
      return {{1, 0, 0}};
    const unsigned int j =
      times[0] - times[1] >= 0.5 * h || times.size() == 2 ? 1 : 2;
    const double          ratio = std::min(h / (times[0] - times[j]), 2.0);
    std::array<double, 3> w{{1 + ratio, 0, 0}};
    w[j] = -ratio;
    return w;
  }


  double
  crossing_fraction(const std::array<double, 3> &t,
                    const std::array<double, 3> &g)
  {
    const double g0 = g[1], g1 = g[2];
    if (g0 == g1)
      return 1.0;
    const double secant = std::clamp(g0 / (g0 - g1), 0.0, 1.0);
    // q(x) = g0 + b x + c x^2 in x = (time - t1) / (t2 - t1), through the
    // earlier point at x_0 < 0.
    const double x0 = (t[0] - t[1]) / (t[2] - t[1]);
    if (!(x0 < 0))
      return secant; // no earlier point (NaN)
    const double c = (g[0] - g0 - (g1 - g0) * x0) / (x0 * (x0 - 1));
    const double b = g1 - g0 - c;
    // A line, or a parabola that turns between the points (it would not
    // describe an indicator that moves one way): the secant.
    if (std::abs(c) <= 1e-12 * (std::abs(b) + std::abs(g0)))
      return secant;
    const double vertex = -b / (2 * c);
    if (vertex > x0 && vertex < 1)
      return secant;
    // The root in [0, 1] (q(0) and q(1) differ in sign: there is one), by
    // the cancellation-free pair of formulas.
    const double disc = b * b - 4 * c * g0;
    if (!(disc >= 0))
      return secant;
    const double r = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    for (const double x : {r / c, r != 0 ? g0 / r : 2.0})
      if (x >= 0 && x <= 1)
        return x;
    return secant;
  }


  HeartbeatStepper::HeartbeatStepper(const Circulation::Model &model,
                                     CoupledVentricles        &ventricles,
                                     const Settings           &settings,
                                     const Vector             &y0,
                                     const Vector             &p0)
    : impl(std::make_unique<Impl>(model, ventricles, settings, y0, p0))
  {
    AssertThrow(!impl->bdf.external_cavities().empty(),
                dealii::ExcMessage("The heartbeat needs a circulation model "
                                   "with at least one external (3D) "
                                   "cavity."));
  }

  HeartbeatStepper::~HeartbeatStepper() = default;


  HeartbeatStepper::Statistics
  HeartbeatStepper::run(Observer &observer)
  {
    Impl           &m = *impl;
    const Settings &s = m.settings;
    if (!m.resumed)
      {
        m.recorder.start(0, 0.0);
        m.record(observer, {});
        m.state_times = {m.bdf.time()};
        m.h           = s.initial_step;
      }
    m.stats.interrupted = false;
    for (;;)
      {
        m.next_end_time(); // step size, breakpoints, beat end, event bracket
        if (!m.solve_coupled()) // electrophysiology, tension, mechanics + 0D
          {
            observer.on_failure(m.bdf.time(), m.attempt.t_new, m.last_failure);
            m.cut_after_failure();
            continue;
          }
        if (m.redo_for_valve_event() || m.redo_for_error())
          continue;
        const auto switched = m.accept(); // valves, phases, next step size
        m.record(observer, switched);     // time series, events
        if (m.attempt.t_new == (m.beat + 1) * s.period && m.end_beat(observer))
          break;
        observer.on_step_complete(m.step_index - 1);
        if (observer.stop_requested())
          {
            m.stats.interrupted = true;
            break;
          }
      }
    return m.stats;
  }


  void
  HeartbeatStepper::save(boost::archive::text_oarchive &archive) const
  {
    impl->serialize(archive);
  }


  void
  HeartbeatStepper::load(boost::archive::text_iarchive &archive)
  {
    impl->serialize(archive);
    impl->resumed = true;
  }
} // namespace systole
