#include "simulation/mechanics_model.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"
#include "base/logger.h"
#include "base/units.h"
#include "fibres/fibre_field.h"
#include "io/results_file.h"
#include "materials/factory.h"
#include "simulation/parameters.h"

#include "postprocess/manager.h"

#include <algorithm>
#include <limits>
#include <sstream>

namespace systole
{
  SolveCounts &
  SolveCounts::operator+=(const SolveCounts &other)
  {
    steps += other.steps;
    cuts += other.cuts;
    newton += other.newton;
    chord += other.chord;
    linear += other.linear;
    solves += other.solves;
    return *this;
  }

  SolveCounts
  MechanicsModel::ramp_load(const LoadRamp &ramp, Logger &logger)
  {
    SolveCounts  counts;
    const double nominal        = 1.0 / params.load_steps;
    double       fraction       = 0.0;
    double       increment      = nominal;
    double       last_increment = nominal;
    problem->save();
    while (fraction < 1.0 - 1e-12)
      {
        increment           = std::min(increment, 1.0 - fraction);
        const double target = fraction + increment;
        if (ramp.before_step)
          ramp.before_step(counts, fraction, target);
        problem->predict(std::min(increment / last_increment, 1.0),
                         target * ramp.pressure,
                         target * ramp.active_tension);
        try
          {
            const auto report = problem->solve(target * ramp.pressure,
                                               target * ramp.active_tension);
            problem->save();
            counts.newton += report.iterations;
            counts.chord += report.reused_iterations;
            counts.linear += report.linear_iterations;
            counts.solves += report.iterations + report.reused_iterations;
            ++counts.steps;
            fraction       = target;
            last_increment = increment;
            if (ramp.after_step)
              ramp.after_step(counts, fraction, report);
            if (params.adaptive_load_steps && report.easy())
              increment *= 1.5;
            else if (params.adaptive_load_steps && report.hard())
              increment *= 0.5;
          }
        catch (const ExcNewtonDidNotConverge &e)
          {
            problem->restore();
            ++counts.cuts;
            AssertThrow(counts.cuts <= params.max_step_cuts,
                        dealii::ExcMessage(ramp.failure(counts, target, e)));
            increment *= 0.5;
            logger.stream()
              << "  Newton failed (" << one_line_message(e)
              << "); cutting the load step to " << increment << std::endl;
          }
      }
    return counts;
  }

  MechanicsModel::MechanicsModel(
    const dealii::ParameterHandler        &prm,
    const RunParameters                   &run,
    Logger                                &logger,
    const MPI_Comm                         comm,
    const std::string                     &saved_mesh,
    std::unique_ptr<Materials::PassiveLaw> passive_law)
    : geometry(Geometry::Parameters::parse(prm, run.parameter_directory))
    , params(Mechanics::Parameters::parse(prm))
    , passive(passive_law ? std::move(passive_law)
                          : Materials::create_passive_law(prm))
    , volumetric(Materials::create_volumetric_law(prm))
    , mesh(Geometry::create_distributed_mesh(geometry, comm, saved_mesh))
    , tria(*mesh.tria)
    , names(mesh.names)
  {
    problem = std::make_unique<Mechanics::Problem>(Mechanics::Problem::Inputs{
      params,
      tria,
      names,
      run.polynomial_degree,
      run.mapping_degree,
      *passive,
      volumetric,
      Fibres::create_fibre_field(
        Fibres::Parameters::parse(prm, run.parameter_directory),
        geometry.lv_shape,
        tria,
        names,
        &logger),
      logger,
      run.problem == "mechanics"});
  }

  std::vector<IO::Column>
  MechanicsModel::statistics(
    std::vector<std::pair<std::string, std::string>> &texts) const
  {
    std::vector<IO::Column> values = {
      {"n_dofs", "-", static_cast<double>(problem->n_dofs())},
      {"n_cells", "-", static_cast<double>(tria.n_global_active_cells())},
      {"n_ranks",
       "-",
       static_cast<double>(
         dealii::Utilities::MPI::n_mpi_processes(tria.get_communicator()))}};
    for (const auto &[section, seconds] : problem->timings())
      values.push_back(
        {"timer: " + dealii::Utilities::replace_in_string(section, " / ", ": "),
         "s",
         seconds});
    texts.emplace_back("discretization", problem->discretization_name());
    texts.emplace_back("linear_solver", problem->linear_solver_name());
    return values;
  }

  std::vector<IO::Column>
  MechanicsModel::solve_summary(const std::string &steps_name,
                                const SolveCounts &counts) const
  {
    const auto blocks  = problem->n_block_dofs();
    const auto timings = problem->timings();
    const auto seconds = [&](const std::string &section) {
      const auto it = timings.find(section);
      return it == timings.end() ? 0.0 : it->second;
    };
    return {
      {"n_dofs", "-", static_cast<double>(problem->n_dofs())},
      {"n_displacement_dofs", "-", static_cast<double>(blocks[0])},
      {"n_pressure_dofs", "-", static_cast<double>(blocks[1])},
      {steps_name, "-", static_cast<double>(counts.steps)},
      {"step_cuts", "-", static_cast<double>(counts.cuts)},
      {"newton_iterations", "-", static_cast<double>(counts.newton)},
      {"chord_iterations", "-", static_cast<double>(counts.chord)},
      {"linear_iterations", "-", static_cast<double>(counts.linear)},
      {"linear_iterations_per_solve",
       "-",
       counts.solves > 0 ? static_cast<double>(counts.linear) / counts.solves
                         : 0.0},
      {"assembly_seconds", "s", seconds("Mechanics / assembly")},
      {"linear_solver_seconds", "s", seconds("Mechanics / linear solver")}};
  }

