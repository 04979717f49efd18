#include "simulation/heartbeat_writer.h"

#include <deal.II/base/timer.h>
#include <deal.II/numerics/data_out.h>

#include "base/interrupt.h"
#include "base/logger.h"
#include "base/units.h"
#include "io/results_file.h"
#include "mechanics/problem.h"
#include "simulation/circulation_columns.h"
#include "simulation/ecg_columns.h"
#include "simulation/electrical_activation.h"
#include "simulation/mechanics_ventricles.h"
#include "simulation/parameters.h"
#include "simulation/timer_section.h"

#include "postprocess/manager.h"
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace systole
{
  HeartbeatWriter::HeartbeatWriter(const HeartbeatWriterParts &parts)
    : HeartbeatWriterParts(parts)
  {
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      if (model.cavities()[c].kind == Circulation::CavityKind::external)
        external.push_back(c);
  }


  void
  HeartbeatWriter::on_step(const HeartbeatStepper::Step &s)
  {
    const auto timed = timer_section(timer, "Heartbeat / output");
    rows.total_iterations += s.newton_iterations;
    rows.total_solves += s.mechanics_solves;
    rows.total_rejected += s.rejected;
    ++rows.steps_in_beat;
    std::vector<IO::Column> row = {{"step", "-", static_cast<double>(s.index)},
                                   {"time", "ms", s.time},
                                   {"beat", "-", static_cast<double>(s.beat)},
                                   {"time_step", "ms", s.step_size},
                                   {"bdf_order",
                                    "-",
                                    static_cast<double>(s.order)}};
    append_model_columns(model, {s.time, s.state, s.pressures}, s.phases, row);
    // The 3D cavities: the volume of the deformed mesh (equal to the 0D
    // volume state to the constraint tolerance), and the old names of the
    // first one (pressure_mmHg, volume_mL, phase).
    const dealii::Vector<double> volumes = problem.cavity_volumes();
    for (unsigned int a = 0; a < external.size(); ++a)
      row.push_back(
        {model.cavities()[external[a]].name + "_mechanics_volume_mL",
         "mL",
         Units::mm3_to_mL(volumes[a])});
    const auto &first = model.cavities()[external[0]];
    row.push_back(
      {"pressure_mmHg", "mmHg", Units::kPa_to_mmHg(s.pressures[external[0]])});
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
    append_ep_columns(s, row);
    // The chosen postprocessors' columns (Postprocess / List of
    // postprocessors).
    postprocess.step(s.time,
                     s.beat,
                     s.beat * period,
                     volumes[0],
                     s.phases[external[0]] == Circulation::Phase::filling,
                     row);
    results.append_timeseries(row);
    rows.last_time = s.time;
    if (run.field_output_interval > 0 &&
        s.index % run.field_output_interval == 0)
      write_fields(s.index);
    rows.last_step = s.index;
    progress.update(s.index, s.time, Circulation::name(s.phases[external[0]]));
  }


  void
  HeartbeatWriter::append_ep_columns(const HeartbeatStepper::Step &s,
                                     std::vector<IO::Column>      &row)
  {
    if (ep == nullptr)
      return;
    // The EP steps taken for this step (EP runs ahead to the end of the
    // longest attempt, so rejected attempts count too).
    const unsigned long ep_steps = ep->statistics().steps;
    row.push_back(
      {"ep_steps", "-", static_cast<double>(ep_steps - rows.ep_steps_written)});
    row.push_back({"activated_fraction", "-", ep->activated_fraction()});
    rows.ep_steps_written = ep_steps;
    if (ep->has_ecg())
      append_ecg_columns(ep->ecg_leads(s.time), row);
  }


  void
  HeartbeatWriter::on_event(const unsigned int            valve,
                            const bool                    opens,
                            const HeartbeatStepper::Step &s)
  {
    const auto timed = timer_section(timer, "Heartbeat / output");
    results.append_event(valve_event_columns(
      model,
      {s.time, s.beat, valve, opens, s.state, s.pressures}));
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
  HeartbeatWriter::on_failure(const double       t_from,
                              const double       t_to,
                              const std::string &why)
  {
    std::ostringstream o;
    o << std::fixed << std::setprecision(1) << "  t = " << t_from
      << " ms: the coupled solve to " << std::setprecision(2) << t_to
      << " ms failed, the step is halved: " << why;
    logger.line(o.str());
  }


  void
  HeartbeatWriter::on_beat(
    const unsigned int                             beat,
    const std::vector<Circulation::SummaryColumn> &summary)
  {
    const auto              timed = timer_section(timer, "Heartbeat / output");
    std::vector<IO::Column> row;
    for (const auto &c : summary)
      row.push_back({c.name, c.unit, c.value});
    row.push_back(
      {"newton_iterations", "-", static_cast<double>(rows.total_iterations)});
    row.push_back(
      {"mechanics_solves", "-", static_cast<double>(rows.total_solves)});
    row.push_back({"steps", "-", static_cast<double>(rows.steps_in_beat)});
    row.push_back(
      {"rejected_steps", "-", static_cast<double>(rows.total_rejected)});
    // The cost of this beat (wall times on rank 0, the slowest rank's share
    // is similar): the mechanics solves, their assembly and linear solver
    // and cavity volume sections, the electrophysiology.
    const std::array<double, 5> seconds  = this->seconds();
    const char                 *names[5] = {"mechanics_seconds",
                                            "assembly_seconds",
                                            "linear_solver_seconds",
                                            "cavity_volume_seconds",
                                            "ep_seconds"};
    for (unsigned int i = 0; i < 5; ++i)
      row.push_back({names[i], "s", seconds[i] - rows.seconds_written[i]});
    rows.seconds_written         = seconds;
    const std::string activation = append_beat_ep_columns(summary, row);
    const auto        times_in_beat =
      ventricles.activation_in_beat(summary_value(summary, "start_time"));
    postprocess.end_beat(&times_in_beat, row);
    results.append_summary(row);
    std::ostringstream o;
    // Two lines (or one per cavity and one more), so that the last screen
    // of a run fits 100 columns.
    o << beat_log_line(model, beat, summary) << "\n  " << rows.steps_in_beat
      << " steps, " << rows.total_solves << " mechanics solves, "
      << rows.total_iterations << " Newton iterations" << activation;
    logger.line(o.str());
    rows.total_iterations = rows.total_solves = rows.total_rejected =
      rows.steps_in_beat                      = 0;
  }


  std::string
  HeartbeatWriter::append_beat_ep_columns(
    const std::vector<Circulation::SummaryColumn> &summary,
    std::vector<IO::Column>                       &row)
  {
    if (ep == nullptr)
      return "";
    // The activation of this beat, from its stimulus onset (the beat
    // start); NaN if the wave did not reach 90 % / all of it.
    std::ostringstream activation;
    const double       start = summary_value(summary, "start_time");
    const auto         a     = ep->beat_summary();
    row.push_back({"activation_time_90", "ms", a.fraction_time - start});
    row.push_back({"total_activation_time", "ms", a.total});
    const unsigned long ep_steps = ep->statistics().steps;
    row.push_back({"ep_steps",
                   "-",
                   static_cast<double>(ep_steps - rows.ep_steps_in_beats)});
    rows.ep_steps_in_beats = ep_steps;
    activation << std::fixed << std::setprecision(1) << ", 90 % active after "
               << a.fraction_time - start << " ms";
    if (ep->has_ecg())
      {
        const std::size_t first = row.size();
        ep->append_ecg_biomarkers(start, start + period, row);
        // A line of its own: the second line fits 100 columns.
        activation << std::setprecision(0) << "\n  ECG: QRS "
                   << row[first + 1].value << " ms, QT " << row[first + 3].value
                   << " ms";
      }
    return activation.str();
  }


  void
  HeartbeatWriter::on_step_complete(const unsigned int step_index)
  {
    stop                 = interrupted(comm);
    const double minutes = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - last_checkpoint)
                             .count() /
                           60.0;
    const bool due =
      stop ||
      (run.checkpoint_interval > 0 &&
       step_index % run.checkpoint_interval == 0) ||
      (run.checkpoint_minutes > 0 &&
       dealii::Utilities::MPI::max(minutes, comm) >= run.checkpoint_minutes);
    if (due && checkpoint)
      {
        const auto timed = timer_section(timer, "Heartbeat / checkpoint");
        checkpoint(step_index);
        last_checkpoint = std::chrono::steady_clock::now();
      }
    // Test hook (the checkpoint tests): SIGKILL after this step.
    if (run.test_kill_after_step == static_cast<long>(step_index))
      std::raise(SIGKILL);
    // Test hook (the write-failure tests): from now on the results file
    // cannot grow (writes beyond its present size fail as on a full disk).
    if (run.test_file_size_limit_after_step == static_cast<long>(step_index))
      {
        std::signal(SIGXFSZ, SIG_IGN);
        const auto   size = std::filesystem::file_size(results.path());
        const rlimit limit{size, size};
        setrlimit(RLIMIT_FSIZE, &limit);
      }
    // Test hook (the rank tests' short runs): end after this step.
    if (run.test_stop_after_step == static_cast<long>(step_index))
      stop = true;
  }


  bool
  HeartbeatWriter::stop_requested()
  {
    return stop;
  }


  std::array<double, 5>
  HeartbeatWriter::beat_seconds() const
  {
    auto s = seconds();
    for (unsigned int i = 0; i < 5; ++i)
      s[i] -= rows.seconds_written[i];
    return s;
  }


  void
  HeartbeatWriter::set_beat_seconds(const std::array<double, 5> &so_far)
  {
    rows.seconds_written = seconds();
    for (unsigned int i = 0; i < 5; ++i)
      rows.seconds_written[i] -= so_far[i];
  }


  void
  HeartbeatWriter::finish()
  {
    if (run.field_output_interval > 0 && rows.last_step != rows.last_field_step)
      write_fields(rows.last_step);
  }


  std::array<double, 5>
  HeartbeatWriter::seconds() const
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
  HeartbeatWriter::write_fields(const unsigned int step)
  {
    dealii::DataOut<3> data_out;
    problem.attach_output(data_out);
    if (ep != nullptr)
      ep->attach_output(data_out);
    postprocess.attach_output(data_out);
    data_out.build_patches(problem.mapping(),
                           problem.cell_kind().output_subdivisions(2));
    results.write_fields(data_out, step, rows.last_time);
    rows.last_field_step = step;
  }
} // namespace systole
