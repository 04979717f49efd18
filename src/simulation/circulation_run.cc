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
  } // namespace

  void
  run_circulation_problem(const dealii::ParameterHandler &prm,
                          const RunParameters            &run,
                          const std::string              &parameter_text,
                          Logger                         &logger,
                          const MPI_Comm                  comm)
  {
    using namespace Circulation;
    const auto   circulation = Circulation::Parameters::parse(prm);
    const auto   model       = create_model(prm);
    const double period      = circulation.period;
    const double interval    = run.time_step;

    Integrator::Settings settings;
    settings.relative_tolerance        = circulation.relative_tolerance;
    settings.absolute_volume_tolerance = circulation.absolute_volume_tolerance;
    settings.max_step                  = circulation.max_time_step;
    settings.initial_step              = circulation.initial_time_step;

    {
      std::ostringstream o;
      o << IO::code_version() << ": problem '" << run.problem << "', model '"
        << model->name() << "'\n  " << model->n_states() << " states, "
        << model->n_cavities() << " cavities (";
      for (unsigned int c = 0; c < model->n_cavities(); ++c)
        o << (c > 0 ? ", " : "") << model->cavities()[c].name;
      o << "), up to " << circulation.n_max_beats << " beats of " << period
        << " ms\n  output every " << interval << " ms, relative tolerance "
        << settings.relative_tolerance;
      logger.line(o.str());
    }

    Vector y0;
    model->initial_state(y0);
    Integrator        integrator(*model, settings, 0.0, y0);
    CavityPhases      phases(*model, integrator.valves_open());
    std::vector<bool> open = integrator.valves_open();
    ModelBeatRecorder recorder(*model, integrator.valves_open());

    IO::ResultsFile results(run.output_directory, parameter_text, comm);
    Progress        progress(logger,
                      Progress::parse_mode(run.progress),
                      0.0,
                      period * circulation.n_max_beats);

    const double total_volume_0 = model->total_blood_volume(y0);
    double       largest_drift  = 0;
    Vector       p_ext(model->n_cavities()), p_cavities, outputs;
    unsigned int beat = 0, row_number = 0;

    // Evaluates the pressures and outputs of (t, y) and adds the sample to
    // the beat.
    const auto sample = [&](const double t, const Vector &y) {
      model->cavity_pressures(t, y, p_ext, p_cavities);
      model->evaluate_outputs(t, y, p_ext, outputs);
      recorder.add(t, y, p_cavities, outputs);
      largest_drift =
        std::max(largest_drift,
                 std::abs(model->total_blood_volume(y) - total_volume_0) /
                   total_volume_0);
    };
    const auto write_row = [&](const double t, const Vector &y) {
      sample(t, y);
      std::vector<IO::Column> row = {{"time", "ms", t},
                                     {"beat", "-", static_cast<double>(beat)}};
      std::vector<Phase>      phase_list;
      for (unsigned int c = 0; c < model->n_cavities(); ++c)
        phase_list.push_back(phases.phase(c));
      append_model_columns(*model, t, y, p_ext, phase_list, row);
      results.append_timeseries(row);
      progress.update(row_number++, t, "beat " + std::to_string(beat));
    };
    const auto write_event = [&](const Integrator::Event &e) {
      open[e.valve] = e.opens;
      phases.update(open);
      sample(e.time, e.state);
      recorder.add_valve_event(e.valve, e.opens, e.time, e.state, p_cavities);
      results.append_event(valve_event_columns(*model,
                                               e.time,
                                               beat,
                                               e.valve,
                                               e.opens,
                                               e.state,
                                               p_cavities));
    };

    const auto   start    = std::chrono::steady_clock::now();
    unsigned int n_events = 0, n_beats = 0;
    bool         periodic = false, stopped = false;
    // Output times j * interval (exact products, no accumulated sums) and
    // the beat ends.
    unsigned long next_output = 1;
    recorder.start(0, 0.0);
    write_row(0.0, y0);
    for (beat = 0; beat < circulation.n_max_beats; ++beat)
      {
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
              {
                write_event(e);
                ++n_events;
              }
            write_row(t_next, integrator.state());
            if (at_end)
              break;
            if (interrupted(comm))
              {
                stopped = true;
                break;
              }
          }
        if (stopped)
          {
            logger.line("Interrupted: " + results.path() +
                        " holds the rows up to t = " +
                        std::to_string(integrator.time()) + " ms.");
            break;
          }

        const auto              summary = recorder.finish(beat_end);
        std::vector<IO::Column> row;
        for (const auto &c : summary)
          row.push_back({c.name, c.unit, c.value});
        results.append_summary(row);
        ++n_beats;

        logger.line(beat_log_line(*model, beat, summary));

        if (beat >= 1 && circulation.periodicity_tolerance > 0 &&
            recorder.periodicity() < circulation.periodicity_tolerance)
          {
            periodic = true;
            break;
          }
      }

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
} // namespace systole