  std::vector<IO::Column>
  MechanicsModel::solve_statistics(const std::string &steps_name,
                                   const SolveCounts &counts)
  {
    return {{steps_name, "-", static_cast<double>(counts.steps)},
            {"step_cuts", "-", static_cast<double>(counts.cuts)},
            {"newton_iterations", "-", static_cast<double>(counts.newton)},
            {"linear_iterations", "-", static_cast<double>(counts.linear)}};
  }

  std::string
  MechanicsModel::banner(const RunParameters &run) const
  {
    std::ostringstream o;
    // Three lines, each under 100 columns (the start of a short run's only
    // screen).
    o << IO::code_version() << ": problem '" << run.problem << "', "
      << tria.n_global_active_cells() << " cells, " << problem->n_dofs()
      << " DOFs, "
      << dealii::Utilities::MPI::n_mpi_processes(tria.get_communicator())
      << " rank(s)\n  " << problem->discretization_name() << ", "
      << passive->name() << "\n  linear solver "
      << problem->linear_solver_name();
    return o.str();
  }
  void
  MechanicsModel::append_solve_columns(const Mechanics::NewtonReport &report,
                                       std::vector<IO::Column>       &row)
  {
    row.push_back(
      {"newton_iterations", "-", static_cast<double>(report.iterations)});
    row.push_back(
      {"chord_iterations", "-", static_cast<double>(report.reused_iterations)});
    row.push_back({"linear_iterations",
                   "-",
                   static_cast<double>(report.linear_iterations)});
    row.push_back({"residual", "mN", report.final_residual});
  }

  void
  MechanicsModel::append_shape_columns(std::vector<IO::Column> &row) const
  {
    if (problem->n_cavities() == 1)
      {
        const double volume = problem->cavity_volume();
        row.push_back({"volume", "mm^3", volume});
        row.push_back({"volume_mL", "mL", Units::mm3_to_mL(volume)});
      }
    else if (problem->n_cavities() > 1)
      {
        const auto volumes = problem->cavity_volumes();
        const auto names   = problem->cavity_names();
        for (unsigned int c = 0; c < volumes.size(); ++c)
          row.push_back(
            {names[c] + "_volume_mL", "mL", Units::mm3_to_mL(volumes[c])});
      }
    std::vector<dealii::Point<3>> reference_points;
    for (const auto &p : params.tracked_points)
      reference_points.push_back(p.position);
    const auto deformed = problem->deformed_positions(reference_points);
    for (unsigned int i = 0; i < deformed.size(); ++i)
      for (unsigned int d = 0; d < 3; ++d)
        row.push_back({params.tracked_points[i].name + "_" + "xyz"[d],
                       "mm",
                       deformed[i][d]});
  }

  void
  MechanicsModel::write_step(const RunParameters     &run,
                             const unsigned int       step,
                             const double             time,
                             const bool               last,
                             std::vector<IO::Column> &row,
                             Postprocess::Manager    &postprocess,
                             IO::ResultsFile         &results) const
  {
    postprocess.step(time,
                     0,
                     0.0,
                     problem->n_cavities() == 1
                       ? problem->cavity_volume()
                       : std::numeric_limits<double>::quiet_NaN(),
                     std::nullopt,
                     row);
    results.append_timeseries(row);
    if (run.field_output_interval > 0 &&
        (step % run.field_output_interval == 0 || last))
      {
        dealii::DataOut<3> data_out;
        problem->attach_output(data_out);
        postprocess.attach_output(data_out);
        data_out.build_patches(problem->mapping(),
                               problem->cell_kind().output_subdivisions(
                                 run.polynomial_degree));
        results.write_fields(data_out, step, time);
      }
  }

  Postprocess::Manager
  MechanicsModel::postprocessors(const dealii::ParameterHandler &prm,
                                 Logger                         &logger) const
  {
    return Postprocess::Manager(Postprocess::Parameters::parse(prm),
                                *problem,
                                names,
                                &logger);
  }

  void
  MechanicsModel::write_solve_summary(const std::string    &steps_name,
                                      const SolveCounts    &counts,
                                      Postprocess::Manager &postprocess,
                                      IO::ResultsFile      &results) const
  {
    std::vector<IO::Column> summary = solve_summary(steps_name, counts);
    postprocess.end_beat(nullptr, summary);
    results.append_summary(summary);
    std::vector<std::pair<std::string, std::string>> texts;
    auto       statistics = this->statistics(texts);
    const auto counted    = solve_statistics(steps_name, counts);
    statistics.insert(statistics.end(), counted.begin(), counted.end());
    results.write_statistics(statistics, texts);
  }
} // namespace systole
