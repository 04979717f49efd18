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
#include "io/results_file.h"
#include "materials/bestel.h"
#include "materials/factory.h"
#include "materials/tension_factory.h"
#include "mechanics/problem.h"
#include "simulation/circulation_columns.h"
#include "simulation/ecg_columns.h"
#include "simulation/electrical_activation.h"
#include "simulation/heartbeat_stepper.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"
#include "simulation/purkinje_output.h"

#include "postprocess/manager.h"
#include <boost/archive/binary_iarchive.hpp>
#include <boost/archive/binary_oarchive.hpp>
#include <boost/serialization/array.hpp>
#include <boost/serialization/vector.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole
{
  namespace
  {
    using Vector = dealii::Vector<double>;

    /// The section @p name of @p timer for the lifetime of the returned
    /// object (nothing without a timer).
    std::unique_ptr<dealii::TimerOutput::Scope>
    section(dealii::TimerOutput *timer, const char *name)
    {
      return timer == nullptr
               ? nullptr
               : std::make_unique<dealii::TimerOutput::Scope>(*timer, name);
    }

    /// The 3D ventricle(s) as the heartbeat stepper sees them: the
    /// mechanics with its cavity volumes constrained (Mechanics::Problem::
    /// solve_cavities), under the active tension of the time, of one of two
    /// kinds of tension model (Materials::TensionModel):
    /// - driven by activation times (Bestel): the tension of each quadrature
    ///   point starts at its activation time, prescribed or the latest
    ///   upstroke at or before t of the electrophysiology (@p ep not null);
    /// - driven by calcium (Land): coupled two-way with the mechanics
    ///   (Mechanics::Problem::set_tension_model), its states stepped from
    ///   the accepted time to t with the calcium of the electrophysiology at
    ///   t (linear in time between EP's samples) and the fibre stretch of
    ///   each Newton iterate; accept() commits them.
    class MechanicsVentricles : public CoupledVentricles
    {
    public:
      /// @p contraction_onset: the earliest time in a beat at which a
      /// point's tension starts to rise [ms].
      MechanicsVentricles(Mechanics::Problem              &problem,
                          const Materials::TensionModel   &tension_model,
                          std::vector<std::vector<double>> activation_times,
                          ElectricalActivation            *ep,
                          const double                     contraction_onset,
                          const bool                       inertia,
                          Logger                          &logger)
        : problem(problem)
        , tension_model(tension_model)
        , calcium_driven(tension_model.drive() ==
                         Materials::TensionDrive::calcium)
        , activation_times(std::move(activation_times))
        , ep(ep)
        , contraction_onset(contraction_onset)
        , inertia(inertia)
        , logger(logger)
      {
        if (calcium_driven)
          {
            AssertThrow(ep != nullptr,
                        dealii::ExcMessage(
                          "A calcium-driven tension model needs the "
                          "electrophysiology of the heartbeat."));
            ep->keep_calcium();
            problem.set_tension_model(&tension_model);
          }
        problem.save();
      }

      std::vector<double>
      breakpoints_in_beat() const override
      {
        return {contraction_onset};
      }

      void
      set_time(const double t) override
      {
        const auto timed = section(timer, "Heartbeat / EP and tension");
        time             = t;
        // With inertia every solve after the first accepted step is one
        // generalized-alpha step from the accepted state (redone steps start
        // there again).
        if (dynamics_started)
          {
            AssertThrow(t > accepted_time,
                        dealii::ExcMessage(
                          "Problem = heartbeat with Mechanics / Inertia: a "
                          "step must end after the accepted time."));
            problem.set_time_step(t - accepted_time);
          }
        if (ep != nullptr)
          {
            const auto start = std::chrono::steady_clock::now();
            ep->advance_to(t);
            ep->activation_times(t, activation_times);
            if (calcium_driven)
              ep->calcium(t, calcium);
            ep_seconds += std::chrono::duration<double>(
                            std::chrono::steady_clock::now() - start)
                            .count();
          }
        if (calcium_driven)
          {
            // The stepper only steps forward from the accepted time.
            problem.set_calcium(calcium);
            problem.set_tension_step(t, t - accepted_time);
            return;
          }
        // The model has no state and no stretch dependence (it is driven
        // by the activation time alone; run_heartbeat_problem checks).
        Materials::TensionInput  in;
        Materials::TensionOutput out;
        in.time = t;
        tension.resize(activation_times.size());
        for (unsigned int c = 0; c < activation_times.size(); ++c)
          {
            tension[c].resize(activation_times[c].size());
            for (unsigned int q = 0; q < activation_times[c].size(); ++q)
              {
                in.activation_time = activation_times[c][q];
                tension_model.step(nullptr, in, nullptr, out);
                tension[c][q] = out.tension;
              }
          }
        problem.set_active_tension(tension);
      }

      void
      predict(const double ratio) override
      {
        const auto timed = section(timer, "Heartbeat / mechanics");
        // Extrapolate the displacement from the last two accepted states
        // (the step may double at most).
        problem.predict(std::clamp(ratio, 0.0, 2.0));
      }

      unsigned int
      solve(const CavityVolumeTarget &target, Vector &p) override
      {
        const auto timed = section(timer, "Heartbeat / mechanics");
        logger.detail() << "    mechanics at t = " << std::fixed
                        << std::setprecision(3) << time << " ms"
                        << std::defaultfloat << std::endl;
        const auto start  = std::chrono::steady_clock::now();
        const auto report = problem.solve_cavities(target, 0.0, p);
        solved_pressures  = p;
        linear_iterations += report.linear_iterations;
        mechanics_seconds += std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count();
        return report.iterations + report.reused_iterations;
      }

      void
      accept() override
      {
        const auto timed = section(timer, "Heartbeat / accept");
        // The dynamic state first: its residual takes the step's tension
        // (before the tension model's state moves on). The first step is
        // quasi-static: the dynamics starts at its end with the velocity of
        // the step, consistent with the inflow (from rest, the inflow of the
        // initial state would need an infinite acceleration).
        if (dynamics_started)
          problem.accept_time_step(solved_pressures, 0.0);
        else if (inertia)
          {
            problem.start_dynamics(solved_pressures, 0.0, time - accepted_time);
            dynamics_started = true;
          }
        if (calcium_driven)
          {
            problem.accept_tension_step();
            ep->forget_calcium_before(time);
            // The accepted tension of every point (for mean_tension()).
            std::vector<std::vector<Mechanics::PointState>> states;
            problem.point_states(states);
            tension.assign(states.size(), {});
            for (unsigned int c = 0; c < states.size(); ++c)
              for (const auto &state : states[c])
                tension[c].push_back(state.active_tension);
          }
        accepted_time = time;
        problem.save();
      }

      /// The accepted time (checkpoints).
      template <class Archive>
      void
      serialize(Archive &archive)
      {
        archive &accepted_time &tension &dynamics_started;
      }

      void
      reject() override
      {
        const auto timed = section(timer, "Heartbeat / accept");
        problem.restore();
      }

      /// Mean of the active tension over the quadrature points [kPa] (of the
      /// last set_time(); collective).
      double
      mean_tension(const MPI_Comm comm) const
      {
        double       sum = 0;
        unsigned int n   = 0;
        for (const auto &cell : tension)
          for (const double value : cell)
            {
              sum += value;
              ++n;
            }
        return dealii::Utilities::MPI::sum(sum, comm) /
               std::max(1u, dealii::Utilities::MPI::sum(n, comm));
      }

      /// The activation time of every quadrature point in the beat that
      /// started at @p beat_start [ms] (NaN: not activated in it), as of the
      /// last set_time().
      std::vector<std::vector<double>>
      activation_in_beat(const double beat_start) const
      {
        auto times = activation_times;
        if (ep != nullptr)
          for (auto &cell : times)
            for (double &t : cell)
              t = t >= beat_start - 1e-9
                    ? t - beat_start
                    : std::numeric_limits<double>::quiet_NaN();
        return times;
      }

      /// Wall times [s]: the mechanics solves, the electrophysiology
      /// (advancing, reading).
      double mechanics_seconds = 0, ep_seconds = 0;
      /// The heartbeat's sections (none: not timed).
      dealii::TimerOutput *timer = nullptr;
      /// Krylov iterations of the mechanics solves (0 with the direct
      /// solver).
      unsigned long linear_iterations = 0;

    private:
      Mechanics::Problem              &problem;
      const Materials::TensionModel   &tension_model;
      const bool                       calcium_driven;
      std::vector<std::vector<double>> activation_times;
      ElectricalActivation            *ep;
      std::vector<std::vector<double>> tension;
      /// The calcium at the points at time [µM] (calcium-driven models).
      std::vector<std::vector<double>> calcium;
      const double                     contraction_onset;
      /// Mechanics / Inertia: every solve after the first accepted step is a
      /// generalized-alpha step.
      const bool inertia;
      bool       dynamics_started = false;
      /// The cavity pressures of the last solve [kPa] (accept_time_step()).
      Vector  solved_pressures;
      Logger &logger;
      double  time = 0, accepted_time = 0;
    };

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

    /// Writes what the stepper computes: one /timeseries row per accepted
    /// step, one /events row per valve event, one /summary row per beat,
    /// fields every Output / Field output interval steps, and the log.
    class Writer : public HeartbeatStepper::Observer
    {
    public:
      Writer(const Circulation::Model &model,
             IO::ResultsFile          &results,
             MechanicsVentricles      &ventricles,
             Mechanics::Problem       &problem,
             ElectricalActivation     *ep,
             const RunParameters      &run,
             Logger                   &logger,
             Progress                 &progress,
             Postprocess::Manager     &postprocess,
             const double              period,
             const MPI_Comm            comm)
        : model(model)
        , results(results)
        , ventricles(ventricles)
        , problem(problem)
        , ep(ep)
        , run(run)
        , logger(logger)
        , progress(progress)
        , postprocess(postprocess)
        , period(period)
        , comm(comm)
      {
        for (unsigned int c = 0; c < model.n_cavities(); ++c)
          if (model.cavities()[c].kind == Circulation::CavityKind::external)
            external.push_back(c);
      }

      void
      on_step(const HeartbeatStepper::Step &s) override
      {
        const auto timed = section(timer, "Heartbeat / output");
        total_iterations += s.newton_iterations;
        total_solves += s.mechanics_solves;
        total_rejected += s.rejected;
        ++steps_in_beat;
        std::vector<IO::Column> row = {
          {"step", "-", static_cast<double>(s.index)},
          {"time", "ms", s.time},
          {"beat", "-", static_cast<double>(s.beat)},
          {"time_step", "ms", s.step_size},
          {"bdf_order", "-", static_cast<double>(s.order)}};
        append_model_columns(model,
                             s.time,
                             s.state,
                             s.pressures,
                             s.phases,
                             row);
        // The 3D cavities: the volume of the deformed mesh (equal to the 0D
        // volume state to the constraint tolerance), and the old names of
        // the first one (pressure_mmHg, volume_mL, phase).
        const Vector volumes = problem.cavity_volumes();
        for (unsigned int a = 0; a < external.size(); ++a)
          row.push_back(
            {model.cavities()[external[a]].name + "_mechanics_volume_mL",
             "mL",
             Units::mm3_to_mL(volumes[a])});
        const auto &first = model.cavities()[external[0]];
        row.push_back({"pressure_mmHg",
                       "mmHg",
                       Units::kPa_to_mmHg(s.pressures[external[0]])});
        row.push_back(
          {"volume_mL", "mL", Units::mm3_to_mL(s.state[first.volume_state])});
        row.push_back(
          {"phase",
           "-",
           static_cast<double>(Circulation::code(s.phases[external[0]]))});
        row.push_back(
          {"mean_active_tension", "kPa", ventricles.mean_tension(comm)});
        row.push_back(
          {"newton_iterations", "-", static_cast<double>(s.newton_iterations)});
        row.push_back(
          {"mechanics_solves", "-", static_cast<double>(s.mechanics_solves)});
        row.push_back({"rejected_steps", "-", static_cast<double>(s.rejected)});
        if (inertia)
          row.push_back(
            {"kinetic_energy", "uJ", problem.kinetic_energy()}); // collective
        if (ep != nullptr)
          {
            // The EP steps taken for this step (EP runs ahead to the end of
            // the longest attempt, so rejected attempts count too).
            const unsigned long ep_steps = ep->statistics().steps;
            row.push_back({"ep_steps",
                           "-",
                           static_cast<double>(ep_steps - ep_steps_written)});
            row.push_back(
              {"activated_fraction", "-", ep->activated_fraction()});
            ep_steps_written = ep_steps;
            if (ep->has_ecg())
              append_ecg_columns(ep->ecg_leads(s.time), row);
          }
        // The chosen postprocessors' columns (Postprocess / List of
        // postprocessors).
        postprocess.step(s.time, s.beat, s.beat * period, volumes[0], row);
        results.append_timeseries(row);
        last_time = s.time;
        if (run.field_output_interval > 0 &&
            s.index % run.field_output_interval == 0)
          write_fields(s.index);
        last_step = s.index;
        progress.update(s.index,
                        s.time,
                        Circulation::name(s.phases[external[0]]));
      }

      void
      on_event(const unsigned int            valve,
               const bool                    opens,
               const HeartbeatStepper::Step &s) override
      {
        const auto timed = section(timer, "Heartbeat / output");
        results.append_event(valve_event_columns(model,
                                                 s.time,
                                                 s.beat,
                                                 valve,
                                                 opens,
                                                 s.state,
                                                 s.pressures));
        std::ostringstream o;
        o << std::fixed << std::setprecision(1) << "  t = " << s.time
          << " ms: " << model.valves()[valve].name << " valve "
          << (opens ? "opens" : "closes");
        for (const unsigned int c : external)
          o << " (" << model.cavities()[c].name << " "
            << Units::kPa_to_mmHg(s.pressures[c]) << " mmHg, "
            << Units::mm3_to_mL(s.state[model.cavities()[c].volume_state])
            << " mL)";
        logger.line(o.str());
      }

      void
      on_beat(const unsigned int                             beat,
              const std::vector<Circulation::SummaryColumn> &summary) override
      {
        const auto              timed = section(timer, "Heartbeat / output");
        std::vector<IO::Column> row;
        for (const auto &c : summary)
          row.push_back({c.name, c.unit, c.value});
        row.push_back(
          {"newton_iterations", "-", static_cast<double>(total_iterations)});
        row.push_back(
          {"mechanics_solves", "-", static_cast<double>(total_solves)});
        row.push_back({"steps", "-", static_cast<double>(steps_in_beat)});
        row.push_back(
          {"rejected_steps", "-", static_cast<double>(total_rejected)});
        // The cost of this beat (wall times on rank 0, the slowest rank's
        // share is similar): the mechanics solves, their assembly and
        // linear solver and cavity volume sections, the electrophysiology.
        const std::array<double, 5> seconds  = this->seconds();
        const char                 *names[5] = {"mechanics_seconds",
                                                "assembly_seconds",
                                                "linear_solver_seconds",
                                                "cavity_volume_seconds",
                                                "ep_seconds"};
        for (unsigned int i = 0; i < 5; ++i)
          row.push_back({names[i], "s", seconds[i] - seconds_written[i]});
        seconds_written = seconds;
        std::ostringstream activation;
        if (ep != nullptr)
          {
            // The activation of this beat, from its stimulus onset (the
            // beat start); NaN if the wave did not reach 90 % / all of it.
            const double start = summary_value(summary, "start_time");
            const auto   a     = ep->beat_summary();
            row.push_back(
              {"activation_time_90", "ms", a.fraction_time - start});
            row.push_back({"total_activation_time", "ms", a.total});
            const unsigned long ep_steps = ep->statistics().steps;
            row.push_back({"ep_steps",
                           "-",
                           static_cast<double>(ep_steps - ep_steps_in_beats)});
            ep_steps_in_beats = ep_steps;
            activation << std::fixed << std::setprecision(1)
                       << ", 90 % active after " << a.fraction_time - start
                       << " ms";
            if (ep->has_ecg())
              {
                const std::size_t first = row.size();
                ep->append_ecg_biomarkers(start, start + period, row);
                // A line of its own: the second line fits 100 columns.
                activation << std::setprecision(0) << "\n  ECG: QRS "
                           << row[first + 1].value << " ms, QT "
                           << row[first + 3].value << " ms";
              }
          }
        const auto times_in_beat =
          ventricles.activation_in_beat(summary_value(summary, "start_time"));
        postprocess.end_beat(&times_in_beat, row);
        results.append_summary(row);
        std::ostringstream o;
        // Two lines (or one per cavity and one more), so that the last screen
        // of a run fits 100 columns.
        o << beat_log_line(model, beat, summary) << "\n  " << steps_in_beat
          << " steps, " << total_solves << " mechanics solves, "
          << total_iterations << " Newton iterations" << activation.str();
        logger.line(o.str());
        total_iterations = total_solves = total_rejected = steps_in_beat = 0;
      }

      /// Checkpoints: every Output / Checkpoint interval steps, after
      /// Output / Checkpoint wall time interval minutes, and on SIGTERM or
      /// SIGINT (then the run stops).
      void
      on_step_complete(const unsigned int step_index) override
      {
        stop = interrupted(comm);
        const double minutes =
          std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                        last_checkpoint)
            .count() /
          60.0;
        const bool due = stop ||
                         (run.checkpoint_interval > 0 &&
                          step_index % run.checkpoint_interval == 0) ||
                         (run.checkpoint_minutes > 0 &&
                          dealii::Utilities::MPI::max(minutes, comm) >=
                            run.checkpoint_minutes);
        if (due && checkpoint)
          {
            const auto timed = section(timer, "Heartbeat / checkpoint");
            checkpoint(step_index);
            last_checkpoint = std::chrono::steady_clock::now();
          }
        // Test hook (the checkpoint tests): SIGKILL after this step.
        if (run.test_kill_after_step == static_cast<long>(step_index))
          std::raise(SIGKILL);
      }

      bool
      stop_requested() override
      {
        return stop;
      }

      /// Writes a checkpoint of the step with the given index.
      std::function<void(unsigned int)> checkpoint;
      /// The heartbeat's sections (none: not timed).
      dealii::TimerOutput *timer = nullptr;
      /// Mechanics / Inertia: a kinetic_energy column [µJ].
      bool inertia = false;

      /// The counters of the rows written (save() and load() of a
      /// checkpoint).
      template <class Archive>
      void
      serialize(Archive &archive)
      {
        archive &total_iterations &total_solves  &total_rejected;
        archive &steps_in_beat &ep_steps_written &ep_steps_in_beats;
        archive &last_time &last_step            &last_field_step;
      }

      /// The wall times of the current beat so far [s] (they are columns of
      /// its summary row; a resumed run adds its own).
      std::array<double, 5>
      beat_seconds() const
      {
        auto s = seconds();
        for (unsigned int i = 0; i < 5; ++i)
          s[i] -= seconds_written[i];
        return s;
      }

      void
      set_beat_seconds(const std::array<double, 5> &so_far)
      {
        seconds_written = seconds();
        for (unsigned int i = 0; i < 5; ++i)
          seconds_written[i] -= so_far[i];
      }

      /// The fields of the last step, unless written already. Collective.
      void
      finish()
      {
        if (run.field_output_interval > 0 && last_step != last_field_step)
          write_fields(last_step);
      }

    private:
      /// Total wall times [s]: mechanics, assembly, linear solver, cavity
      /// volume, electrophysiology.
      std::array<double, 5>
      seconds() const
      {
        const auto timings = problem.timings();
        const auto in      = [&](const std::string &section) {
          const auto it = timings.find(section);
          return it == timings.end() ? 0.0 : it->second;
        };
        return {{ventricles.mechanics_seconds,
                 in("Mechanics / assembly"),
                 in("Mechanics / linear solver"),
                 in("Mechanics / cavity volume"),
                 ventricles.ep_seconds}};
      }

      void
      write_fields(const unsigned int step)
      {
        dealii::DataOut<3> data_out;
        problem.attach_output(data_out);
        if (ep != nullptr)
          ep->attach_output(data_out);
        postprocess.attach_output(data_out);
        data_out.build_patches(problem.mapping(),
                               problem.cell_kind().output_subdivisions(2));
        results.write_fields(data_out, step, last_time);
        last_field_step = step;
      }

      const Circulation::Model &model;
      IO::ResultsFile          &results;
      MechanicsVentricles      &ventricles;
      Mechanics::Problem       &problem;
      ElectricalActivation     *ep;
      const RunParameters      &run;
      Logger                   &logger;
      Progress                 &progress;
      Postprocess::Manager     &postprocess;
      const double              period;
      MPI_Comm                  comm;
      std::vector<unsigned int> external;
      unsigned int  total_iterations = 0, total_solves = 0, total_rejected = 0;
      unsigned int  steps_in_beat    = 0;
      unsigned long ep_steps_written = 0, ep_steps_in_beats = 0;
      /// Totals at the last summary row: mechanics, assembly, linear solver,
      /// cavity volume, electrophysiology [s].
      std::array<double, 5> seconds_written = {{0, 0, 0, 0, 0}};
      double                last_time       = 0;
      unsigned int          last_step       = 0;
      /// Step of the last field output (none: the largest value).
      unsigned int last_field_step = std::numeric_limits<unsigned int>::max();
      bool         stop            = false;
      std::chrono::steady_clock::time_point last_checkpoint =
        std::chrono::steady_clock::now();
    };

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
      // Mechanics / Inertia: the dynamic mechanics (penalty formulation).
      const bool inertia = prm.get_bool({"Mechanics"}, "Inertia");
      AssertThrow(!inertia ||
                    prm.get({"Material"}, "Incompressibility") == "penalty",
                  dealii::ExcMessage(
                    "Problem = heartbeat: Mechanics / Inertia = true is "
                    "implemented for Material / Incompressibility = penalty "
                    "only (it is " +
                    prm.get({"Material"}, "Incompressibility") +
                    "): set Incompressibility = penalty or Inertia = false."));
      AssertThrow(!inertia || prm.get_double({"Mechanics"}, "Density") > 0.0,
                  dealii::ExcMessage(
                    "Problem = heartbeat: Mechanics / Inertia = true needs a "
                    "positive Mechanics / Density (kg/m^3; the tissue's is "
                    "1000)."));
    }

    /// Resume: the newest valid checkpoint of the run, written for the same
    /// problem (every entry outside subsection Output equal to
    /// @p all_entries); "" when the run does not resume.
    std::string
    resume_checkpoint(const RunParameters &run,
                      IO::CheckpointStore &store,
                      const std::string   &all_entries,
                      Logger              &logger)
    {
      if (!run.resume)
        return "";
      std::ostringstream faults;
      const std::string  checkpoint = store.newest_valid(faults);
      std::istringstream fault_lines(faults.str());
      for (std::string line; std::getline(fault_lines, line);)
        logger.line(line);
      AssertThrow(!checkpoint.empty(),
                  dealii::ExcMessage(
                    "Output / Resume: there is no valid checkpoint in '" +
                    run.output_directory +
                    "' (set Output / Checkpoint interval when starting "
                    "the run)."));
      std::ifstream      in(checkpoint + "/parameters.prm");
      std::ostringstream saved;
      saved << in.rdbuf();
      const auto differences =
        IO::parameter_differences(saved.str(), all_entries, {"Output"});
      if (!differences.empty())
        {
          std::string message =
            "The checkpoint " + checkpoint +
            " was written for another problem: " + differences[0];
          if (differences.size() > 1)
            message += " (and " + std::to_string(differences.size() - 1) +
                       " more difference(s))";
          AssertThrow(false,
                      dealii::ExcMessage(
                        message +
                        ". Only subsection Output may change when a run "
                        "resumes."));
        }
      logger.line("Resuming from " + checkpoint);
      return checkpoint;
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
          a.ep = std::make_unique<ElectricalActivation>(prm,
                                                        run,
                                                        model.geometry,
                                                        model.tria,
                                                        *model.problem,
                                                        period,
                                                        logger,
                                                        comm,
                                                        checkpoint);
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
      zero_d.cavity_pressures(0.0, y0, no_pressures, p0);
    }

    HeartbeatStepper::Settings
    stepper_settings(const Circulation::Parameters &circulation)
    {
      HeartbeatStepper::Settings settings;
      settings.period                = circulation.period;
      settings.n_max_beats           = circulation.n_max_beats;
      settings.periodicity_tolerance = circulation.periodicity_tolerance;
      settings.relative_tolerance    = circulation.relative_tolerance;
      settings.absolute_volume_tolerance =
        circulation.absolute_volume_tolerance;
      settings.absolute_pressure_tolerance =
        circulation.absolute_pressure_tolerance;
      settings.max_step             = circulation.max_time_step;
      settings.initial_step         = circulation.initial_time_step;
      settings.event_time_tolerance = circulation.event_time_tolerance;
      settings.max_step_cuts        = circulation.max_step_cuts;
      return settings;
    }

    /// The small state of a checkpoint (state.bin) as a string on every
    /// rank (read on rank 0).
    std::string
    read_state_bytes(const std::string &checkpoint, const MPI_Comm comm)
    {
      std::string bytes;
      if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
        {
          std::ifstream      in(checkpoint + "/state.bin", std::ios::binary);
          std::ostringstream o;
          o << in.rdbuf();
          bytes = o.str();
        }
      return dealii::Utilities::MPI::broadcast(comm, bytes, 0);
    }

    /// The results file: new, or (resuming from @p checkpoint) reopened
    /// with the rows of its small state, whose rest @p state_in then reads
    /// from @p saved_state.
    std::unique_ptr<IO::ResultsFile>
    open_results(const std::string   &checkpoint,
                 const RunParameters &run,
                 const std::string   &parameter_text,
                 std::istringstream  &saved_state,
                 std::unique_ptr<boost::archive::binary_iarchive> &state_in,
                 const MPI_Comm                                    comm)
    {
      if (checkpoint.empty())
        return std::make_unique<IO::ResultsFile>(run.output_directory,
                                                 parameter_text,
                                                 comm);
      saved_state.str(read_state_bytes(checkpoint, comm));
      state_in = std::make_unique<boost::archive::binary_iarchive>(saved_state);
      IO::ResultsFile::Rows rows;
      unsigned int          resumed_step = 0;
      *state_in &rows.timeseries &rows.summary &rows.events &resumed_step;
      return std::make_unique<IO::ResultsFile>(run.output_directory,
                                               rows,
                                               resumed_step,
                                               comm);
    }

    /// The parts of a running heartbeat whose state a checkpoint holds, in
    /// the order of state.bin (after the rows of the results file and the
    /// step).
    struct HeartbeatState
    {
      Mechanics::Problem   &problem;
      ElectricalActivation *ep;
      HeartbeatStepper     &stepper;
      MechanicsVentricles  &ventricles;
      Writer               &writer;
      Postprocess::Manager &postprocess;

      void
      load(boost::archive::binary_iarchive &archive)
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
      save(boost::archive::binary_oarchive &archive, const std::string &folder)
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

    /// Writes checkpoints: the meshes with their cell data (the mechanics'
    /// states, the EP state, the activation at the mechanics points)
    /// through p::d::Triangulation::save, the small state through boost
    /// serialization, the parameters; into a temporary folder that is
    /// renamed when complete.
    struct Checkpointer
    {
      IO::CheckpointStore                                     &store;
      const IO::ResultsFile                                   &results;
      HeartbeatState                                           state;
      const dealii::parallel::DistributedTriangulationBase<3> *tria;
      const std::string                                       &all_entries;
      const RunParameters                                     &run;
      Logger                                                  &logger;
      MPI_Comm                                                 comm;
      double                                                   seconds = 0;
      unsigned int                                             count   = 0;

      void
      write(const unsigned int step)
      {
        const auto         begin  = std::chrono::steady_clock::now();
        const std::string  folder = store.begin(step);
        std::ostringstream bytes;
        {
          boost::archive::binary_oarchive archive(bytes);
          const auto                      rows = results.rows();
          archive &rows.timeseries &rows.summary &rows.events &step;
          state.save(archive, folder);
        }
        tria->save(folder + "mechanics.mesh");
        state.problem.finish_checkpoint();
        if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
          write_files(folder, bytes.str(), step);
        const std::string path = store.commit();
        seconds += std::chrono::duration<double>(
                     std::chrono::steady_clock::now() - begin)
                     .count();
        ++count;
        logger.detail() << "  checkpoint " << path << std::endl;
      }

      void
      write_files(const std::string &folder,
                  const std::string &data,
                  const unsigned int step) const
      {
        std::ofstream state_file(folder + "state.bin", std::ios::binary);
        // Test hook (Output / Test kill in checkpoint): die by SIGKILL
        // halfway through the state of the checkpoint of this step.
        if (run.test_kill_in_checkpoint == static_cast<long>(step))
          {
            state_file.write(data.data(), data.size() / 2);
            state_file.flush();
            std::raise(SIGKILL);
          }
        state_file.write(data.data(), data.size());
        std::ofstream(folder + "parameters.prm") << all_entries;
        std::ofstream(folder + "parameter_file") << run.parameter_file;
        AssertThrow(state_file.good(),
                    dealii::ExcMessage("Cannot write " + folder +
                                       "state.bin."));
      }
    };

    /// The log lines of the end of a run.
    void
    log_run(const HeartbeatStepper::Statistics &stats,
            const MechanicsVentricles          &ventricles,
            const ElectricalActivation         *ep,
            const Checkpointer                 &checkpointer,
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
        << ventricles.mechanics_seconds << " s in the mechanics of " << wall
        << " s";
      logger.line(o.str());
      if (checkpointer.count > 0)
        {
          std::ostringstream c;
          c << std::fixed << std::setprecision(3) << checkpointer.count
            << " checkpoint(s), " << checkpointer.seconds / checkpointer.count
            << " s per checkpoint, " << problem.n_dofs()
            << " mechanics DOFs;\n  the last in "
            << checkpointer.store.list().front();
          logger.line(c.str());
        }
      if (stats.interrupted)
        logger.line("Interrupted: continue with systole --resume " +
                    checkpointer.run.output_directory);
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
                     const Checkpointer                 &checkpointer,
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
        texts.emplace_back("last_checkpoint",
                           checkpointer.store.list().front());
      results.write_statistics(statistics, texts);
    }
  } // namespace

  void
  run_heartbeat_problem(const dealii::ParameterHandler &prm,
                        const RunParameters            &run,
                        const std::string              &parameter_text,
                        Logger                         &logger,
                        const MPI_Comm                  comm)
  {
    // The sections of the run (written to /statistics as "timer: Heartbeat:
    // ..."); the mechanics' own sections are inside "mechanics".
    // (Without a communicator: this rank's times, no collective calls.)
    std::ostringstream  no_output;
    dealii::TimerOutput timer(no_output,
                              dealii::TimerOutput::never,
                              dealii::TimerOutput::wall_times);
    timer.enter_subsection("Heartbeat / set-up");
    const auto circulation = Circulation::Parameters::parse(prm);
    const auto tension_model =
      Materials::create_tension_model(prm, circulation.period);
    check_heartbeat_options(prm, *tension_model);
    const bool inertia = prm.get_bool({"Mechanics"}, "Inertia");

    std::ostringstream entries;
    prm.print_parameters(entries, dealii::ParameterHandler::ShortPRM);
    const std::string   all_entries = entries.str();
    IO::CheckpointStore store(run.output_directory, comm);
    const std::string   checkpoint =
      resume_checkpoint(run, store, all_entries, logger);

    MechanicsModel      model(prm,
                         run,
                         logger,
                         comm,
                         checkpoint.empty() ? ""
                                                 : checkpoint + "/mechanics.mesh");
    Mechanics::Problem &problem = *model.problem;
    const auto ventricle_names  = ventricle_names_of(problem, model.names);
    const auto circulation_model =
      Circulation::create_model(prm, ventricle_names);
    const Circulation::Model &zero_d           = *circulation_model;
    const Vector              unloaded_volumes = problem.cavity_volumes();
    logger.line(model.banner(run) +
                unloaded_text(unloaded_volumes, ventricle_names) +
                "; circulation '" + zero_d.name() + "'");

    const bool calcium_driven =
      tension_model->drive() == Materials::TensionDrive::calcium;
    Activation            activation = create_activation(prm,
                                              run,
                                              model,
                                              calcium_driven,
                                              circulation.period,
                                              checkpoint,
                                              logger,
                                              comm);
    ElectricalActivation *ep         = activation.ep.get();

    Vector y0, p0;
    initial_state(zero_d, unloaded_volumes, y0, p0);

    // The tension starts to rise at the earliest activation plus the
    // model's onset delay, taken within the beat.
    const double onset =
      std::fmod(activation.earliest + tension_model->onset_delay(),
                circulation.period);
    MechanicsVentricles ventricles(problem,
                                   *tension_model,
                                   activation.times,
                                   ep,
                                   onset,
                                   inertia,
                                   logger);
    // The small state of a checkpoint (state.bin): the rows of the results
    // file and the last step first, then the components in a fixed order.
    std::istringstream                               saved_state;
    std::unique_ptr<boost::archive::binary_iarchive> state_in;
    const auto       results_file = open_results(checkpoint,
                                           run,
                                           parameter_text,
                                           saved_state,
                                           state_in,
                                           comm);
    IO::ResultsFile &results      = *results_file;
    if (ep != nullptr && checkpoint.empty())
      write_purkinje(results, ep->purkinje(), comm);
    Postprocess::Manager postprocess(Postprocess::Parameters::parse(prm),
                                     problem,
                                     model.names,
                                     &logger);
    Progress             progress(logger,
                      Progress::parse_mode(run.progress),
                      0.0,
                      circulation.period * circulation.n_max_beats);
    Writer               writer(zero_d,
                  results,
                  ventricles,
                  problem,
                  ep,
                  run,
                  logger,
                  progress,
                  postprocess,
                  circulation.period,
                  comm);
    HeartbeatStepper     stepper(zero_d,
                             ventricles,
                             stepper_settings(circulation),
                             y0,
                             p0);
    writer.inertia = inertia;

    HeartbeatState state{problem, ep, stepper, ventricles, writer, postprocess};
    if (state_in)
      state.load(*state_in);
    state_in.reset();
    Checkpointer checkpointer{store,
                              results,
                              state,
                              &model.tria,
                              all_entries,
                              run,
                              logger,
                              comm};
    writer.checkpoint = [&](const unsigned int step) {
      checkpointer.write(step);
    };
    // The electrophysiology on tetrahedra cannot be checkpointed yet (nor
    // can the mechanics there resume): an interrupted run stops without one.
    if (ep != nullptr && !ep->checkpointable())
      writer.checkpoint = nullptr;

    ventricles.timer = &timer;
    writer.timer     = &timer;
    timer.leave_subsection("Heartbeat / set-up");
    const auto start = std::chrono::steady_clock::now();
    const auto stats = stepper.run(writer);
    {
      const auto timed = section(&timer, "Heartbeat / output");
      writer.finish();
    }
    const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
    log_run(stats, ventricles, ep, checkpointer, problem, wall, logger);
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
} // namespace systole
