#include "simulation/electrophysiology_run.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/numerics/data_out.h>

#include "base/interrupt.h"
#include "base/logger.h"
#include "electrophysiology/monodomain.h"
#include "fibres/fibre_field.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "io/checkpoint.h"
#include "io/checkpoint_format.h"
#include "io/results_file.h"
#include "simulation/ecg_columns.h"
#include "simulation/electrical_activation.h"
#include "simulation/parameters.h"
#include "simulation/purkinje_output.h"
#include "simulation/run_checkpoint.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/serialization/vector.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <iomanip>
#include <sstream>

namespace systole
{
  namespace
  {
    /// The ECG samples of a checkpoint, the 12 leads flattened.
    void
    save_ecg(boost::archive::text_oarchive &archive, const EcgBeat &ecg)
    {
      std::vector<double> leads;
      for (const auto &sample : ecg.leads)
        leads.insert(leads.end(), sample.begin(), sample.end());
      archive &ecg.times &leads;
    }

    void
    load_ecg(boost::archive::text_iarchive &archive, EcgBeat &ecg)
    {
      std::vector<double> leads;
      archive &ecg.times &leads;
      AssertThrow(leads.size() == 12 * ecg.times.size(),
                  dealii::ExcMessage("The checkpoint's ECG samples are "
                                     "incomplete."));
      ecg.leads.resize(ecg.times.size());
      for (unsigned int k = 0; k < ecg.times.size(); ++k)
        std::copy(leads.begin() + 12 * k,
                  leads.begin() + 12 * (k + 1),
                  ecg.leads[k].begin());
    }

    /// The electrophysiology problem: the monodomain (or eikonal) model on
    /// the Geometry mesh, its rows, fields and checkpoints.
    class ElectrophysiologyRun
    {
    public:
      ElectrophysiologyRun(const dealii::ParameterHandler &prm,
                           const RunParameters            &run,
                           Logger                         &logger,
                           const MPI_Comm                  comm);

      /// The results file of the run @p in: a new one, or the one of the
      /// checkpoint with the state of the run at its step.
      void
      open_results(const RunInputs &in);

      /// The time loop from the first step on (to the end, or to an
      /// interruption).
      void
      time_loop();

      /// The activation summary, the log of the costs and the statistics.
      void
      finish();

    private:
      void
      log_start();
      void
      write_row(const unsigned int step, const double time);
      void
      write_checkpoint(const unsigned int step);
      void
      write_summary(const Electrophysiology::ActivationSummary &summary,
                    const std::vector<double> &activation_times);
      void
      log_cost(const Electrophysiology::Statistics &stats,
               const double                         seconds);

      const RunParameters                                 &run;
      Logger                                              &logger;
      const MPI_Comm                                       comm;
      const Geometry::Parameters                           geometry;
      const Electrophysiology::Parameters                  params;
      const std::string                                    all_entries;
      IO::CheckpointStore                                  store;
      const std::string                                    checkpoint;
      const Geometry::DistributedMesh                      mesh;
      const Geometry::CellKind                             kind;
      const std::unique_ptr<dealii::Mapping<3>>            mapping;
      const std::unique_ptr<Electrophysiology::Monodomain> ep;
      std::vector<dealii::Point<3>>                        probe_points;
      Electrophysiology::Statistics                        last;
      /// The 12 leads of every row (the biomarkers at the end).
      EcgBeat                               ecg;
      std::unique_ptr<IO::ResultsFile>      results;
      std::unique_ptr<RunCheckpointer>      checkpointer;
      unsigned int                          first_step = 1;
      const unsigned int                    n_steps;
      std::chrono::steady_clock::time_point last_checkpoint;
    };

    // Checkpoints (hexahedra): the mesh with the EP state (ep.mesh), the
    // small state (the rows, the step, the ECG samples, the integrator's).
    // Hexahedra on p4est, tetrahedra fully distributed.
    ElectrophysiologyRun::ElectrophysiologyRun(
      const dealii::ParameterHandler &prm,
      const RunParameters            &run,
      Logger                         &logger,
      const MPI_Comm                  comm)
      : run(run)
      , logger(logger)
      , comm(comm)
      , geometry(Geometry::Parameters::parse(prm, run.parameter_directory))
      , params(Electrophysiology::Parameters::parse(prm))
      , all_entries(checkpoint_entries(prm))
      , store(run.output_directory, comm)
      , checkpoint(resume_checkpoint(run, store, all_entries, logger, comm))
      , mesh(Geometry::create_distributed_mesh(geometry,
                                               comm,
                                               checkpoint.empty()
                                                 ? ""
                                                 : checkpoint + "/ep.mesh"))
      , kind(*mesh.tria)
      , mapping(kind.mapping(*mesh.tria, run.mapping_degree))
      , ep(create_monodomain(
          {prm, run, params, geometry, mesh, *mapping, logger, run.start_time}))
      , n_steps(static_cast<unsigned int>(
          std::ceil((run.end_time - run.start_time) / run.time_step - 1e-9)))
    {
      log_start();
      for (const auto &p : params.probes)
        probe_points.push_back(p.position);
    }

