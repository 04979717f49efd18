#include "simulation/elastodynamics.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"
#include "base/interrupt.h"
#include "base/logger.h"
#include "base/units.h"
#include "io/checkpoint.h"
#include "io/checkpoint_format.h"
#include "io/results_file.h"
#include "mechanics/problem.h"
#include "simulation/load_curves.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"
#include "simulation/run_checkpoint.h"

#include "postprocess/manager.h"
#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/serialization/vector.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>

namespace systole
{
  void
  declare_elastodynamics_parameters(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Elastodynamics");
    LoadCurveParameters::declare(prm,
                                 "Pressure",
                                 "kPa (1 mmHg = 0.133322 kPa)");
    LoadCurveParameters::declare(prm, "Active stress", "kPa");
    prm.leave_subsection();
  }

  void
  validate_elastodynamics_parameters(const dealii::ParameterHandler &prm)
  {
    LoadCurveParameters::create(prm, "Pressure");
    LoadCurveParameters::create(prm, "Active stress");
    if (prm.get("Problem") != "elastodynamics")
      return;
    AssertThrow(prm.get_double({"Mechanics"}, "Density") > 0.0,
                dealii::ExcMessage("Problem = elastodynamics needs Mechanics / "
                                   "Density > 0 (kg/m^3; 1000 for tissue)."));
  }

  namespace
  {
    /// The state of the time integration at the last accepted step.
    struct AcceptedState
    {
      unsigned int step     = 0;
      double       time     = 0.0; ///< [ms]
      double       pressure = 0.0; ///< [kPa]
      double       tension  = 0.0; ///< [kPa]
      /// The energy dissipated and the work of the loads since the start,
      /// by the trapezoidal rule over the steps [uJ].
      double                 dissipated = 0.0, work = 0.0;
      Mechanics::PowerReport powers; ///< of the accepted state
      SolveCounts            counts;
      /// The step the next one tries [ms] (0: the nominal one), and whether
      /// the last accepted solve was easy.
      double sub_step  = 0.0;
      bool   last_easy = false;

      /// Reads or writes the state (a checkpoint's).
      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &step &time &pressure &tension &dissipated &work;
        archive &powers.dissipation &powers.loads;
        archive &counts.steps &counts.cuts &counts.newton &counts.chord;
        archive &counts.linear &counts.solves &sub_step &last_easy;
      }
    };

    /// A time integration of the mechanics (generalized alpha) under the
    /// loads of subsection Elastodynamics, writing a row per accepted step.
    class TimeIntegration
    {
    public:
      TimeIntegration(const RunParameters  &run,
                      MechanicsModel       &model,
                      LoadCurve            &pressure_curve,
                      LoadCurve            &tension_curve,
                      Postprocess::Manager &postprocess,
                      IO::ResultsFile      &results,
                      Logger               &logger)
        : run(run)
        , model(model)
        , problem(*model.problem)
        , pressure_curve(pressure_curve)
        , tension_curve(tension_curve)
        , postprocess(postprocess)
        , results(results)
        , logger(logger)
      {}

      /// The loads at the start time (the ODE curves integrate from t = 0),
      /// the dynamic state at rest and the first row.
      void
      start();

      /// The state of a checkpoint: the time integration's, the load
      /// curves', the postprocessors' and the mechanics' (after the rows and
      /// the step of the results file, see RunCheckpointer).
      void
      save(boost::archive::text_oarchive &archive);
      void
      load(boost::archive::text_iarchive &archive);

      /// Called after each accepted step with whether the run stops there
      /// (interrupted): writes the checkpoints.
      std::function<void(unsigned int step, bool stopping)> after_step;

      /// Steps to the end time: a failed solve halves the step (at most
      /// Mechanics / Max step cuts times below the nominal one), an easy one
      /// doubles it back. Stops early when interrupted.
      void
      run_to_end(Progress &progress, const MPI_Comm comm);

      /// What was counted.
      const SolveCounts &
      counts() const
      {
        return state.counts;
      }

