#include "simulation/heartbeat_stepper.h"

#include <deal.II/base/exceptions.h>

#include "base/errors.h"
#include "circulation/bdf_step.h"

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
      model.valve_indicators(0.0, y0, p0, indicators);
    }

    /// The valves open at (0, @p y0, @p p0): positive indicators.
    static std::vector<bool>
    initial_valves(const Circulation::Model &model,
                   const Vector             &y0,
                   const Vector             &p0)
    {
      Vector g;
      model.valve_indicators(0.0, y0, p0, g);
      std::vector<bool> open;
      for (const double value : g)
        open.push_back(value > 0);
      return open;
    }

    /// One coupled solve to @p t_new from the last accepted state: false if
    /// the mechanics or the 0D step failed (the ventricles are back at the
    /// accepted state then).
    bool
    solve_coupled(const double t_new, const double ratio);

    /// The earliest sign change of a valve indicator between the accepted
    /// state and the last solve, as the fraction of the step (linear in the
    /// indicators); 2 if none.
    double
    crossing(const Vector &g_new) const;

    /// Record the accepted step; report it (and its events, its beat end).
    void
    record(Observer &observer, const std::vector<unsigned int> &switched);

    const Circulation::Model                  &model;
    CoupledVentricles                         &ventricles;
    const Settings                             settings;
    Circulation::BdfStep                       bdf;
    std::vector<bool>                          open;
    Circulation::ModelBeatRecorder             recorder;
    std::unique_ptr<Circulation::CavityPhases> phases;
    std::vector<Circulation::Phase>            phase_list;
    const std::vector<double>                  breakpoints;
    Vector       indicators; ///< at the accepted state
    Statistics   stats;
    unsigned int beat = 0, step_index = 0;
    double       last_step = 0;
    // Counters of the step being attempted.
    unsigned int step_iterations = 0, step_solves = 0, step_rejected = 0;
    unsigned int step_order = 1;
  };


  bool
  HeartbeatStepper::Impl::solve_coupled(const double t_new, const double ratio)
  {
    bdf.begin(t_new);
    ventricles.set_time(t_new);
    ventricles.predict(ratio);
    Vector                   p = bdf.predicted_pressures();
    const CavityVolumeTarget target =
      [this](const Vector &p, Vector &W, dealii::FullMatrix<double> &dW_dp) {
        bdf.solve(p, W, dW_dp);
      };
    ++step_solves;
    ++stats.n_solves;
    try
      {
        const unsigned int its = ventricles.solve(target, p);
        step_iterations += its;
        stats.n_newton_iterations += its;
        // The 0D state of the converged pressures (the last target
        // evaluation of the solve may have been at another iterate).
        Vector                     W;
        dealii::FullMatrix<double> dW_dp;
        bdf.solve(p, W, dW_dp);
      }
    catch (const ExcNewtonDidNotConverge &)
      {
        ventricles.reject();
        return false;
      }
    catch (const ExcInvertedElement &)
      {
        ventricles.reject();
        return false;
      }
    return true;
  }


  double
  HeartbeatStepper::Impl::crossing(const Vector &g_new) const
  {
    double theta = 2;
    for (unsigned int v = 0; v < g_new.size(); ++v)
      if ((g_new[v] > 0) != open[v])
        {
          const double g0 = indicators[v];
          theta           = std::min(theta,
                           g0 == g_new[v]
                                       ? 1.0
                                       : std::clamp(g0 / (g0 - g_new[v]), 0.0, 1.0));
        }
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
                    step_iterations,
                    step_solves,
                    step_rejected,
                    step_order};
    Vector     outputs;
    model.evaluate_outputs(bdf.time(), bdf.state(), bdf.pressures(), outputs);
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
    step_iterations = step_solves = step_rejected = 0;
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
    m.recorder.start(0, 0.0);
    m.record(observer, {});

    double h     = s.initial_step;
    double upper = std::numeric_limits<double>::infinity(); // a crossing
    // After a failed solve, the steps grow back slowly: at most 3/4 of the
    // failed step, then 10 % more per accepted step.
    double       cap  = std::numeric_limits<double>::infinity();
    unsigned int cuts = 0;
    for (;;)
      {
        const double t        = m.bdf.time();
        const double beat_end = (m.beat + 1) * s.period;
        // The next breakpoint after t (the steps end there).
        double breakpoint = beat_end;
        for (const double b : m.breakpoints)
          if (m.beat * s.period + b > t + s.min_step)
            breakpoint = std::min(breakpoint, m.beat * s.period + b);
        double t_new = std::min({t + std::min(h, cap), breakpoint, upper});
        if (breakpoint - t_new < s.min_step)
          t_new = breakpoint; // no sliver before a breakpoint
        const double h_try = t_new - t;
        m.step_order       = m.bdf.order();

        // Solve the coupled step; on failure, cut it.
        if (!m.solve_coupled(t_new, m.last_step > 0 ? h_try / m.last_step : 0))
          {
            ++m.stats.n_failures;
            ++m.step_rejected;
            ++cuts;
            std::ostringstream o;
            o << "The coupled mechanics and circulation step from t = " << t
              << " ms failed " << cuts
              << " times in a row, the last time with a step of " << h_try
              << " ms. See the Newton log (Output / Solver log = on).";
            AssertThrow(cuts <= s.max_step_cuts && h_try > s.min_step,
                        dealii::ExcMessage(o.str()));
            h   = 0.5 * h_try;
            cap = 0.75 * h_try;
            continue;
          }
        cuts = 0;

        // A valve event inside the step: redo it to end just after it.
        Vector g;
        m.model.valve_indicators(t_new,
                                 m.bdf.solution(),
                                 m.bdf.solution_pressures(),
                                 g);
        const double theta = m.crossing(g);
        if (theta <= 1 && (1 - theta) * h_try > s.event_time_tolerance)
          {
            m.ventricles.reject();
            ++m.stats.n_event_rejections;
            ++m.step_rejected;
            upper = t_new;
            h     = std::max(theta * h_try + 0.5 * s.event_time_tolerance,
                         s.min_step);
            continue;
          }

        // The local error.
        const auto   e     = m.bdf.error_norms();
        const double ratio = m.bdf.step_ratio();
        if (std::max(e[0], e[1]) > 1 && h_try > s.min_step)
          {
            m.ventricles.reject();
            ++m.stats.n_error_rejections;
            ++m.step_rejected;
            h = std::max(ratio * h_try, s.min_step);
            continue;
          }

        // Accept.
        m.bdf.accept();
        m.ventricles.accept();
        m.last_step = h_try;
        ++m.stats.n_steps;
        std::vector<unsigned int> switched;
        for (unsigned int v = 0; v < g.size(); ++v)
          if ((g[v] > 0) != m.open[v])
            {
              m.open[v] = g[v] > 0;
              switched.push_back(v);
            }
        m.indicators = g;
        if (!switched.empty())
          {
            m.phases->update(m.open);
            m.bdf.restart();
            m.stats.n_events += switched.size();
            h     = s.initial_step;
            upper = std::numeric_limits<double>::infinity();
          }
        else if (t_new == breakpoint && t_new < beat_end)
          h = s.initial_step;
        else
          h = std::clamp(ratio * h_try, s.min_step, s.max_step);
        if (upper <= t_new)
          upper = std::numeric_limits<double>::infinity();
        cap *= 1.1;
        m.record(observer, switched);
        m.stats.end_time = t_new;

        if (t_new == beat_end)
          {
            observer.on_beat(m.beat, m.recorder.finish(beat_end));
            ++m.beat;
            ++m.stats.n_beats;
            const double periodicity = m.recorder.periodicity();
            if (m.beat >= 2 && s.periodicity_tolerance > 0 &&
                periodicity < s.periodicity_tolerance)
              {
                m.stats.periodic = true;
                break;
              }
            if (m.beat == s.n_max_beats)
              break;
            m.recorder.start(m.beat, beat_end);
          }
        if (observer.stop_requested())
          {
            m.stats.interrupted = true;
            break;
          }
      }
    return m.stats;
  }
} // namespace systole
