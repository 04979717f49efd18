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
  namespace
  {
    using namespace Electrophysiology;

    /// A calcium-driven tension model (Active tension / Model = Land) at the
    /// fixed stretch Cell / Fibre stretch: one implicit step per cell step,
    /// driven by the calcium at its end. The prescribed models (Bestel) need
    /// an activation time and are not run here.
    class TensionAtStretch
    {
    public:
      TensionAtStretch(const dealii::ParameterHandler &prm,
                       const IonicModel               &model,
                       const SingleCell::Pacing       &pacing,
                       const RunParameters            &run)
        : model(model)
        , stretch(pacing.stretch)
        , tension_model(Materials::create_tension_model(
            prm,
            pacing.period > 0 ? pacing.period : std::max(run.end_time, 1.0)))
        , enabled(tension_model &&
                  tension_model->drive() == Materials::TensionDrive::calcium)
        , state(enabled ? tension_model->n_states() : 0)
        , trial(state.size())
        , time(run.start_time)
      {
        if (enabled)
          tension_model->initial_state(state.data());
      }

      /// One step to @p t with the cell state @p s at its end.
      void
      step(const double t, const double *s)
      {
        if (!enabled || !(t > time))
          return;
        Materials::TensionInput in;
        in.time             = t;
        in.time_step        = t - time;
        in.calcium          = model.calcium_uM(s);
        in.stretch          = stretch;
        in.previous_stretch = stretch;
        Materials::TensionOutput out;
        tension_model->step(state.data(), in, trial.data(), out);
        state.swap(trial);
        tension = out.tension;
        time    = t;
        peak    = std::max(peak, tension);
      }

      const IonicModel                              &model;
      const double                                   stretch;
      const std::unique_ptr<Materials::TensionModel> tension_model;
      const bool                                     enabled;
      std::vector<double>                            state, trial;
      double                                         time;
      double                                         tension = 0; ///< [kPa]
      double peak = 0; ///< of the beat so far [kPa]
    };

    /// The single-cell run: the time loop, the beats' summaries (beat k is
    /// [k P, (k + 1) P), measured from its stimulus onset on) and rows.
    class CellRun
    {
    public:
      explicit CellRun(const RunInputs &in)
        : run(in.run)
        , logger(in.logger)
        , comm(in.comm)
        , ep(Parameters::parse(in.prm))
        , pacing(SingleCell::Pacing::parse(in.prm))
        , model(*ep.ionic_model)
        , cell(model, ep, pacing, in.run.start_time)
        , tension(in.prm, model, pacing, in.run)
        , results(in.run.output_directory, in.parameter_text, in.comm)
        , period(pacing.period > 0 ? pacing.period
                                   : std::max(in.run.end_time, 1.0))
        , beat(beat_of(in.run.start_time))
        , onset(beat * period + pacing.start)
      {}

      void
      run_loop();

    private:
      long
      beat_of(const double t) const
      {
        return static_cast<long>(std::floor(t / period + 1e-9));
      }

      double
      mV(const double v) const
      {
        return model.to_mV(v);
      }

      void
      log_start() const;
      void
      write_summary();
      void
      observe(const double t, const double v, const double *s);
      void
      write_row(const double time);

      const RunParameters     &run;
      Logger                  &logger;
      const MPI_Comm           comm;
      const Parameters         ep;
      const SingleCell::Pacing pacing;
      const IonicModel        &model;
      SingleCell               cell;
      TensionAtStretch         tension;
      IO::ResultsFile          results;
      const double             period;
      long                     beat;
      double                   onset;
      bool                     measuring = false;
      ActionPotentialRecorder  recorder;
      unsigned long            steps_at_beat_start = 0;
    };

    void
    CellRun::log_start() const
    {
      std::ostringstream o;
      o << IO::code_version() << ": problem '" << run.problem << "', "
        << model.name() << " (" << model.n_states() << " states, "
        << model.n_gates() << " gates by Rush-Larsen)\n  step " << ep.time_step
        << " ms, paced every " << pacing.period << " ms";
      if (tension.enabled)
        o << "; " << tension.tension_model->name() << " tension at stretch "
          << pacing.stretch;
      logger.line(o.str());
    }

    void
    CellRun::write_summary()
    {
      const BeatSummary       s   = recorder.summary();
      std::vector<IO::Column> row = {
        {"beat", "-", static_cast<double>(beat)},
        {"start_time", "ms", beat * period},
        {"resting_potential_mV", "mV", s.resting_potential_mV},
        {"peak_potential_mV", "mV", s.peak_potential_mV},
        {"APD90_ms", "ms", s.APD90_ms},
        {"peak_calcium_uM", "µM", s.peak_calcium_uM}};
      if (tension.enabled)
        row.push_back({"peak_tension_kPa", "kPa", tension.peak});
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
      if (tension.enabled)
        o << ", peak tension " << tension.peak << " kPa";
      logger.line(o.str());
    }

    /// Every ARKode step: the beat's samples from its stimulus onset (a step
    /// boundary) on, and a summary row when a beat ends.
    void
    CellRun::observe(const double t, const double v, const double *s)
    {
      tension.step(t, s);
      if (beat_of(t) > beat)
        {
          if (measuring)
            write_summary();
          tension.peak        = tension.tension;
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
    }

    void
    CellRun::write_row(const double time)
    {
      std::vector<IO::Column> row = {
        {"time", "ms", time},
        {"beat", "-", static_cast<double>(beat_of(time))},
        {"potential_mV", "mV", mV(cell.potential())},
        {"calcium_uM", "µM", model.calcium_uM(cell.state().data())}};
      if (tension.enabled)
        row.push_back({"active_tension", "kPa", tension.tension});
      results.append_timeseries(row);
    }

    void
    CellRun::run_loop()
    {
      log_start();
      Progress   progress(logger,
                        Progress::parse_mode(run.progress),
                        run.start_time,
                        run.end_time);
      const auto observer = [this](const double  t,
                                   const double  v,
                                   const double *s) { observe(t, v, s); };
      if (std::abs(run.start_time - onset) < 1e-9 * period)
        observe(run.start_time, cell.potential(), cell.state().data());

      const unsigned int n_steps = static_cast<unsigned int>(
        std::ceil((run.end_time - run.start_time) / run.time_step - 1e-9));
      write_row(run.start_time);
      for (unsigned int step = 1; step <= n_steps; ++step)
        {
          const double time =
            std::min(run.start_time + step * run.time_step, run.end_time);
          progress.update(step, time, "cell");
          cell.advance(time, observer);
          write_row(time);
          if (interrupted(comm))
            {
              logger.line("Interrupted: " + results.path() +
                          " holds steps 0.." + std::to_string(step) + ".");
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
  } // namespace

  void
  run_cell_problem(const RunInputs &in)
  {
    CellRun(in).run_loop();
  }
} // namespace systole
