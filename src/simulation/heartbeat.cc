#include "simulation/heartbeat.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"
#include "base/interrupt.h"
#include "base/logger.h"
#include "base/units.h"
#include "circulation/cardiac_cycle.h"
#include "circulation/parameters.h"
#include "circulation/windkessel.h"
#include "fibres/fibre_field.h"
#include "geometry/mesh.h"
#include "io/results_file.h"
#include "materials/bestel.h"
#include "materials/factory.h"
#include "mechanics/problem.h"
#include "simulation/electrical_activation.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"

#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole
{
  namespace
  {
    /// The 3D ventricle as the circulation sees it: p = P(t, V), one
    /// volume-constrained mechanics solve per call, warm-started by
    /// extrapolating the last two accepted states in time. The Bestel
    /// tension of each quadrature point starts at its activation time:
    /// prescribed, or the latest upstroke at or before t of the
    /// electrophysiology (@p ep not null).
    class MechanicsVentricle : public Circulation::Ventricle
    {
    public:
      MechanicsVentricle(Mechanics::Problem              &problem,
                         const Materials::Bestel         &bestel,
                         std::vector<std::vector<double>> activation_times,
                         ElectricalActivation            *ep,
                         Logger                          &logger)
        : problem(problem)
        , bestel(bestel)
        , activation_times(std::move(activation_times))
        , ep(ep)
        , logger(logger)
      {
        problem.save();
      }

      double
      pressure(const double t, const double volume) override
      {
        if (t == last_time && volume == last_volume)
          return last_pressure;
        set_tension(t);
        // Extrapolate the displacement and the pressure from the last two
        // accepted states (at most one accepted interval ahead).
        double ratio = 0;
        if (accepted_time > previous_time)
          ratio =
            std::clamp((t - accepted_time) / (accepted_time - previous_time),
                       -1.0,
                       1.0);
        problem.predict(ratio);
        double p =
          accepted_pressure + ratio * (accepted_pressure - previous_pressure);
        logger.detail() << "    mechanics at t = " << t
                        << " ms, V = " << Units::mm3_to_mL(volume) << " mL"
                        << std::endl;
        const auto start = std::chrono::steady_clock::now();
        try
          {
            const auto report = problem.solve_volume(volume, 0.0, p);
            step_newton_iterations += report.iterations;
            ++step_solves;
          }
        catch (const ExcNewtonDidNotConverge &)
          {
            problem.restore();
            last_time = std::numeric_limits<double>::quiet_NaN();
            throw;
          }
        mechanics_seconds += std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count();
        last_time     = t;
        last_volume   = volume;
        last_pressure = p;
        return p;
      }

      void
      accept_step(const double t, const double volume) override
      {
        pressure(t, volume); // no-op when the last solve was at (t, V)
        problem.save();
        previous_time     = accepted_time;
        previous_pressure = accepted_pressure;
        accepted_time     = t;
        accepted_pressure = last_pressure;
      }

      /// Newton iterations and solves since the last call.
      std::pair<unsigned int, unsigned int>
      take_step_counts()
      {
        const auto counts = std::make_pair(step_newton_iterations, step_solves);
        step_newton_iterations = 0;
        step_solves            = 0;
        return counts;
      }

      /// Mean of the active tension over the quadrature points [kPa] (of the
      /// last solve; collective).
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

      double mechanics_seconds = 0;
      /// Wall time in the electrophysiology (advancing, reading) [s].
      double ep_seconds = 0;

    private:
      void
      set_tension(const double t)
      {
        if (ep != nullptr)
          {
            const auto start = std::chrono::steady_clock::now();
            ep->advance_to(t);
            ep->activation_times(t, activation_times);
            ep_seconds += std::chrono::duration<double>(
                            std::chrono::steady_clock::now() - start)
                            .count();
          }
        tension.resize(activation_times.size());
        for (unsigned int c = 0; c < activation_times.size(); ++c)
          {
            tension[c].resize(activation_times[c].size());
            for (unsigned int q = 0; q < activation_times[c].size(); ++q)
              {
                const double t_a = activation_times[c][q];
                // Not activated yet: at rest.
                tension[c][q] = std::isnan(t_a) ? 0.0 : bestel.tension(t, t_a);
              }
          }
        problem.set_active_tension(tension);
      }

      Mechanics::Problem              &problem;
      const Materials::Bestel         &bestel;
      std::vector<std::vector<double>> activation_times;
      ElectricalActivation            *ep;
      std::vector<std::vector<double>> tension;
      Logger                          &logger;

      double       last_time     = std::numeric_limits<double>::quiet_NaN();
      double       last_volume   = 0;
      double       last_pressure = 0;
      double       accepted_time = 0, previous_time = 0;
      double       accepted_pressure = 0, previous_pressure = 0;
      unsigned int step_newton_iterations = 0, step_solves = 0;
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
      std::vector<std::vector<double>> times(points.size());
      for (unsigned int c = 0; c < points.size(); ++c)
        for (const auto &X : points[c])
          {
            double s = (height(X) - lowest) / (highest - lowest);
            if (!apex_is_low)
              s = 1.0 - s;
            times[c].push_back(params.activation_map == "uniform"
                                 ? 0.0
                                 : params.activation_delay * s);
          }
      return times;
    }

    class Writer : public Circulation::CardiacCycle::Observer
    {
    public:
      Writer(IO::ResultsFile      &results,
             MechanicsVentricle   &ventricle,
             Mechanics::Problem   &problem,
             ElectricalActivation *ep,
             const RunParameters  &run,
             Logger               &logger,
             Progress             &progress,
             const double          end_time,
             const MPI_Comm        comm)
        : results(results)
        , ventricle(ventricle)
        , problem(problem)
        , ep(ep)
        , run(run)
        , logger(logger)
        , progress(progress)
        , end_time(end_time)
        , comm(comm)
      {}

      void
      on_step(const Circulation::StepRecord &r) override
      {
        const auto [iterations, solves] = ventricle.take_step_counts();
        total_iterations += iterations;
        total_solves += solves;
        std::vector<IO::Column> row = {
          {"step", "-", static_cast<double>(step)},
          {"time", "ms", r.time},
          {"beat", "-", static_cast<double>(r.beat)},
          {"phase", "-", static_cast<double>(Circulation::code(r.phase))},
          {"pressure", "kPa", r.pressure},
          {"pressure_mmHg", "mmHg", Units::kPa_to_mmHg(r.pressure)},
          {"volume", "mm^3", r.volume},
          {"volume_mL", "mL", Units::mm3_to_mL(r.volume)},
          {"mechanics_volume_mL",
           "mL",
           Units::mm3_to_mL(problem.cavity_volume())},
          {"flow", "mL/s", Circulation::flow_to_mL_per_s(r.flow)},
          {"aortic_outflow",
           "mL/s",
           Circulation::flow_to_mL_per_s(r.aortic_outflow)},
          {"mitral_inflow",
           "mL/s",
           Circulation::flow_to_mL_per_s(r.mitral_inflow)},
          {"aortic_pressure_mmHg",
           "mmHg",
           Units::kPa_to_mmHg(r.aortic_pressure)},
          {"arterial_pressure_mmHg",
           "mmHg",
           Units::kPa_to_mmHg(r.arterial_pressure)},
          {"cumulative_outflow_mL",
           "mL",
           Units::mm3_to_mL(r.cumulative_aortic_outflow)},
          {"cumulative_inflow_mL",
           "mL",
           Units::mm3_to_mL(r.cumulative_mitral_inflow)},
          {"mean_active_tension", "kPa", ventricle.mean_tension(comm)},
          {"newton_iterations", "-", static_cast<double>(iterations)},
          {"mechanics_solves", "-", static_cast<double>(solves)},
          {"time_step", "ms", r.step_size}};
        if (ep != nullptr)
          {
            // The EP steps taken for this step (EP runs ahead to the last
            // stage of the step, so rejected stages count too).
            const unsigned long ep_steps = ep->statistics().steps;
            row.push_back({"ep_steps",
                           "-",
                           static_cast<double>(ep_steps - ep_steps_written)});
            row.push_back(
              {"activated_fraction", "-", ep->activated_fraction()});
            ep_steps_written = ep_steps;
          }
        results.append_timeseries(row);
        last_time = r.time;
        if (run.field_output_interval > 0 &&
            step % run.field_output_interval == 0)
          write_fields();
        progress.update(step, r.time, Circulation::name(r.phase));
        ++step;
      }

      /// The fields of the last step, unless written already. Collective.
      void
      finish()
      {
        if (run.field_output_interval > 0 && step > 0 &&
            last_field_step + 1 != step)
          {
            --step;
            write_fields();
            ++step;
          }
      }

      void
      on_transition(const Circulation::Transition &e) override
      {
        results.append_event(
          {{"time", "ms", e.time},
           {"beat", "-", static_cast<double>(e.beat)},
           {"from_phase", "-", static_cast<double>(Circulation::code(e.from))},
           {"to_phase", "-", static_cast<double>(Circulation::code(e.to))},
           {"pressure_mmHg", "mmHg", Units::kPa_to_mmHg(e.pressure)},
           {"volume_mL", "mL", Units::mm3_to_mL(e.volume)},
           {"arterial_pressure_mmHg",
            "mmHg",
            Units::kPa_to_mmHg(e.arterial_pressure)}});
        std::ostringstream o;
        o << std::fixed << std::setprecision(1) << "  t = " << e.time
          << " ms: " << Circulation::event_name(e.from, e.to)
          << " (p = " << Units::kPa_to_mmHg(e.pressure)
          << " mmHg, V = " << Units::mm3_to_mL(e.volume) << " mL)";
        logger.line(o.str());
      }

      void
      on_beat(const Circulation::BeatSummary &summary) override
      {
        std::vector<IO::Column> row;
        for (const auto &c : Circulation::summary_columns(summary))
          row.push_back({c.name, c.unit, c.value});
        row.push_back(
          {"newton_iterations", "-", static_cast<double>(total_iterations)});
        row.push_back(
          {"mechanics_solves", "-", static_cast<double>(total_solves)});
        // The cost of this beat (wall times on rank 0, the slowest rank's
        // share is similar): the mechanics solves, their assembly and
        // linear solver and cavity volume sections, the electrophysiology.
        const auto timings = problem.timings();
        const auto in      = [&](const std::string &section) {
          const auto it = timings.find(section);
          return it == timings.end() ? 0.0 : it->second;
        };
        const std::array<double, 5> seconds  = {{ventricle.mechanics_seconds,
                                                 in("Mechanics / assembly"),
                                                 in("Mechanics / linear solver"),
                                                 in("Mechanics / cavity volume"),
                                                 ventricle.ep_seconds}};
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
            const auto a = ep->beat_summary();
            row.push_back({"activation_time_90",
                           "ms",
                           a.fraction_time - summary.start_time});
            row.push_back({"total_activation_time", "ms", a.total});
            const unsigned long ep_steps = ep->statistics().steps;
            row.push_back({"ep_steps",
                           "-",
                           static_cast<double>(ep_steps - ep_steps_in_beats)});
            ep_steps_in_beats = ep_steps;
            activation << std::fixed << std::setprecision(1)
                       << ", 90 % active after "
                       << a.fraction_time - summary.start_time << " ms";
          }
        results.append_summary(row);
        total_iterations = 0;
        total_solves     = 0;
        std::ostringstream o;
        o << std::fixed << std::setprecision(1) << "Beat " << summary.beat
          << ": EDV " << Units::mm3_to_mL(summary.end_diastolic_volume)
          << " mL, ESV " << Units::mm3_to_mL(summary.end_systolic_volume)
          << " mL, EF " << 100 * summary.ejection_fraction << " %, peak "
          << Units::kPa_to_mmHg(summary.peak_pressure) << " mmHg, EDP "
          << Units::kPa_to_mmHg(summary.end_diastolic_pressure)
          << " mmHg, EDV change " << 100 * summary.periodicity << " %"
          << activation.str();
        logger.line(o.str());
      }

      bool
      stop_requested() override
      {
        return interrupted(comm);
      }

    private:
      void
      write_fields()
      {
        dealii::DataOut<3> data_out;
        problem.attach_output(data_out);
        if (ep != nullptr)
          ep->attach_output(data_out);
        data_out.build_patches(problem.mapping(), 2);
        results.write_fields(data_out, step, last_time);
        last_field_step = step;
      }

      IO::ResultsFile      &results;
      MechanicsVentricle   &ventricle;
      Mechanics::Problem   &problem;
      ElectricalActivation *ep;
      const RunParameters  &run;
      Logger               &logger;
      Progress             &progress;
      double                end_time;
      MPI_Comm              comm;
      unsigned int          step             = 0;
      unsigned int          total_iterations = 0, total_solves = 0;
      unsigned long         ep_steps_written = 0, ep_steps_in_beats = 0;
      /// Totals at the last summary row: mechanics, assembly, linear solver,
      /// cavity volume, electrophysiology [s].
      std::array<double, 5> seconds_written = {{0, 0, 0, 0, 0}};
      double                last_time       = 0;
      /// Step of the last field output (none: the largest value).
      unsigned int last_field_step = std::numeric_limits<unsigned int>::max();
    };
  } // namespace

  void
  run_heartbeat_problem(const dealii::ParameterHandler &prm,
                        const RunParameters            &run,
                        const std::string              &parameter_text,
                        Logger                         &logger,
                        const MPI_Comm                  comm)
  {
    const auto circulation   = Circulation::Parameters::parse(prm);
    const auto bestel_params = Materials::Bestel::Parameters::parse(prm);
    const Materials::Bestel bestel(bestel_params, circulation.period);
    AssertThrow(Mechanics::Parameters::parse(prm).pressure_boundary ==
                  "endocardium",
                dealii::ExcMessage(
                  "Problem = heartbeat needs Mechanics / Pressure boundary = "
                  "endocardium (the cavity pressure acts there)."));

    MechanicsModel model(prm, run, logger, comm);
    const auto    &tria  = model.tria;
    const auto    &names = model.names;
    AssertThrow(names.has("base"),
                dealii::ExcMessage(
                  names.source() +
                  " has no boundary part named 'base': the "
                  "cavity volume is closed by the base plane."));
    Mechanics::Problem &problem         = *model.problem;
    const double        unloaded_volume = problem.cavity_volume();
    logger.line(
      model.banner(run) + ", unloaded cavity " +
      dealii::Utilities::to_string(Units::mm3_to_mL(unloaded_volume)) + " mL");

    // The activation times: from the electrophysiology, or prescribed.
    std::unique_ptr<ElectricalActivation> ep;
    std::vector<std::vector<double>>      times;
    double earliest = std::numeric_limits<double>::max();
    if (bestel_params.activation_map == "electrophysiology")
      {
        ep = std::make_unique<ElectricalActivation>(prm,
                                                    run,
                                                    model.geometry,
                                                    tria,
                                                    problem,
                                                    circulation.period,
                                                    logger,
                                                    comm);
        logger.line(ep->description());
        earliest = ep->earliest_stimulus();
      }
    else
      {
        times = activation_times(problem,
                                 bestel_params,
                                 Geometry::boundary_plane(tria,
                                                          names.id("base"),
                                                          "base"),
                                 comm);
        for (const auto &cell : times)
          for (const double t : cell)
            earliest = std::min(earliest, t);
        earliest = dealii::Utilities::MPI::min(earliest, comm);
      }

    MechanicsVentricle ventricle(problem, bestel, times, ep.get(), logger);
    IO::ResultsFile    results(run.output_directory, parameter_text, comm);
    const double       end_time = circulation.period * circulation.n_max_beats;
    Progress           progress(logger,
                      Progress::parse_mode(run.progress),
                      0.0,
                      end_time);
    Writer             writer(results,
                  ventricle,
                  problem,
                  ep.get(),
                  run,
                  logger,
                  progress,
                  end_time,
                  comm);

    // The mitral valve may close once the tension starts to rise anywhere.
    Circulation::CardiacCycle cycle(circulation,
                                    ventricle,
                                    unloaded_volume,
                                    earliest + bestel.onset());
    const auto                start = std::chrono::steady_clock::now();
    const auto                stats = cycle.run(writer);
    writer.finish();
    const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();

    std::ostringstream o;
    o << std::fixed << std::setprecision(2) << stats.n_beats << " beat(s)"
      << (stats.periodic ? ", periodic" : ", not yet periodic") << "; "
      << stats.n_steps << " steps, " << stats.n_ventricle_calls
      << " mechanics solves; " << ventricle.mechanics_seconds
      << " s in the mechanics";
    logger.line(o.str());
    if (ep != nullptr)
      {
        const auto         s = ep->statistics();
        std::ostringstream e;
        e << std::fixed << std::setprecision(2)
          << "Electrophysiology: " << s.steps << " ARKode steps ("
          << static_cast<double>(s.steps) / std::max(1ul, stats.n_steps)
          << " per accepted mechanics step), " << s.seconds
          << " s integrating, " << ep->transfer_seconds()
          << " s reading it at the mechanics points; of the " << wall
          << " s of the cycle " << 100 * ventricle.ep_seconds / wall
          << " % in EP, " << 100 * ventricle.mechanics_seconds / wall
          << " % in the mechanics";
        logger.line(e.str());
      }
    logger.line("Wrote " + results.path());
  }
} // namespace systole
