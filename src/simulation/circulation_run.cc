#include "simulation/circulation_run.h"

#include <deal.II/base/parameter_handler.h>

#include "base/interrupt.h"
#include "base/logger.h"
#include "base/units.h"
#include "circulation/model_factory.h"
#include "circulation/model_summary.h"
#include "circulation/ode_integrator.h"
#include "circulation/parameters.h"
#include "io/results_file.h"
#include "simulation/circulation_columns.h"
#include "simulation/parameters.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace systole
{
  namespace
  {
    using Vector = dealii::Vector<double>;
    using namespace Circulation;

    /// The integrator's settings from subsection Circulation.
    Integrator::Settings
    integrator_settings(const Circulation::Parameters &circulation)
    {
      Integrator::Settings settings;
      settings.relative_tolerance = circulation.steps.relative_tolerance;
      settings.absolute_volume_tolerance =
        circulation.steps.absolute_volume_tolerance;
      settings.max_step     = circulation.steps.max_step;
      settings.initial_step = circulation.steps.initial_step;
      return settings;
    }

    /// One line: code version, model, states, cavities, beats, output.
    void
    log_banner(const Circulation::Parameters &circulation,
               const Model                   &model,
               const RunParameters           &run,
               Logger                        &logger)
    {
      std::ostringstream o;
      o << IO::code_version() << ": problem '" << run.problem << "', model '"
        << model.name() << "'\n  " << model.n_states() << " states, "
        << model.n_cavities() << " cavities (";
      for (unsigned int c = 0; c < model.n_cavities(); ++c)
        o << (c > 0 ? ", " : "") << model.cavities()[c].name;
      o << "), up to " << circulation.steps.n_max_beats << " beats of "
        << circulation.steps.period << " ms\n  output every " << run.time_step
        << " ms, relative tolerance " << circulation.steps.relative_tolerance;
      logger.line(o.str());
    }

    /// The 0D model alone, beat by beat: rows at the output times, the
    /// valve events, a summary row per beat.
    class CirculationRun
    {
    public:
      /// The settings, logger and communicator of the run are those of
      /// @p in.
      CirculationRun(const Circulation::Parameters &circulation,
                     const Model                   &model,
                     const RunInputs               &in);

      /// Integrates beat @p beat to its end, writing its rows and events;
      /// false when interrupted.
      bool
      integrate_beat(const unsigned int beat);

      /// The summary row of the beat ended at @p beat_end; true when the
      /// run is periodic (Periodicity tolerance).
      bool
      finish_beat(const unsigned int beat, const double beat_end);

      /// Statistics and the last log lines.
      void
      finish(const unsigned int n_beats, const bool periodic);

    private:
      /// Evaluates the pressures and outputs of (t, y) and adds the sample
      /// to the beat.
      void
      sample(const double t, const Vector &y);
      void
      write_row(const double t, const Vector &y);
      void
      write_event(const Integrator::Event &e);

      const Circulation::Parameters &circulation;
      const Model                   &model;
      const RunParameters           &run;
      Logger                        &logger;
      const MPI_Comm                 comm;
      const Vector                   y0;
      Integrator                     integrator;
      CavityPhases                   phases;
      std::vector<bool>              open;
      ModelBeatRecorder              recorder;
      IO::ResultsFile                results;
      Progress                       progress;
      const double                   total_volume_0;
      double                         largest_drift = 0;
      Vector                         p_ext, p_cavities, outputs;
      unsigned int                   beat = 0, row_number = 0, n_events = 0;
      /// Output times j * interval (exact products, no accumulated sums).
      unsigned long                               next_output = 1;
      const std::chrono::steady_clock::time_point start;
    };

    Vector
    initial_state(const Model &model)
    {
      Vector y0;
      model.initial_state(y0);
      return y0;
    }

    CirculationRun::CirculationRun(const Circulation::Parameters &circulation,
                                   const Model                   &model,
                                   const RunInputs               &in)
      : circulation(circulation)
      , model(model)
      , run(in.run)
      , logger(in.logger)
      , comm(in.comm)
      , y0(initial_state(model))
      , integrator(model, integrator_settings(circulation), 0.0, y0)
      , phases(model, integrator.valves_open())
      , open(integrator.valves_open())
      , recorder(model, integrator.valves_open())
      , results(run.output_directory, in.parameter_text, comm)
      , progress(logger,
                 Progress::parse_mode(run.progress),
                 0.0,
                 circulation.steps.period * circulation.steps.n_max_beats)
      , total_volume_0(model.total_blood_volume(y0))
      , p_ext(model.n_cavities())
      , start(std::chrono::steady_clock::now())
    {
      recorder.start(0, 0.0);
      write_row(0.0, y0);
    }

    void
    CirculationRun::sample(const double t, const Vector &y)
    {
      model.cavity_pressures({t, y, p_ext}, p_cavities);
      model.evaluate_outputs({t, y, p_ext}, outputs);
      recorder.add(t, y, p_cavities, outputs);
      largest_drift =
        std::max(largest_drift,
                 std::abs(model.total_blood_volume(y) - total_volume_0) /
                   total_volume_0);
    }

    void
    CirculationRun::write_row(const double t, const Vector &y)
    {
      sample(t, y);
      std::vector<IO::Column> row = {{"time", "ms", t},
                                     {"beat", "-", static_cast<double>(beat)}};
      std::vector<Phase>      phase_list;
      for (unsigned int c = 0; c < model.n_cavities(); ++c)
        phase_list.push_back(phases.phase(c));
      append_model_columns(model, {t, y, p_ext}, phase_list, row);
      results.append_timeseries(row);
      progress.update(row_number++, t, "beat " + std::to_string(beat));
    }

    void
    CirculationRun::write_event(const Integrator::Event &e)
    {
      open[e.valve] = e.opens;
      phases.update(open);
      sample(e.time, e.state);
      recorder.add_valve_event(e.valve, e.opens, e.time, e.state, p_cavities);
      results.append_event(valve_event_columns(
        model,
        {e.time, beat, e.valve, e.opens, e.state, p_cavities}));
      ++n_events;
    }

    bool
    CirculationRun::integrate_beat(const unsigned int this_beat)
    {
      beat                  = this_beat;
      const double period   = circulation.steps.period;
      const double interval = run.time_step;
      const double beat_end = (beat + 1) * period;
      if (beat > 0)
        recorder.start(beat, beat * period);
      while (true)
        {
          double     t_next = next_output * interval;
          const bool at_end = t_next >= beat_end - 1e-9 * period;
          if (at_end)
            {
              if (std::abs(t_next - beat_end) <= 1e-9 * period)
                ++next_output;
              t_next = beat_end;
            }
          else
            ++next_output;
          for (const auto &e : integrator.advance(t_next))
            write_event(e);
          write_row(t_next, integrator.state());
          if (at_end)
            return true;
          if (interrupted(comm))
            {
              logger.line("Interrupted: " + results.path() +
                          " holds the rows up to t = " +
                          std::to_string(integrator.time()) + " ms.");
              return false;
            }
        }
    }

    bool
    CirculationRun::finish_beat(const unsigned int this_beat,
                                const double       beat_end)
    {
      const auto              summary = recorder.finish(beat_end);
      std::vector<IO::Column> row;
      for (const auto &c : summary)
        row.push_back({c.name, c.unit, c.value});
      results.append_summary(row);
      logger.line(beat_log_line(model, this_beat, summary));
      return this_beat >= 1 && circulation.steps.periodicity_tolerance > 0 &&
             recorder.periodicity() < circulation.steps.periodicity_tolerance;
    }

    void
    CirculationRun::finish(const unsigned int n_beats, const bool periodic)
    {
      const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
      const auto         stats = integrator.statistics();
      std::ostringstream o;
      o << n_beats << " beat(s)" << (periodic ? ", periodic" : "") << "; "
        << stats.steps << " ARKode steps, " << stats.rhs_evaluations
        << " right-hand sides, " << stats.jacobian_evaluations
        << " Jacobians,\n  " << stats.error_test_failures
        << " error test failures, " << n_events << " valve events; "
        << std::setprecision(3) << wall << " s\n  blood volume "
        << std::setprecision(6) << Units::mm3_to_mL(total_volume_0)
        << " mL, largest relative change " << std::setprecision(2)
        << std::scientific << largest_drift;
      logger.line(o.str());
      results.write_statistics(
        {{"beats", "-", static_cast<double>(n_beats)},
         {"periodic", "-", periodic ? 1.0 : 0.0},
         {"arkode_steps", "-", static_cast<double>(stats.steps)},
         {"rhs_evaluations", "-", static_cast<double>(stats.rhs_evaluations)},
         {"jacobian_evaluations",
          "-",
          static_cast<double>(stats.jacobian_evaluations)},
         {"error_test_failures",
          "-",
          static_cast<double>(stats.error_test_failures)},
         {"valve_events", "-", static_cast<double>(n_events)},
         {"integration_seconds", "s", wall}});
      logger.line("Wrote " + results.path());
    }
  } // namespace

  void
  run_circulation_problem(const RunInputs &in)
  {
    const auto circulation = Circulation::Parameters::parse(in.prm);
    const auto model       = create_model(in.prm);
    log_banner(circulation, *model, in.run, in.logger);
    CirculationRun r(circulation, *model, in);
    unsigned int   n_beats  = 0;
    bool           periodic = false;
    for (unsigned int beat = 0; beat < circulation.steps.n_max_beats; ++beat)
      {
        if (!r.integrate_beat(beat))
          break;
        ++n_beats;
        if (r.finish_beat(beat, (beat + 1) * circulation.steps.period))
          {
            periodic = true;
            break;
          }
      }
    r.finish(n_beats, periodic);
  }
} // namespace systole
