#include "simulation/cell_run.h"

#include <deal.II/base/parameter_handler.h>

#include "base/interrupt.h"
#include "base/logger.h"
#include "electrophysiology/action_potential.h"
#include "electrophysiology/parameters.h"
#include "electrophysiology/single_cell.h"
#include "io/results_file.h"
#include "materials/tension_factory.h"
#include "simulation/parameters.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>
#include <vector>

namespace systole
{
  void
  run_cell_problem(const dealii::ParameterHandler &prm,
                   const RunParameters            &run,
                   const std::string              &parameter_text,
                   Logger                         &logger,
                   const MPI_Comm                  comm)
  {
    using namespace Electrophysiology;
    const auto        ep     = Parameters::parse(prm);
    const auto        pacing = SingleCell::Pacing::parse(prm);
    const IonicModel &model  = *ep.ionic_model;

    SingleCell::Settings settings;
    settings.time_step          = ep.time_step;
    settings.order              = ep.order;
    settings.adaptive           = ep.adaptive;
    settings.relative_tolerance = ep.relative_tolerance;
    settings.absolute_tolerance = ep.absolute_tolerance;
    SingleCell cell(model, settings, pacing, run.start_time);

    // A calcium-driven tension model (Active tension / Model = Land) at the
    // fixed stretch Cell / Fibre stretch: one implicit step per cell step,
    // driven by the calcium at its end. The prescribed models (Bestel) need
    // an activation time and are not run here.
    const std::unique_ptr<Materials::TensionModel> tension_model =
      Materials::create_tension_model(prm,
                                      pacing.period > 0
                                        ? pacing.period
                                        : std::max(run.end_time, 1.0));
    const bool with_tension =
      tension_model &&
      tension_model->drive() == Materials::TensionDrive::calcium;
    const unsigned int n_tension = with_tension ? tension_model->n_states() : 0;
    std::vector<double> tension_state(n_tension), tension_trial(n_tension);
    if (with_tension)
      tension_model->initial_state(tension_state.data());
    double     tension = 0, tension_time = run.start_time, peak_tension = 0;
    const auto step_tension = [&](const double t, const double *s) {
      if (!with_tension || !(t > tension_time))
        return;
      Materials::TensionInput in;
      in.time             = t;
      in.time_step        = t - tension_time;
      in.calcium          = model.calcium_uM(s);
      in.stretch          = pacing.stretch;
      in.previous_stretch = pacing.stretch;
      Materials::TensionOutput out;
      tension_model->step(tension_state.data(), in, tension_trial.data(), out);
      tension_state.swap(tension_trial);
      tension      = out.tension;
      tension_time = t;
      peak_tension = std::max(peak_tension, tension);
    };

    {
      std::ostringstream o;
      o << IO::code_version() << ": problem '" << run.problem << "', "
        << model.name() << " (" << model.n_states() << " states, "
        << model.n_gates() << " gates by Rush-Larsen)\n  step " << ep.time_step
        << " ms, paced every " << pacing.period << " ms";
      if (with_tension)
        o << "; " << tension_model->name() << " tension at stretch "
          << pacing.stretch;
      logger.line(o.str());
    }

    IO::ResultsFile results(run.output_directory, parameter_text, comm);
    Progress        progress(logger,
                      Progress::parse_mode(run.progress),
                      run.start_time,
                      run.end_time);

    // Beat k is [k P, (k + 1) P), measured from its stimulus onset on.
    const double period =
      pacing.period > 0 ? pacing.period : std::max(run.end_time, 1.0);
    const auto beat_of = [&](const double t) {
      return static_cast<long>(std::floor(t / period + 1e-9));
    };
    const auto              mV = [&](const double v) { return model.to_mV(v); };
    long                    beat      = beat_of(run.start_time);
    double                  onset     = beat * period + pacing.start;
    bool                    measuring = false;
    ActionPotentialRecorder recorder;
    unsigned long           steps_at_beat_start = 0;

    const auto write_summary = [&]() {
      const BeatSummary       s   = recorder.summary();
      std::vector<IO::Column> row = {
        {"beat", "-", static_cast<double>(beat)},
        {"start_time", "ms", beat * period},
        {"resting_potential_mV", "mV", s.resting_potential_mV},
        {"peak_potential_mV", "mV", s.peak_potential_mV},
        {"APD90_ms", "ms", s.APD90_ms},
        {"peak_calcium_uM", "µM", s.peak_calcium_uM}};
      if (with_tension)
        row.push_back({"peak_tension_kPa", "kPa", peak_tension});
      row.push_back(
        {"arkode_steps",
         "-",
         static_cast<double>(cell.n_steps() - steps_at_beat_start)});
      results.append_summary(row);
      std::ostringstream o;
      o << std::setprecision(5) << "Beat " << beat << ": rest "
        << s.resting_potential_mV << " mV, peak " << s.peak_potential_mV
        << " mV, APD90 " << s.APD90_ms << " ms, peak calcium "
        << s.peak_calcium_uM << " µM";
      if (with_tension)
        o << ", peak tension " << peak_tension << " kPa";
      logger.line(o.str());
    };

    // Every ARKode step: the beat's samples from its stimulus onset (a step
    // boundary) on, and a summary row when a beat ends.
    const auto observe = [&](const double t, const double v, const double *s) {
      step_tension(t, s);
      if (beat_of(t) > beat)
        {
          if (measuring)
            write_summary();
          peak_tension        = tension;
          beat                = beat_of(t);
          onset               = beat * period + pacing.start;
          measuring           = false;
          steps_at_beat_start = cell.n_steps();
        }
      if (!measuring && std::abs(t - onset) < 1e-9 * period)
        {
          recorder.start(t, mV(v), model.calcium_uM(s));
          measuring = true;
        }
      else if (measuring)
        recorder.add(t, mV(v), model.calcium_uM(s));
    };
    if (std::abs(run.start_time - onset) < 1e-9 * period)
      observe(run.start_time, cell.potential(), cell.state().data());

    const auto write_row = [&](const double time) {
      std::vector<IO::Column> row = {
        {"time", "ms", time},
        {"beat", "-", static_cast<double>(beat_of(time))},
        {"potential_mV", "mV", mV(cell.potential())},
        {"calcium_uM", "µM", model.calcium_uM(cell.state().data())}};
      if (with_tension)
        row.push_back({"active_tension", "kPa", tension});
      results.append_timeseries(row);
    };

    const unsigned int n_steps = static_cast<unsigned int>(
      std::ceil((run.end_time - run.start_time) / run.time_step - 1e-9));
    write_row(run.start_time);
    for (unsigned int step = 1; step <= n_steps; ++step)
      {
        const double time =
          std::min(run.start_time + step * run.time_step, run.end_time);
        progress.update(step, time, "cell");
        cell.advance(time, observe);
        write_row(time);
        if (interrupted(comm))
          {
            logger.line("Interrupted: " + results.path() + " holds steps 0.." +
                        std::to_string(step) + ".");
            break;
          }
      }
    // (A beat that ends exactly at the end time was written by observe; a
    // beat cut short by the end time is not summarised.)
    std::ostringstream o;
    o << cell.n_steps() << " ARKode steps";
    logger.line(o.str());
    results.write_statistics(
      {{"arkode_steps", "-", static_cast<double>(cell.n_steps())}});
    logger.line("Wrote " + results.path());
  }
} // namespace systole
