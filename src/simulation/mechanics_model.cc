#include "simulation/mechanics_model.h"

#include <deal.II/base/parameter_handler.h>

#include "base/logger.h"
#include "fibres/fibre_field.h"
#include "io/results_file.h"
#include "materials/factory.h"
#include "simulation/parameters.h"

#include <sstream>

namespace systole
{
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
    problem = std::make_unique<Mechanics::Problem>(
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
      logger);
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
} // namespace systole
