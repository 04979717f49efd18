#include "simulation/elastodynamics.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"
#include "base/interrupt.h"
#include "base/logger.h"
#include "base/units.h"
#include "io/results_file.h"
#include "mechanics/problem.h"
#include "simulation/load_curves.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"

#include "postprocess/manager.h"

#include <cmath>
#include <limits>
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
    AssertThrow(prm.get({"Material"}, "Incompressibility") == "penalty",
                dealii::ExcMessage(
                  "Problem = elastodynamics: the inertia is implemented for "
                  "Material / Incompressibility = penalty only (set it to "
                  "penalty; the bulk modulus of Material / Volumetric holds "
                  "the volume)."));
    AssertThrow(prm.get_double({"Mechanics"}, "Density") > 0.0,
                dealii::ExcMessage("Problem = elastodynamics needs Mechanics / "
                                   "Density > 0 (kg/m^3; 1000 for tissue)."));
  }

  void
  run_elastodynamics_problem(const dealii::ParameterHandler &prm,
                             const RunParameters            &run,
                             const std::string              &parameter_text,
                             Logger                         &logger,
                             const MPI_Comm                  comm)
  {
    MechanicsModel      model(prm, run, logger, comm);
    const auto         &params  = model.params;
    Mechanics::Problem &problem = *model.problem;
    logger.line(model.banner(run));
    AssertThrow(!params.mixed(),
                dealii::ExcMessage(
                  "Problem = elastodynamics: the inertia is implemented for "
                  "Material / Incompressibility = penalty only."));
    AssertThrow(params.density > 0.0,
                dealii::ExcMessage("Problem = elastodynamics needs Mechanics / "
                                   "Density > 0 (kg/m^3)."));
    const auto pressure_curve = LoadCurveParameters::create(prm, "Pressure");
    const auto tension_curve =
      LoadCurveParameters::create(prm, "Active stress");
    AssertThrow(!params.pressure_boundaries().empty() ||
                  pressure_curve->value(run.start_time) == 0.0,
                dealii::ExcMessage(
                  "Problem = elastodynamics: Elastodynamics / Pressure is set "
                  "but Mechanics / Pressure boundary is empty: name the "
                  "boundary part that carries it."));

    std::vector<dealii::Point<3>> reference_points;
    for (const auto &p : params.tracked_points)
      reference_points.push_back(p.position);

    IO::ResultsFile      results(run.output_directory, parameter_text, comm);
    Postprocess::Manager postprocess(Postprocess::Parameters::parse(prm),
                                     problem,
                                     model.names,
                                     &logger);
    Progress             progress(logger,
                      Progress::parse_mode(run.progress),
                      run.start_time,
                      run.end_time);

    // The loads at the start; the ODE curves integrate from t = 0.
    double time = run.start_time;
    pressure_curve->accept(time);
    tension_curve->accept(time);
    double pressure = pressure_curve->value(time);
    double tension  = tension_curve->value(time);
    problem.start_dynamics(pressure, tension);
    problem.save();
    const bool has_pressure = !params.pressure_boundaries().empty();
    const auto pressures_of = [&](const double p) {
      dealii::Vector<double> pressures(
        has_pressure ? params.pressure_boundaries().size() : 0);
      for (auto &value : pressures)
        value = p;
      return pressures;
    };

    unsigned int step       = 0;
    double       dissipated = 0.0, work = 0.0;
    auto powers = problem.accepted_powers(pressures_of(pressure), tension);
    const auto write_row = [&](const Mechanics::NewtonReport &report,
                               const double                   time_step) {
      std::vector<IO::Column> row = {
        {"step", "-", static_cast<double>(step)},
        {"time", "ms", time},
        {"time_step", "ms", time_step},
        {"pressure", "kPa", pressure},
        {"pressure_mmHg", "mmHg", Units::kPa_to_mmHg(pressure)},
        {"active_tension", "kPa", tension},
        {"newton_iterations", "-", static_cast<double>(report.iterations)},
        {"chord_iterations",
         "-",
         static_cast<double>(report.reused_iterations)},
        {"linear_iterations",
         "-",
         static_cast<double>(report.linear_iterations)},
        {"residual", "mN", report.final_residual}};
      if (problem.n_cavities() == 1)
        {
          const double volume = problem.cavity_volume();
          row.push_back({"volume", "mm^3", volume});
          row.push_back({"volume_mL", "mL", Units::mm3_to_mL(volume)});
        }
      else if (problem.n_cavities() > 1)
        {
          const auto volumes = problem.cavity_volumes();
          const auto names   = problem.cavity_names();
          for (unsigned int c = 0; c < volumes.size(); ++c)
            row.push_back(
              {names[c] + "_volume_mL", "mL", Units::mm3_to_mL(volumes[c])});
        }
      const auto deformed = problem.deformed_positions(reference_points);
      for (unsigned int i = 0; i < deformed.size(); ++i)
        for (unsigned int d = 0; d < 3; ++d)
          row.push_back({params.tracked_points[i].name + "_" + "xyz"[d],
                         "mm",
                         deformed[i][d]});
      // Energies [µJ = kPa mm^3]: kinetic + strain + support + dissipated =
      // work of the loads + the initial stored energy, to the scheme's
      // accuracy.
      row.push_back({"kinetic_energy", "uJ", problem.kinetic_energy()});
      row.push_back({"strain_energy", "uJ", problem.strain_energy()});
      row.push_back({"support_energy", "uJ", problem.support_energy()});
      row.push_back({"dissipated_energy", "uJ", dissipated});
      row.push_back({"load_work", "uJ", work});
      postprocess.step(time,
                       0,
                       0.0,
                       problem.n_cavities() == 1
                         ? problem.cavity_volume()
                         : std::numeric_limits<double>::quiet_NaN(),
                       row);
      results.append_timeseries(row);
      const bool last = time >= run.end_time - 1e-9;
      if (run.field_output_interval > 0 &&
          (step % run.field_output_interval == 0 || last))
        {
          dealii::DataOut<3> data_out;
          problem.attach_output(data_out);
          postprocess.attach_output(data_out);
          data_out.build_patches(problem.mapping(),
                                 problem.cell_kind().output_subdivisions(
                                   run.polynomial_degree));
          results.write_fields(data_out, step, time);
        }
    };
    write_row({}, 0.0);

    const double nominal  = run.time_step;
    const double smallest = nominal / std::pow(2.0, params.max_step_cuts);
    double       sub_step = nominal;
    unsigned int cuts = 0, total_newton = 0, total_chord = 0, total_linear = 0,
                 total_solves = 0;
    while (time < run.end_time - 1e-9 * nominal)
      {
        const double dt   = std::min(sub_step, run.end_time - time);
        const double next = time + dt;
        progress.update(step, time, "elastodynamics");
        const double next_pressure = pressure_curve->value(next);
        const double next_tension  = tension_curve->value(next);
        logger.stream() << "  Time step " << step + 1 << ": t = " << next
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
            ++cuts;
            AssertThrow(sub_step > smallest * 1.5,
                        dealii::ExcMessage(
                          "The elastodynamics did not converge at t = " +
                          dealii::Utilities::to_string(next) +
                          " ms with a "
                          "step of " +
                          dealii::Utilities::to_string(dt) + " ms after " +
                          std::to_string(params.max_step_cuts) +
                          " step cuts (" + one_line_message(e) +
                          "). The loads may be too large for the material, or "
                          "the mesh too coarse; the results file holds the " +
                          std::to_string(step) + " converged steps."));
            sub_step *= 0.5;
            logger.stream() << "  Newton failed (" << one_line_message(e)
                            << "); cutting the time step to " << sub_step
                            << " ms" << std::endl;
            continue;
          }
        problem.accept_time_step(next_pressure, next_tension);
        problem.save();
        pressure_curve->accept(next);
        tension_curve->accept(next);
        // The energy flows by the trapezoidal rule over the step.
        const auto next_powers =
          problem.accepted_powers(pressures_of(next_pressure), next_tension);
        dissipated += 0.5 * dt * (powers.dissipation + next_powers.dissipation);
        work += 0.5 * dt * (powers.loads + next_powers.loads);
        powers   = next_powers;
        time     = next;
        pressure = next_pressure;
        tension  = next_tension;
        ++step;
        total_newton += report.iterations;
        total_chord += report.reused_iterations;
        total_linear += report.linear_iterations;
        total_solves += report.iterations + report.reused_iterations;
        write_row(report, dt);
        // Back towards the nominal step after an easy one.
        if (sub_step < nominal && report.easy())
          sub_step = std::min(2.0 * sub_step, nominal);
        if (interrupted(comm))
          {
            logger.line("Interrupted: " + results.path() + " holds steps 0.." +
                        std::to_string(step) + ".");
            break;
          }
      }

    const SolveCounts       counts{step,
                             cuts,
                             total_newton,
                             total_chord,
                             total_linear,
                             total_solves};
    std::vector<IO::Column> summary = model.solve_summary("time_steps", counts);
    postprocess.end_beat(nullptr, summary);
    results.append_summary(summary);
    std::vector<std::pair<std::string, std::string>> texts;
    auto       statistics = model.statistics(texts);
    const auto counted = MechanicsModel::solve_statistics("time_steps", counts);
    statistics.insert(statistics.end(), counted.begin(), counted.end());
    results.write_statistics(statistics, texts);
    std::ostringstream o;
    o << step << " time steps (" << cuts << " cuts), " << total_newton
      << " Newton iterations, " << total_chord << " chord iterations, "
      << total_linear << " Krylov iterations";
    logger.line(o.str());
    logger.line("Wrote " + results.path());
  }
} // namespace systole