    void
    ElectrophysiologyRun::log_start()
    {
      std::ostringstream o;
      o << IO::code_version() << ": problem '" << run.problem << "', "
        << mesh.tria->n_global_active_cells() << " " << kind.name() << ", "
        << (kind.simplex() ? "P" : "Q") << params.degree << ", " << ep->n_dofs()
        << " DOFs, " << dealii::Utilities::MPI::n_mpi_processes(comm)
        << " rank(s)\n  " << params.ionic_model->name();
      logger.line(o.str());
    }

    void
    ElectrophysiologyRun::open_results(const RunInputs &in)
    {
      std::unique_ptr<IO::StateReader> state_in;
      unsigned int                     step = 0;
      results = systole::open_results(checkpoint, in, state_in, &step);
      checkpointer =
        std::make_unique<RunCheckpointer>(RunCheckpointerParts{store,
                                                               *results,
                                                               *mesh.tria,
                                                               "ep.mesh",
                                                               all_entries,
                                                               run,
                                                               logger,
                                                               comm});
      if (!state_in)
        {
          write_purkinje(*results, ep->purkinje(), comm);
          return;
        }
      auto    &archive = state_in->archive();
      archive &last.steps &last.linear_iterations;
      load_ecg(archive, ecg);
      ep->load_checkpoint(archive);
      first_step = step + 1;
    }

    void
    ElectrophysiologyRun::write_row(const unsigned int step, const double time)
    {
      const auto              now = ep->statistics();
      std::vector<IO::Column> row = {
        {"time", "ms", time},
        {"step", "-", static_cast<double>(step)},
        {"activated_fraction", "-", ep->activated_fraction()},
        {"arkode_steps", "-", static_cast<double>(now.steps - last.steps)},
        {"linear_iterations",
         "-",
         static_cast<double>(now.linear_iterations - last.linear_iterations)}};
      last              = now;
      const auto values = ep->values_at_points(probe_points);
      for (unsigned int i = 0; i < probe_points.size(); ++i)
        row.push_back(
          {params.probes[i].name + "_potential", "mV", values.potential[i]});
      if (params.ionic_model->has_calcium())
        for (unsigned int i = 0; i < probe_points.size(); ++i)
          row.push_back({params.probes[i].name + "_calcium_uM",
                         "µM",
                         values.calcium_uM[i]});
      if (ep->has_ecg())
        {
          const auto leads = ep->ecg_leads();
          append_ecg_columns(leads, row);
          ecg.add(time, leads);
        }
      results->append_timeseries(row);

      if (run.field_output_interval > 0 &&
          (step % run.field_output_interval == 0 || step == n_steps))
        {
          dealii::DataOut<3> data_out;
          ep->attach_output(data_out);
          data_out.build_patches(*mapping,
                                 kind.output_subdivisions(params.degree));
          results->write_fields(data_out, step, time);
        }
    }

    /// The small state after the rows and the step: the statistics, the
    /// ECG samples, the integrator's; the EP state on the mesh (ep.mesh).
    void
    ElectrophysiologyRun::write_checkpoint(const unsigned int step)
    {
      checkpointer->write(
        step,
        [&](boost::archive::text_oarchive &archive, const std::string &) {
          archive &last.steps &last.linear_iterations;
          save_ecg(archive, ecg);
          ep->prepare_checkpoint(archive);
        },
        [&]() { ep->finish_checkpoint(); });
      last_checkpoint = std::chrono::steady_clock::now();
    }

    void
    ElectrophysiologyRun::time_loop()
    {
      Progress progress(logger,
                        Progress::parse_mode(run.progress),
                        run.start_time,
                        run.end_time);
      last_checkpoint = std::chrono::steady_clock::now();
      if (checkpoint.empty())
        write_row(0, run.start_time);
      for (unsigned int step = first_step; step <= n_steps; ++step)
        {
          const double time =
            std::min(run.start_time + step * run.time_step, run.end_time);
          progress.update(step, time, "electrophysiology");
          ep->advance(time);
          write_row(step, time);
          const bool stop = interrupted(comm);
          if (checkpoint_due(run, step, last_checkpoint, comm) ||
              (stop && !kind.simplex()))
            write_checkpoint(step);
          // Test hook (the checkpoint tests): SIGKILL after this step.
          if (run.test_kill_after_step == static_cast<long>(step))
            std::raise(SIGKILL);
          if (stop)
            {
              logger.line("Interrupted: " + results->path() +
                          " holds steps 0.." + std::to_string(step) + ".");
              break;
            }
        }
    }

