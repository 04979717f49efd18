#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/distributed/tria_base.h>

#include "geometry/boundary_names.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "io/results_file.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/parameters.h"
#include "mechanics/problem.h"

#include <memory>
#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace systole
{
  class Logger;
  struct RunParameters;

  /// The mechanics of a run as the parameter file describes it: the mesh
  /// (subsection Geometry), the material laws (Material), the fibre field
  /// (Fibres) and the quasi-static problem (Mechanics, Discretization). Shared
  /// by the problems that solve the mechanics (quasi-static load stepping,
  /// heartbeat).
  /// What a run of mechanics solves counted (a load ramp, a time
  /// integration).
  struct SolveCounts
  {
    unsigned int steps = 0, cuts = 0;
    unsigned int newton = 0, chord = 0, linear = 0;
    /// Newton and chord iterations that solved a linear system.
    unsigned int solves = 0;
  };

  struct MechanicsModel
  {
    /// @p saved_mesh: load the mesh from this file (a checkpoint's, see
    /// Geometry::create_distributed_mesh()) instead of refining.
    /// @p passive_law: use this law instead of the one of Material / Passive
    /// law (the calibration passes one whose parameters it changes).
    MechanicsModel(const dealii::ParameterHandler        &prm,
                   const RunParameters                   &run,
                   Logger                                &logger,
                   const MPI_Comm                         comm,
                   const std::string                     &saved_mesh  = "",
                   std::unique_ptr<Materials::PassiveLaw> passive_law = {});

    /// One line for the log: code version, problem, cells, degree, DOFs,
    /// ranks, passive law, linear solver.
    std::string
    banner(const RunParameters &run) const;

    /// The sizes and the mechanics' timer sections for /statistics:
    /// n_dofs, n_cells, n_ranks, "timer: <section>" [s] (this rank's wall
    /// times); @p texts gets discretization and linear_solver.
    std::vector<IO::Column>
    statistics(std::vector<std::pair<std::string, std::string>> &texts) const;

    /// The /summary row of a run of solves: the DOFs of both blocks,
    /// @p steps_name (e.g. load_steps, time_steps) = counts.steps, the step
    /// cuts, Newton, chord and Krylov iterations, Krylov iterations per
    /// solve, and this rank's assembly and linear-solver wall times [s].
    std::vector<IO::Column>
    solve_summary(const std::string &steps_name,
                  const SolveCounts &counts) const;

    /// The counts of a run of solves for /statistics (@p steps_name, cuts,
    /// Newton and Krylov iterations), to append to statistics().
    static std::vector<IO::Column>
    solve_statistics(const std::string &steps_name, const SolveCounts &counts);

    Geometry::Parameters                   geometry;
    Mechanics::Parameters                  params;
    std::unique_ptr<Materials::PassiveLaw> passive;
    Materials::VolumetricLaw               volumetric;
    /// The mesh: hexahedra on p4est, tetrahedra fully distributed
    /// (Geometry::create_distributed_mesh()).
    Geometry::DistributedMesh                          mesh;
    dealii::parallel::DistributedTriangulationBase<3> &tria;
    const Geometry::BoundaryNames                     &names;
    std::unique_ptr<Mechanics::Problem>                problem;
  };
} // namespace systole
