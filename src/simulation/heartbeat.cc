#include "simulation/heartbeat.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"
#include "base/interrupt.h"
#include "base/logger.h"
#include "base/units.h"
#include "circulation/model_factory.h"
#include "circulation/parameters.h"
#include "electrophysiology/ionic_factory.h"
#include "electrophysiology/ionic_model.h"
#include "fibres/fibre_field.h"
#include "geometry/mesh.h"
#include "io/checkpoint.h"
#include "io/checkpoint_format.h"
#include "io/results_file.h"
#include "materials/bestel.h"
#include "materials/factory.h"
#include "materials/tension_factory.h"
#include "mechanics/problem.h"
#include "simulation/circulation_columns.h"
#include "simulation/ecg_columns.h"
#include "simulation/electrical_activation.h"
#include "simulation/heartbeat_stepper.h"
#include "simulation/heartbeat_writer.h"
#include "simulation/mechanics_model.h"
#include "simulation/mechanics_ventricles.h"
#include "simulation/parameters.h"
#include "simulation/purkinje_output.h"
#include "simulation/run_checkpoint.h"
#include "simulation/timer_section.h"

#include "postprocess/manager.h"
#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/serialization/array.hpp>
#include <boost/serialization/vector.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole
{
  namespace
  {
    using Vector = dealii::Vector<double>;


    /// Activation time of every quadrature point of the mechanics [ms].
    std::vector<std::vector<double>>
    activation_times(const Mechanics::Problem            &problem,
                     const Materials::Bestel::Parameters &params,
                     const Geometry::Plane               &base,
                     const MPI_Comm                       comm)
    {
      std::vector<std::vector<dealii::Point<3>>> points;
      problem.quadrature_points(points);
      // Height above the apex along the base normal, normalized to [0, 1].
      double     lowest = std::numeric_limits<double>::max(), highest = -lowest;
      const auto height = [&](const dealii::Point<3> &X) {
        return (X - base.point) * base.normal;
      };
      for (const auto &cell : points)
        for (const auto &X : cell)
          {
            lowest  = std::min(lowest, height(X));
            highest = std::max(highest, height(X));
          }
      lowest  = dealii::Utilities::MPI::min(lowest, comm);
      highest = dealii::Utilities::MPI::max(highest, comm);
      // The base normal's sign is arbitrary: the apex is the far end.
      const bool apex_is_low = std::abs(lowest) > std::abs(highest);
      // uniform: every point at 0 (a zero delay).
      const double delay =
        params.activation_map == "uniform" ? 0.0 : params.activation_delay;
      std::vector<std::vector<double>> times(points.size());
      for (unsigned int c = 0; c < points.size(); ++c)
        for (const auto &X : points[c])
          {
            double s = (height(X) - lowest) / (highest - lowest);
            if (!apex_is_low)
              s = 1.0 - s;
            times[c].push_back(delay * s);
          }
      return times;
    }


    /// The options of the tension model and the inertia the heartbeat
    /// supports; one clear message otherwise.
    void
    check_heartbeat_options(const dealii::ParameterHandler &prm,
                            const Materials::TensionModel  &tension_model)
    {
      AssertThrow(tension_model.drive() != Materials::TensionDrive::calcium ||
                    Electrophysiology::create_ionic_model(prm)->has_calcium(),
                  dealii::ExcMessage(
                    "Problem = heartbeat: Active tension / Model = " +
                    tension_model.name() +
                    " is driven by the intracellular calcium of the cell "
                    "model, and Electrophysiology / Ionic model = " +
                    prm.get({"Electrophysiology"}, "Ionic model") +
                    " has none: set it to ten Tusscher-Panfilov."));
      // Mechanics / Inertia: the dynamic mechanics.
      const bool inertia = prm.get_bool({"Mechanics"}, "Inertia");
      AssertThrow(!inertia || prm.get_double({"Mechanics"}, "Density") > 0.0,
                  dealii::ExcMessage(
                    "Problem = heartbeat: Mechanics / Inertia = true needs a "
                    "positive Mechanics / Density (kg/m^3; the tissue's is "
                    "1000)."));
    }

    /// The 3D ventricles of the mesh: "lv", or "lv" and "rv" of a
    /// biventricular mesh; the other chambers of the model are 0D.
    std::vector<std::string>
    ventricle_names_of(const Mechanics::Problem      &problem,
                       const Geometry::BoundaryNames &names)
    {
      AssertThrow(names.has("base"),
                  dealii::ExcMessage(
                    names.source() +
                    " has no boundary part named 'base': the "
                    "cavity volume is closed by the base plane."));
      bool on_endocardium = problem.n_cavities() > 0;
      for (const std::string &name : problem.cavity_names())
        on_endocardium =
          on_endocardium && name.find("endocardium") != std::string::npos;
      AssertThrow(on_endocardium,
                  dealii::ExcMessage(
                    "Problem = heartbeat needs Mechanics / Pressure boundary "
                    "= endocardium (the cavity pressure acts there; a part "
                    "whose name contains 'endocardium')."));
      const auto cavity_names = problem.cavity_names();
      if (cavity_names.size() == 1)
        return {"lv"};
      AssertThrow(cavity_names.size() == 2 && cavity_names[0].find("lv") == 0 &&
                    cavity_names[1].find("rv") == 0,
                  dealii::ExcMessage(
                    "Problem = heartbeat couples the left ventricle, or the "
                    "left and the right ventricle of a biventricular mesh; "
                    "Mechanics / Pressure boundary lists " +
                    std::to_string(cavity_names.size()) +
                    " parts. Name the endocardium, or lv_endocardium, "
                    "rv_endocardium in this order."));
      return {"lv", "rv"};
    }

    /// "unloaded cavity 101.2 mL" or "unloaded cavities lv ..., rv ...".
    std::string
    unloaded_text(const Vector                   &volumes,
                  const std::vector<std::string> &ventricle_names)
    {
      std::string text = "\n  unloaded cavit";
      text += volumes.size() == 1 ? "y" : "ies";
      for (unsigned int a = 0; a < volumes.size(); ++a)
        text +=
          (a == 0 ? " " : ", ") +
          (volumes.size() == 1 ? std::string() : ventricle_names[a] + " ") +
          dealii::Utilities::to_string(Units::mm3_to_mL(volumes[a])) + " mL";
      return text;
    }

    /// Where the activation times come from: the electrophysiology (@p ep)
    /// or a prescribed map (@p times per quadrature point); @p earliest the
    /// earliest activation [ms].
    struct Activation
    {
      std::unique_ptr<ElectricalActivation> ep;
      std::vector<std::vector<double>>      times;
      double earliest = std::numeric_limits<double>::max();
    };

    Activation
    create_activation(const dealii::ParameterHandler &prm,
                      const RunParameters            &run,
                      MechanicsModel                 &model,
                      const bool                      calcium_driven,
                      const double                    period,
                      const std::string              &checkpoint,
                      Logger                         &logger,
                      const MPI_Comm                  comm)
    {
      Activation a;
      const auto bestel = Materials::Bestel::Parameters::parse(prm);
      // (A calcium-driven tension always runs the electrophysiology.)
      if (calcium_driven || bestel.activation_map == "electrophysiology")
        {
          a.ep = std::make_unique<ElectricalActivation>(
            ElectricalActivation::Inputs{prm,
                                         run,
                                         model.geometry,
                                         model.tria,
                                         *model.problem,
                                         period,
                                         logger,
                                         comm,
                                         checkpoint});
          logger.line(a.ep->description());
          a.earliest = a.ep->earliest_stimulus();
          return a;
        }
      a.times = activation_times(
        *model.problem,
        bestel,
        Geometry::boundary_plane(model.tria, model.names.id("base"), "base"),
        comm);
      for (const auto &cell : a.times)
        for (const double t : cell)
          a.earliest = std::min(a.earliest, t);
      a.earliest = dealii::Utilities::MPI::min(a.earliest, comm);
      return a;
    }

    /// The initial state @p y0 (and cavity pressures @p p0): the 0D
    /// model's, with the 3D cavities unloaded (u = 0, p = 0) and their
    /// volumes @p unloaded_volumes, those of the mesh.
    void
    initial_state(const Circulation::Model &zero_d,
                  const Vector             &unloaded_volumes,
                  Vector                   &y0,
                  Vector                   &p0)
    {
      Vector no_pressures(zero_d.n_cavities());
      zero_d.initial_state(y0);
      unsigned int a = 0;
      for (const auto &cavity : zero_d.cavities())
        if (cavity.kind == Circulation::CavityKind::external)
          y0[cavity.volume_state] = unloaded_volumes[a++];
      zero_d.cavity_pressures({0.0, y0, no_pressures}, p0);
    }

    /// The parts of a running heartbeat whose state a checkpoint holds, in
    /// the order of the state file (after the rows of the results file and the
    /// step).
    struct HeartbeatState
    {
      Mechanics::Problem   &problem;
      ElectricalActivation *ep;
      HeartbeatStepper     &stepper;
      MechanicsVentricles  &ventricles;
      HeartbeatWriter      &writer;
      Postprocess::Manager &postprocess;

      void
      load(boost::archive::text_iarchive &archive)
      {
        problem.load_checkpoint(archive);
        if (ep != nullptr)
          ep->load_checkpoint(archive);
        stepper.load(archive);
        ventricles.serialize(archive);
        writer.serialize(archive);
        std::array<double, 5> beat_seconds;
        archive              &beat_seconds;
        writer.set_beat_seconds(beat_seconds);
        std::vector<double> postprocess_state;
        archive            &postprocess_state;
        postprocess.set_state(postprocess_state);
      }

      void
      save(boost::archive::text_oarchive &archive, const std::string &folder)
      {
        problem.prepare_checkpoint(archive);
        if (ep != nullptr)
          ep->save_checkpoint(archive, folder);
        stepper.save(archive);
        ventricles.serialize(archive);
        writer.serialize(archive);
        std::array<double, 5> beat_seconds = writer.beat_seconds();
        archive              &beat_seconds;
        // The postprocessors' reference values and peaks of the beat.
        std::vector<double> postprocess_state = postprocess.state();
        archive            &postprocess_state;
      }
    };

    /// stepper.run(writer); if a step fails for good, a checkpoint of the
    /// last accepted step first (where the run can write one), named in the
    /// one-line error.
    HeartbeatStepper::Statistics
    run_or_checkpoint(HeartbeatStepper &stepper,
                      HeartbeatWriter  &writer,
                      RunCheckpointer  &checkpointer)
    {
      try
        {
          return stepper.run(writer);
        }
      catch (const ExcStepFailed &e)
        {
          std::string where =
            " No checkpoint written (this run cannot write one).";
          if (writer.checkpoint)
            {
              writer.checkpoint(e.last_step);
              where = " Wrote a checkpoint of the last accepted step (" +
                      std::to_string(e.last_step) + ") to " +
                      checkpointer.list().front() +
                      "; resume from it (Output / Resume = true) with "
                      "Output / Solver log = on to see the failing solves.";
            }
          AssertThrow(false, dealii::ExcMessage(e.what() + where));
        }
      return {};
    }

    /// The log lines of the end of a run.
    void
    log_run(const HeartbeatStepper::Statistics &stats,
            const MechanicsVentricles          &ventricles,
            const ElectricalActivation         *ep,
            const RunCheckpointer              &checkpointer,
            const Mechanics::Problem           &problem,
            const double                        wall,
            Logger                             &logger)
    {
      std::ostringstream o;
      o << std::fixed << std::setprecision(2) << stats.n_beats << " beat(s)"
        << (stats.periodic ? ", periodic" : ", not yet periodic") << "; "
        << stats.n_steps << " steps, " << stats.n_solves << " coupled solves, "
        << stats.n_newton_iterations
        << " Newton iterations\n  solves redone: " << stats.n_error_rejections
        << " for the error, " << stats.n_event_rejections
        << " to locate valve events; " << stats.n_failures << " failed\n  "
        << ventricles.mechanics_seconds << " s in the mechanics ("
        << ventricles.tangent_iterations
        << " Newton iterations with a new tangent) of " << wall << " s";
      logger.line(o.str());
      if (checkpointer.count > 0)
        {
          std::ostringstream c;
          c << std::fixed << std::setprecision(3) << checkpointer.count
            << " checkpoint(s), " << checkpointer.seconds / checkpointer.count
            << " s per checkpoint, " << problem.n_dofs()
            << " mechanics DOFs;\n  the last in "
            << checkpointer.list().front();
          logger.line(c.str());
        }
      if (stats.interrupted)
        logger.line("Interrupted: continue with systole --resume " +
                    checkpointer.output_directory());
      if (ep == nullptr)
        return;
      const auto         s = ep->statistics();
      std::ostringstream e;
      e << std::fixed << std::setprecision(2)
        << "Electrophysiology: " << s.steps << " ARKode steps ("
        << static_cast<double>(s.steps) / std::max(1ul, stats.n_steps)
        << " per accepted mechanics step),\n  " << s.seconds
        << " s integrating, " << ep->transfer_seconds()
        << " s reading it at the mechanics points;\n  of the " << wall
        << " s of the cycle " << 100 * ventricles.ep_seconds / wall
        << " % in EP, " << 100 * ventricles.mechanics_seconds / wall
        << " % in the mechanics";
      logger.line(e.str());
    }

    /// The cost of the run as numbers in /statistics (scripts/bench reads
    /// them).
    void
    write_statistics(const HeartbeatStepper::Statistics &stats,
                     const MechanicsVentricles          &ventricles,
                     const ElectricalActivation         *ep,
                     const RunCheckpointer              &checkpointer,
                     const MechanicsModel               &model,
                     const double                        wall,
                     const dealii::TimerOutput          &timer,
                     IO::ResultsFile                    &results)
    {
      std::vector<std::pair<std::string, std::string>> texts;
      auto statistics = model.statistics(texts);
      for (const auto &[name, seconds] :
           timer.get_summary_data(dealii::TimerOutput::total_wall_time))
        statistics.push_back(
          {"timer: " + dealii::Utilities::replace_in_string(name, " / ", ": "),
           "s",
           seconds});
      const auto count = [](const auto n) { return static_cast<double>(n); };
      statistics.insert(
        statistics.end(),
        {{"beats", "-", count(stats.n_beats)},
         {"periodic", "-", stats.periodic ? 1.0 : 0.0},
         {"steps", "-", count(stats.n_steps)},
         {"coupled_solves", "-", count(stats.n_solves)},
         {"newton_iterations", "-", count(stats.n_newton_iterations)},
         {"linear_iterations", "-", count(ventricles.linear_iterations)},
         {"error_rejections", "-", count(stats.n_error_rejections)},
         {"event_rejections", "-", count(stats.n_event_rejections)},
         {"failed_solves", "-", count(stats.n_failures)},
         {"cycle_seconds", "s", wall},
         {"mechanics_seconds", "s", ventricles.mechanics_seconds},
         {"ep_seconds", "s", ventricles.ep_seconds}});
      if (ep != nullptr)
        {
          const auto s = ep->statistics();
          statistics.insert(
            statistics.end(),
            {{"ep_steps", "-", count(s.steps)},
             {"ep_integration_seconds", "s", s.seconds},
             {"ep_transfer_seconds", "s", ep->transfer_seconds()},
             {"ep_nodes", "-", count(ep->n_nodes())}});
        }
      statistics.insert(
        statistics.end(),
        {{"checkpoints", "-", count(checkpointer.count)},
         {"checkpoint_seconds", "s", checkpointer.seconds},
         {"mechanics_dofs", "-", count(model.problem->n_dofs())}});
      if (checkpointer.count > 0)
        texts.emplace_back("last_checkpoint", checkpointer.list().front());
      results.write_statistics(statistics, texts);
    }

    /// The tension model of @p prm, checked against the heartbeat's options.
    std::unique_ptr<Materials::TensionModel>
    checked_tension_model(const dealii::ParameterHandler &prm,
                          const double                    period)
    {
      auto tension_model = Materials::create_tension_model(prm, period);
      check_heartbeat_options(prm, *tension_model);
      return tension_model;
    }

    /// The parts of a heartbeat that the coupled run starts from: the
    /// options, the checkpoint to resume from, the mechanics, the 0D
    /// circulation and the activation (electrophysiology or a prescribed
    /// map).
    struct HeartbeatSetUp
    {
      HeartbeatSetUp(const dealii::ParameterHandler &prm,
                     const RunParameters            &run,
                     Logger                         &logger,
                     const MPI_Comm                  comm)
        : circulation(Circulation::Parameters::parse(prm))
        , tension_model(checked_tension_model(prm, circulation.steps.period))
        , inertia(prm.get_bool({"Mechanics"}, "Inertia"))
        , all_entries(checkpoint_entries(prm))
        , store(run.output_directory, comm)
        , checkpoint(resume_checkpoint(run, store, all_entries, logger, comm))
        , model(prm,
                run,
                logger,
                comm,
                checkpoint.empty() ? "" : checkpoint + "/mechanics.mesh")
        , ventricle_names(ventricle_names_of(*model.problem, model.names))
        , circulation_model(Circulation::create_model(prm, ventricle_names))
        , unloaded_volumes(model.problem->cavity_volumes())
      {
        logger.line(model.banner(run) +
                    unloaded_text(unloaded_volumes, ventricle_names) +
                    "; circulation '" + circulation_model->name() + "'");
        const bool calcium_driven =
          tension_model->drive() == Materials::TensionDrive::calcium;
        activation = create_activation(prm,
                                       run,
                                       model,
                                       calcium_driven,
                                       circulation.steps.period,
                                       checkpoint,
                                       logger,
                                       comm);
      }

      const Circulation::Parameters                  circulation;
      const std::unique_ptr<Materials::TensionModel> tension_model;
      const bool                                     inertia;
      const std::string                              all_entries;
      IO::CheckpointStore                            store;
      const std::string                              checkpoint;
      MechanicsModel                                 model;
      const std::vector<std::string>                 ventricle_names;
      const std::unique_ptr<Circulation::Model>      circulation_model;
      const Vector                                   unloaded_volumes;
      Activation                                     activation;
    };

    /// The coupled run from the end of its set-up: the time loop (to the
    /// last beat, a periodic state or an interruption), the last output,
    /// and the cost of the run on the log and in /statistics.
    void
    run_and_report(HeartbeatStepper           &stepper,
                   HeartbeatWriter            &writer,
                   RunCheckpointer            &checkpointer,
                   MechanicsVentricles        &ventricles,
                   const ElectricalActivation *ep,
                   const MechanicsModel       &model,
                   dealii::TimerOutput        &timer,
                   IO::ResultsFile            &results,
                   Logger                     &logger)
    {
      ventricles.timer = &timer;
      writer.timer     = &timer;
      timer.leave_subsection("Heartbeat / set-up");
      const auto start = std::chrono::steady_clock::now();
      const auto stats = run_or_checkpoint(stepper, writer, checkpointer);
      {
        const auto timed = timer_section(&timer, "Heartbeat / output");
        writer.finish();
      }
      const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
      log_run(stats,
              ventricles,
              ep,
              checkpointer,
              *model.problem,
              wall,
              logger);
      write_statistics(stats,
                       ventricles,
                       ep,
                       checkpointer,
                       model,
                       wall,
                       timer,
                       results);
      logger.line("Wrote " + results.path());
    }
  } // namespace

  void
  run_heartbeat_problem(const RunInputs &in)
  {
    // The sections of the run (written to /statistics as "timer: Heartbeat:
    // ..."); the mechanics' own sections are inside "mechanics".
    // (Without a communicator: this rank's times, no collective calls.)
    std::ostringstream  no_output;
    dealii::TimerOutput timer(no_output,
                              dealii::TimerOutput::never,
                              dealii::TimerOutput::wall_times);
    timer.enter_subsection("Heartbeat / set-up");
    HeartbeatSetUp            set_up(in.prm, in.run, in.logger, in.comm);
    const auto               &circulation      = set_up.circulation;
    const bool                inertia          = set_up.inertia;
    const std::string        &checkpoint       = set_up.checkpoint;
    MechanicsModel           &model            = set_up.model;
    Mechanics::Problem       &problem          = *model.problem;
    const Circulation::Model &zero_d           = *set_up.circulation_model;
    const Vector             &unloaded_volumes = set_up.unloaded_volumes;
    const auto               &activation       = set_up.activation;
    ElectricalActivation     *ep               = activation.ep.get();

    Vector y0, p0;
    initial_state(zero_d, unloaded_volumes, y0, p0);

    // The tension starts to rise at the earliest activation plus the
    // model's onset delay, taken within the beat.
    const double onset =
      std::fmod(activation.earliest + set_up.tension_model->onset_delay(),
                circulation.steps.period);
    MechanicsVentricles ventricles(problem,
                                   *set_up.tension_model,
                                   activation.times,
                                   ep,
                                   onset,
                                   inertia,
                                   in.logger);
    // The small state of a checkpoint (IO::checkpoint_state_file): the rows
    // of the results file and the last step first, then the components in a
    // fixed order.
    std::unique_ptr<IO::StateReader> state_in;
    const auto       results_file = open_results(checkpoint, in, state_in);
    IO::ResultsFile &results      = *results_file;
    if (ep != nullptr && checkpoint.empty())
      write_purkinje(results, ep->purkinje(), in.comm);
    Postprocess::Manager postprocess = model.postprocessors(in.prm, in.logger);
    Progress             progress(in.logger,
                      Progress::parse_mode(in.run.progress),
                      0.0,
                      circulation.steps.period * circulation.steps.n_max_beats);
    HeartbeatWriter      writer({zero_d,
                                 results,
                                 ventricles,
                                 problem,
                                 ep,
                                 in.run,
                                 in.logger,
                                 progress,
                                 postprocess,
                                 circulation.steps.period,
                                 in.comm});
    HeartbeatStepper     stepper(zero_d,
                             ventricles,
                             HeartbeatStepper::Settings(circulation.steps),
                             y0,
                             p0);
    writer.inertia = inertia;

    HeartbeatState state{problem, ep, stepper, ventricles, writer, postprocess};
    if (state_in)
      state.load(state_in->archive());
    state_in.reset();
    RunCheckpointer checkpointer({set_up.store,
                                  results,
                                  model.tria,
                                  "mechanics.mesh",
                                  set_up.all_entries,
                                  in.run,
                                  in.logger,
                                  in.comm});
    writer.checkpoint = [&](const unsigned int step) {
      checkpointer.write(
        step,
        [&](boost::archive::text_oarchive &archive, const std::string &folder) {
          state.save(archive, folder);
        },
        [&]() { problem.finish_checkpoint(); });
    };
    // The electrophysiology on tetrahedra cannot be checkpointed yet (nor
    // can the mechanics there resume): an interrupted run stops without one.
    if (ep != nullptr && !ep->checkpointable())
      writer.checkpoint = nullptr;

    run_and_report(stepper,
                   writer,
                   checkpointer,
                   ventricles,
                   ep,
                   model,
                   timer,
                   results,
                   in.logger);
  }
} // namespace systole
