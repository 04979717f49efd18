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
    MechanicsModel      model(in.prm, in.run, in.logger, in.comm);
    const auto         &params  = model.params;
    Mechanics::Problem &problem = *model.problem;
    in.logger.line(model.banner(in.run));

    IO::ResultsFile      results(in.run.output_directory,
                            in.parameter_text,
                            in.comm);
    Postprocess::Manager postprocess(Postprocess::Parameters::parse(in.prm),
                                     problem,
                                     model.names,
                                     &in.logger);
    Progress             progress(in.logger,
                      Progress::parse_mode(in.run.progress),
                      0.0,
                      1.0);

    unsigned int step      = 0;
    const auto   write_row = [&](const double                   fraction,
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
    write_row(0.0, {});

    const double nominal        = 1.0 / params.load_steps;
    double       fraction       = 0.0;
    double       increment      = nominal;
    double       last_increment = nominal;
    unsigned int cuts           = 0;
    unsigned int total_newton = 0, total_chord = 0, total_linear = 0,
                 total_solves = 0;
    problem.save();
    while (fraction < 1.0 - 1e-12)
      {
        increment           = std::min(increment, 1.0 - fraction);
        const double target = fraction + increment;
        progress.update(step, fraction, "mechanics");
        in.logger.stream() << "  Load step " << step + 1 << ": load fraction "
                           << target << std::endl;
        // Extrapolate, but never further than the last increment and only
        // where it lowers the residual: the exponential laws stiffen, and
        // the extrapolation overshoots.
        problem.predict(std::min(increment / last_increment, 1.0),
                        target * params.pressure,
                        target * params.active_tension);
        try
          {
            const auto report = problem.solve(target * params.pressure,
                                              target * params.active_tension);
            problem.save();
            total_newton += report.iterations;
            total_chord += report.reused_iterations;
            total_linear += report.linear_iterations;
            total_solves += report.iterations + report.reused_iterations;
            fraction       = target;
            last_increment = increment;
            ++step;
            write_row(fraction, report);
            // Adapt the increment to how hard Newton worked: grow it after
            // an easy step (NewtonReport::easy(): at most 4 iterations; after
            // accelerated chords also no shortened update), shrink it after a
            // hard one (8 or more), so that the steps follow the nonlinearity
            // of the response (the exponential laws are soft first, stiff
            // later).
            if (params.adaptive_load_steps && report.easy())
              increment *= 1.5;
            else if (params.adaptive_load_steps && report.hard())
              increment *= 0.5;
          }
        catch (const ExcNewtonDidNotConverge &e)
          {
            problem.restore();
            ++cuts;
            AssertThrow(cuts <= params.max_step_cuts,
                        dealii::ExcMessage(
                          "The mechanics did not converge at load fraction " +
                          dealii::Utilities::to_string(target) + " after " +
                          std::to_string(params.max_step_cuts) +
                          " step cuts (" + one_line_message(e) +
                          "). The load may be too large for the material, or "
                          "the mesh too coarse; the results file holds the " +
                          std::to_string(step) + " converged steps."));
            increment *= 0.5;
            in.logger.stream()
              << "  Newton failed (" << one_line_message(e)
              << "); cutting the load step to " << increment << std::endl;
          }
      }
    // One summary row: sizes, counts and the mechanics' timer sections
    // (this rank's wall times), read by scripts/bench.
    const SolveCounts counts{step,
                             cuts,
                             total_newton,
                             total_chord,
                             total_linear,
                             total_solves};
    model.write_solve_summary("load_steps", counts, postprocess, results);
    in.logger.line("Wrote " + results.path());
  }
} // namespace systole