    private:
      /// Solves the step to @p next; false (the problem restored, the step
      /// counted as a cut) when Newton fails, throwing once @p can_cut is
      /// false.
      bool
      try_step(const double next,
               const double dt,
               const bool   can_cut,
               std::string &failure);

      /// Accepts the solved step to @p next (of length @p dt) with the loads
      /// @p pressure and @p tension.
      void
      accept(const Mechanics::NewtonReport &report,
             const double                   next,
             const double                   dt,
             const double                   pressure,
             const double                   tension);

      /// p on every pressure part (none without a pressure boundary).
      dealii::Vector<double>
      pressures_of(const double p) const
      {
        dealii::Vector<double> pressures(
          model.params.pressure_boundaries().size());
        for (auto &value : pressures)
          value = p;
        return pressures;
      }

      /// The row of the accepted state (@p report: its solve over @p
      /// time_step).
      void
      write_row(const Mechanics::NewtonReport &report, const double time_step);

      const RunParameters  &run;
      MechanicsModel       &model;
      Mechanics::Problem   &problem;
      LoadCurve            &pressure_curve, &tension_curve;
      Postprocess::Manager &postprocess;
      IO::ResultsFile      &results;
      Logger               &logger;
      AcceptedState         state;
    };

    void
    TimeIntegration::start()
    {
      state.time = run.start_time;
      pressure_curve.accept(state.time);
      tension_curve.accept(state.time);
      state.pressure = pressure_curve.value(state.time);
      state.tension  = tension_curve.value(state.time);
      problem.start_dynamics(state.pressure, state.tension);
      problem.save();
      state.powers =
        problem.accepted_powers(pressures_of(state.pressure), state.tension);
      write_row({}, 0.0);
    }

    void
    TimeIntegration::save(boost::archive::text_oarchive &archive)
    {
      archive            &state;
      std::vector<double> curves[2] = {pressure_curve.state(),
                                       tension_curve.state()};
      archive            &curves[0] & curves[1];
      // The postprocessors' reference values and peaks.
      std::vector<double> postprocessing = postprocess.state();
      archive            &postprocessing;
      problem.prepare_checkpoint(archive);
    }

    void
    TimeIntegration::load(boost::archive::text_iarchive &archive)
    {
      archive            &state;
      std::vector<double> curves[2];
      archive            &curves[0] & curves[1];
      pressure_curve.set_state(curves[0]);
      tension_curve.set_state(curves[1]);
      std::vector<double> postprocessing;
      archive            &postprocessing;
      postprocess.set_state(postprocessing);
      problem.load_checkpoint(archive);
    }

    void
    TimeIntegration::run_to_end(Progress &progress, const MPI_Comm comm)
    {
      const double nominal = run.time_step;
      const double smallest =
        nominal / std::pow(2.0, model.params.max_step_cuts);
      double &sub_step = state.sub_step;
      if (sub_step <= 0.0)
        sub_step = nominal;
      while (state.time < run.end_time - 1e-9 * nominal)
        {
          const double dt = std::min(sub_step, run.end_time - state.time);
          progress.update(state.step, state.time, "elastodynamics");
          std::string failure;
          if (!try_step(state.time + dt,
                        dt,
                        sub_step > smallest * 1.5,
                        failure))
            {
              sub_step *= 0.5;
              logger.stream() << "  Newton failed (" << failure
                              << "); cutting the time step to " << sub_step
                              << " ms" << std::endl;
              continue;
            }
          // Back towards the nominal step after an easy one.
          if (sub_step < nominal && state.last_easy)
            sub_step = std::min(2.0 * sub_step, nominal);
          const bool stop = interrupted(comm);
          if (after_step)
            after_step(state.step, stop);
          if (stop)
            {
              logger.line("Interrupted: " + results.path() +
                          " holds steps 0.." + std::to_string(state.step) +
                          "; continue with systole --resume " +
                          run.output_directory);
              break;
            }
        }
    }

