#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria_base.h>

#include "geometry/boundary_names.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "io/results_file.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/parameters.h"
#include "mechanics/problem.h"

#include <functional>
#include <memory>
#include <string>

namespace systole
{
  class Logger;
  struct RunParameters;
  namespace Postprocess
  {
    class Manager;
  }

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

    SolveCounts &
    operator+=(const SolveCounts &other);
  };

  /// A ramp of the loads (MechanicsModel::ramp_load()): the loads at load
  /// fraction 1, and what to call around the steps (before_step and
  /// after_step may be empty).
  struct LoadRamp
  {
    double pressure       = 0; ///< [kPa]
    double active_tension = 0; ///< [kPa]
    /// Before the solve of the step from load @p fraction to @p target.
    std::function<void(const SolveCounts &counts,
                       const double       fraction,
                       const double       target)>
      before_step;
    /// After a converged step (counted in @p counts), at its @p fraction.
    std::function<void(const SolveCounts             &counts,
                       const double                   fraction,
                       const Mechanics::NewtonReport &report)>
      after_step;
    /// The message when the step cuts ran out at @p target, @p e the last
    /// failure.
    std::function<std::string(const SolveCounts    &counts,
                              const double          target,
                              const std::exception &e)>
      failure;
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

    /// Appends the counts of a solve to @p row: newton_iterations,
    /// chord_iterations, linear_iterations and the final residual [mN].
    static void
    append_solve_columns(const Mechanics::NewtonReport &report,
                         std::vector<IO::Column>       &row);

    /// Appends the columns of the deformed shape to @p row: with one cavity
    /// its volume [mm^3] and volume_mL, with several <part>_volume_mL each
    /// (named after its boundary part), and the tracked points' positions
    /// <name>_x, _y, _z [mm] (Mechanics / Tracked points). Collective.
    void
    append_shape_columns(std::vector<IO::Column> &row) const;

    /// Writes the output of step @p step at @p time (a time [ms] or a load
    /// fraction): the postprocessors' columns into @p row, @p row into
    /// /timeseries and, every Output / Field output interval steps and at
    /// the @p last step, the fields. Collective.
    void
    write_step(const RunParameters     &run,
               const unsigned int       step,
               const double             time,
               const bool               last,
               std::vector<IO::Column> &row,
               Postprocess::Manager    &postprocess,
               IO::ResultsFile         &results) const;

    /// Loads the problem from load fraction 0 to 1 of @p ramp in Mechanics /
    /// Load steps equal steps, adapted (Mechanics / Adaptive load steps) to
    /// how hard Newton worked: grown after an easy step
    /// (NewtonReport::easy(): at most 4 iterations; after accelerated chords
    /// also no shortened update), shrunk after a hard one (8 or more), so
    /// that the steps follow the nonlinearity of the response (the
    /// exponential laws are soft first, stiff later). Each step is
    /// extrapolated from the last, but never further than the last
    /// increment and only where it lowers the residual (the exponential laws
    /// stiffen, and the extrapolation overshoots). A failed solve is
    /// restored and its step halved, at most Mechanics / Maximum step cuts
    /// times (then ExcMessage(ramp.failure())). Returns the counts.
    SolveCounts
    ramp_load(const LoadRamp &ramp, Logger &logger);

    /// The postprocessors of Postprocess in @p prm on this problem.
    Postprocess::Manager
    postprocessors(const dealii::ParameterHandler &prm, Logger &logger) const;

    /// Writes the end of a run of solves counted by @p counts: the /summary
    /// row (solve_summary() with the postprocessors' end-of-run columns)
    /// and /statistics (statistics() and solve_statistics()).
    void
    write_solve_summary(const std::string    &steps_name,
                        const SolveCounts    &counts,
                        Postprocess::Manager &postprocess,
                        IO::ResultsFile      &results) const;

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
