#include "simulation/quasi_static.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"
#include "base/logger.h"
#include "base/units.h"
#include "fibres/fibre_field.h"
#include "geometry/mesh.h"
#include "io/results_file.h"
#include "materials/factory.h"
#include "mechanics/problem.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"

#include "postprocess/manager.h"

#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole
{
  namespace
  {
    /// The time-series row of load step @p step at load @p fraction, solved
    /// as @p report says: the loads, the solve, the stored energy (passive
    /// law and volumetric penalty, for energy balances: with a fixed base it
    /// equals the pressure work int p dV) and the deformed shape.
    std::vector<IO::Column>
    load_step_row(const MechanicsModel          &model,
                  const unsigned int             step,
                  const double                   fraction,
                  const Mechanics::NewtonReport &report)
    {
      const Mechanics::Parameters &params = model.params;
      std::vector<IO::Column>      row    = {
                {"step", "-", static_cast<double>(step)},
                {"load_fraction", "-", fraction},
                {"pressure", "kPa", fraction * params.pressure},
                {"pressure_mmHg",
                 "mmHg",
                 Units::kPa_to_mmHg(fraction * params.pressure)},
                {"active_tension", "kPa", fraction * params.active_tension}};
      MechanicsModel::append_solve_columns(report, row);
      if (!params.mixed())
        row.push_back({"strain_energy", "uJ", model.problem->strain_energy()});
      model.append_shape_columns(row);
      return row;
    }
  } // namespace

  void
  run_quasi_static_problem(const RunInputs &in)
  {
    MechanicsModel model(in.prm, in.run, in.logger, in.comm);
    const auto    &params = model.params;
    in.logger.line(model.banner(in.run));

    IO::ResultsFile      results(in.run.output_directory,
                            in.parameter_text,
                            in.comm);
    Postprocess::Manager postprocess = model.postprocessors(in.prm, in.logger);
    Progress             progress(in.logger,
                      Progress::parse_mode(in.run.progress),
                      0.0,
                      1.0);

    const auto write_row = [&](const unsigned int             step,
                               const double                   fraction,
                               const Mechanics::NewtonReport &report) {
      std::vector<IO::Column> row =
        load_step_row(model, step, fraction, report);
      // The chosen postprocessors' columns; time is the load fraction.
      model.write_step(in.run,
                       step,
                       fraction,
                       fraction >= 1.0,
                       row,
                       postprocess,
                       results);
    };
    write_row(0, 0.0, {});

    LoadRamp ramp;
    ramp.pressure       = params.pressure;
    ramp.active_tension = params.active_tension;
    ramp.before_step    = [&](const SolveCounts &counts,
                           const double       fraction,
                           const double       target) {
      progress.update(counts.steps, fraction, "mechanics");
      in.logger.stream() << "  Load step " << counts.steps + 1
                         << ": load fraction " << target << std::endl;
    };
    ramp.after_step = [&](const SolveCounts             &counts,
                          const double                   fraction,
                          const Mechanics::NewtonReport &report) {
      write_row(counts.steps, fraction, report);
    };
    ramp.failure = [&params](const SolveCounts    &counts,
                             const double          target,
                             const std::exception &e) {
      return "The mechanics did not converge at load fraction " +
             dealii::Utilities::to_string(target) + " after " +
             std::to_string(params.max_step_cuts) + " step cuts (" +
             one_line_message(e) +
             "). The load may be too large for the material, or the mesh "
             "too coarse; the results file holds the " +
             std::to_string(counts.steps) + " converged steps.";
    };
    const SolveCounts counts = model.ramp_load(ramp, in.logger);
    // One summary row: sizes, counts and the mechanics' timer sections
    // (this rank's wall times), read by scripts/bench.
    model.write_solve_summary("load_steps", counts, postprocess, results);
    in.logger.line("Wrote " + results.path());
  }
} // namespace systole