    bool
    TimeIntegration::try_step(const double next,
                              const double dt,
                              const bool   can_cut,
                              std::string &failure)
    {
      const double next_pressure = pressure_curve.value(next);
      const double next_tension  = tension_curve.value(next);
      logger.stream() << "  Time step " << state.step + 1 << ": t = " << next
                      << " ms, dt = " << dt << " ms, p = " << next_pressure
                      << " kPa, active stress = " << next_tension << " kPa"
                      << std::endl;
      problem.set_time_step(dt);
      Mechanics::NewtonReport report;
      try
        {
          report = problem.solve(next_pressure, next_tension);
        }
      catch (const ExcNewtonDidNotConverge &e)
        {
          problem.restore();
          ++state.counts.cuts;
          AssertThrow(
            can_cut,
            dealii::ExcMessage(
              "The elastodynamics did not converge at t = " +
              dealii::Utilities::to_string(next) + " ms with a step of " +
              dealii::Utilities::to_string(dt) + " ms after " +
              std::to_string(model.params.max_step_cuts) + " step cuts (" +
              one_line_message(e) +
              "). The loads may be too large for the material, or the mesh "
              "too coarse; the results file holds the " +
              std::to_string(state.step) + " converged steps."));
          failure = one_line_message(e);
          return false;
        }
      accept(report, next, dt, next_pressure, next_tension);
      state.last_easy = report.easy();
      return true;
    }

    void
    TimeIntegration::accept(const Mechanics::NewtonReport &report,
                            const double                   next,
                            const double                   dt,
                            const double                   pressure,
                            const double                   tension)
    {
      problem.accept_time_step(pressure, tension);
      problem.save();
      pressure_curve.accept(next);
      tension_curve.accept(next);
      // The energy flows by the trapezoidal rule over the step.
      const auto next_powers =
        problem.accepted_powers(pressures_of(pressure), tension);
      state.dissipated +=
        0.5 * dt * (state.powers.dissipation + next_powers.dissipation);
      state.work += 0.5 * dt * (state.powers.loads + next_powers.loads);
      state.powers   = next_powers;
      state.time     = next;
      state.pressure = pressure;
      state.tension  = tension;
      ++state.step;
      SolveCounts &counts = state.counts;
      counts.steps        = state.step;
      counts.newton += report.iterations;
      counts.chord += report.reused_iterations;
      counts.linear += report.linear_iterations;
      counts.solves += report.iterations + report.reused_iterations;
      write_row(report, dt);
    }

    void
    TimeIntegration::write_row(const Mechanics::NewtonReport &report,
                               const double                   time_step)
    {
      std::vector<IO::Column> row = {
        {"step", "-", static_cast<double>(state.step)},
        {"time", "ms", state.time},
        {"time_step", "ms", time_step},
        {"pressure", "kPa", state.pressure},
        {"pressure_mmHg", "mmHg", Units::kPa_to_mmHg(state.pressure)},
        {"active_tension", "kPa", state.tension}};
      MechanicsModel::append_solve_columns(report, row);
      model.append_shape_columns(row);
      // Energies [µJ = kPa mm^3]: kinetic + strain + support + dissipated =
      // work of the loads + the initial stored energy, to the scheme's
      // accuracy.
      row.push_back({"kinetic_energy", "uJ", problem.kinetic_energy()});
      row.push_back({"strain_energy", "uJ", problem.strain_energy()});
      row.push_back({"support_energy", "uJ", problem.support_energy()});
      row.push_back({"dissipated_energy", "uJ", state.dissipated});
      row.push_back({"load_work", "uJ", state.work});
      model.write_step(run,
                       state.step,
                       state.time,
                       state.time >= run.end_time - 1e-9,
                       row,
                       postprocess,
                       results);
    }
    /// The checks of the model a time integration needs (a density, a part
    /// for a pressure load).
    void
    check_elastodynamics_model(const MechanicsModel           &model,
                               const dealii::ParameterHandler &prm,
                               const RunParameters            &run)
    {
      const auto &params = model.params;
      AssertThrow(params.density > 0.0,
                  dealii::ExcMessage("Problem = elastodynamics needs "
                                     "Mechanics / Density > 0 (kg/m^3)."));
      AssertThrow(
        !params.pressure_boundaries().empty() ||
          LoadCurveParameters::create(prm, "Pressure")->value(run.start_time) ==
            0.0,
        dealii::ExcMessage(
          "Problem = elastodynamics: Elastodynamics / Pressure is set but "
          "Mechanics / Pressure boundary is empty: name the boundary part "
          "that carries it."));
    }