    /// The activation map: summary over the volume and at the probes; the
    /// ECG's biomarkers over the run (its first beat with a Stimulus
    /// period), in the run's clock from its start.
    void
    ElectrophysiologyRun::write_summary(
      const Electrophysiology::ActivationSummary &summary,
      const std::vector<double>                  &activation_times)
    {
      const auto              stats = ep->statistics();
      std::vector<IO::Column> row   = {
          {"activated_fraction", "-", summary.activated_fraction},
          {"first_activation_time", "ms", summary.first},
          {"last_activation_time", "ms", summary.last},
          {"total_activation_time", "ms", summary.total},
          {"activation_time_90", "ms", summary.fraction_time},
          {"n_dofs", "-", static_cast<double>(ep->n_dofs())},
          {"arkode_steps", "-", static_cast<double>(stats.steps)},
          {"linear_solves", "-", static_cast<double>(stats.linear_solves)},
          {"linear_iterations",
           "-",
           static_cast<double>(stats.linear_iterations)}};
      for (unsigned int i = 0; i < probe_points.size(); ++i)
        row.push_back({params.probes[i].name + "_activation_time",
                       "ms",
                       activation_times[i]});
      if (ep->has_ecg())
        ecg.append_biomarkers(run.start_time,
                              params.stimulus_period > 0
                                ? run.start_time + params.stimulus_period
                                : run.end_time,
                              params.ecg.threshold,
                              row);
      results->append_summary(row);
    }

    void
    ElectrophysiologyRun::log_cost(const Electrophysiology::Statistics &stats,
                                   const double                         seconds)
    {
      std::ostringstream o;
      o << std::setprecision(4) << "EP cost: " << seconds << " s in "
        << stats.steps << " ARKode steps, "
        << (stats.steps > 0 ? 1e6 * seconds / (stats.steps * ep->n_dofs())
                            : 0.0)
        << " us per step per DOF; " << stats.linear_solves << " stage solves, "
        << (stats.linear_solves > 0
              ? double(stats.linear_iterations) / stats.linear_solves
              : 0.0)
        << " CG iterations per solve, " << stats.amg_setups << " AMG set-up(s)";
      if (stats.mass_solves > 0)
        o << "; " << stats.mass_solves << " consistent-mass solves, "
          << double(stats.mass_iterations) / stats.mass_solves
          << " CG iterations per solve";
      logger.line(o.str());
    }

    void
    ElectrophysiologyRun::finish()
    {
      const auto summary = ep->activation_summary(0.9);
      const auto values  = ep->values_at_points(probe_points);
      write_summary(summary, values.activation_time);

      std::ostringstream o;
      o << std::setprecision(4)
        << "Activation: " << 100 * summary.activated_fraction
        << " % of the volume active, first " << summary.first << " ms, last "
        << summary.last << " ms, 90 % at " << summary.fraction_time << " ms";
      for (unsigned int i = 0; i < probe_points.size(); ++i)
        o << "; " << params.probes[i].name << " " << values.activation_time[i]
          << " ms";
      logger.line(o.str());
      const auto   stats   = ep->statistics();
      const double seconds = dealii::Utilities::MPI::max(stats.seconds, comm);
      log_cost(stats, seconds);
      results->write_statistics(
        {{"n_dofs", "-", static_cast<double>(ep->n_dofs())},
         {"n_cells",
          "-",
          static_cast<double>(mesh.tria->n_global_active_cells())},
         {"n_ranks",
          "-",
          static_cast<double>(dealii::Utilities::MPI::n_mpi_processes(comm))},
         {"ep_seconds", "s", seconds},
         {"ep_steps", "-", static_cast<double>(stats.steps)},
         {"linear_solves", "-", static_cast<double>(stats.linear_solves)},
         {"linear_iterations",
          "-",
          static_cast<double>(stats.linear_iterations)},
         {"amg_setups", "-", static_cast<double>(stats.amg_setups)},
         {"mass_solves", "-", static_cast<double>(stats.mass_solves)},
         {"mass_iterations", "-", static_cast<double>(stats.mass_iterations)}});
      logger.line("Wrote " + results->path());
    }
  } // namespace


  void
  run_electrophysiology_problem(const RunInputs &in)
  {
    ElectrophysiologyRun ep_run(in.prm, in.run, in.logger, in.comm);
    ep_run.open_results(in);
    ep_run.time_loop();
    ep_run.finish();
  }
} // namespace systole