    /// What runs after each accepted step: the checkpoint when due (or when
    /// the run stops) and the test hook Output / Test kill after step.
    std::function<void(unsigned int, bool)>
    checkpoint_writer(RunCheckpointer     &checkpointer,
                      TimeIntegration     &integration,
                      const RunParameters &run,
                      Mechanics::Problem  &problem,
                      const MPI_Comm       comm)
    {
      auto last = std::make_shared<std::chrono::steady_clock::time_point>(
        std::chrono::steady_clock::now());
      return [&, last, comm](const unsigned int step, const bool stopping) {
        if (stopping || checkpoint_due(run, step, *last, comm))
          {
            checkpointer.write(
              step,
              [&](boost::archive::text_oarchive &archive, const std::string &) {
                integration.save(archive);
              },
              [&]() { problem.finish_checkpoint(); });
            *last = std::chrono::steady_clock::now();
          }
        // Test hook (the checkpoint tests): SIGKILL after this step.
        if (run.test_kill_after_step == static_cast<long>(step))
          std::raise(SIGKILL);
      };
    }
  } // namespace

  void
  run_elastodynamics_problem(const RunInputs &in)
  {
    // Checkpoints: the mesh with the mechanics' cell data (mechanics.mesh),
    // the small state (rows, step, time integration, curves, mechanics).
    std::ostringstream entries;
    in.prm.print_parameters(entries, dealii::ParameterHandler::ShortPRM);
    const std::string   all_entries = entries.str();
    IO::CheckpointStore store(in.run.output_directory, in.comm);
    const std::string   checkpoint =
      resume_checkpoint(in.run, store, all_entries, in.logger, in.comm);
    MechanicsModel model(in.prm,
                         in.run,
                         in.logger,
                         in.comm,
                         checkpoint.empty() ? ""
                                            : checkpoint + "/mechanics.mesh");
    check_elastodynamics_model(model, in.prm, in.run);
    in.logger.line(model.banner(in.run));
    const auto pressure_curve = LoadCurveParameters::create(in.prm, "Pressure");
    const auto tension_curve =
      LoadCurveParameters::create(in.prm, "Active stress");

    std::unique_ptr<IO::StateReader> state_in;
    const auto           results_file = open_results(checkpoint, in, state_in);
    IO::ResultsFile     &results      = *results_file;
    Postprocess::Manager postprocess  = model.postprocessors(in.prm, in.logger);
    Progress             progress(in.logger,
                      Progress::parse_mode(in.run.progress),
                      in.run.start_time,
                      in.run.end_time);
    TimeIntegration      integration(in.run,
                                model,
                                *pressure_curve,
                                *tension_curve,
                                postprocess,
                                results,
                                in.logger);
    if (state_in)
      integration.load(state_in->archive());
    else
      integration.start();
    state_in.reset();
    RunCheckpointer checkpointer({store,
                                  results,
                                  model.tria,
                                  "mechanics.mesh",
                                  all_entries,
                                  in.run,
                                  in.logger,
                                  in.comm});
    integration.after_step = checkpoint_writer(checkpointer,
                                               integration,
                                               in.run,
                                               *model.problem,
                                               in.comm);
    integration.run_to_end(progress, in.comm);

    const SolveCounts &counts = integration.counts();
    model.write_solve_summary("time_steps", counts, postprocess, results);
    std::ostringstream o;
    o << counts.steps << " time steps (" << counts.cuts << " cuts), "
      << counts.newton << " Newton iterations, " << counts.chord
      << " chord iterations, " << counts.linear << " Krylov iterations";
    if (checkpointer.count > 0)
      o << "; " << checkpointer.count << " checkpoint(s), the last in "
        << checkpointer.list().front();
    in.logger.line(o.str());
    in.logger.line("Wrote " + results.path());
  }
} // namespace systole
