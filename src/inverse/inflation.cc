#include "inverse/inflation.h"

#include <deal.II/base/function.h>
#include <deal.II/base/utilities.h>

#include "base/errors.h"
#include "base/logger.h"
#include "base/units.h"
#include "mechanics/problem.h"

#include "inverse/adjustable_law.h"

#include <algorithm>
#include <cmath>

namespace systole::Inverse
{
  PassiveInflation::PassiveInflation(Mechanics::Problem        &problem,
                                     AdjustableLaw             &law,
                                     const LawRebuilder        &rebuilder,
                                     const std::vector<double> &pressures,
                                     const double               max_step,
                                     const unsigned int         max_step_cuts,
                                     Logger                    &logger)
    : problem(problem)
    , law(law)
    , rebuilder(rebuilder)
    , pressures(pressures)
    , max_step(max_step)
    , max_step_cuts(max_step_cuts)
    , logger(logger)
  {
    AssertThrow(!pressures.empty() && pressures.front() > 0 &&
                  std::is_sorted(pressures.begin(), pressures.end()),
                dealii::ExcMessage("The target pressures of a calibration "
                                   "must be positive and ascending."));
    AssertThrow(max_step > 0, dealii::ExcInternalError());
    AssertThrow(problem.n_cavities() == 1,
                dealii::ExcMessage(
                  "A calibration to a pressure-volume relation needs one "
                  "cavity: a mesh with a base and Mechanics / Pressure "
                  "boundary naming one part (the endocardium)."));
  }

  std::vector<double>
  PassiveInflation::volumes(const std::vector<double> &values,
                            std::vector<double>       *derivatives,
                            const double               h)
  {
    const unsigned int n = values.size(), m = pressures.size();
    law.set(rebuilder.build(values));
    ++totals.inflations;

    problem.set_displacement(dealii::Functions::ZeroFunction<3>(3));
    problem.save();
    problem.save(); // no secant predictor from an earlier inflation

    std::vector<double> V(m);
    if (derivatives)
      derivatives->assign(m * n, 0.0);
    double       p         = 0;
    double       last_step = 0;
    unsigned int cuts      = 0;
    const auto   count     = [&](const Mechanics::NewtonReport &report) {
      ++totals.forward_solves;
      totals.newton_iterations += report.iterations;
      totals.chord_iterations += report.reused_iterations;
    };
    for (unsigned int j = 0; j < m; ++j)
      {
        const double       target = pressures[j];
        const unsigned int n_steps =
          std::max(1u,
                   static_cast<unsigned int>(
                     std::ceil((target - p) / max_step - 1e-9)));
        double step = (target - p) / n_steps;
        while (p < target - 1e-12 * target)
          {
            step = std::min(step, target - p);
            const double next =
              (target - p - step <= 1e-12 * target) ? target : p + step;
            if (last_step > 0)
              problem.predict(std::min((next - p) / last_step, 1.0), next, 0.0);
            try
              {
                count(problem.solve(next, 0.0));
                problem.save();
                last_step = next - p;
                p         = next;
                ++totals.load_steps;
              }
            catch (const ExcNewtonDidNotConverge &e)
              {
                problem.restore();
                ++cuts;
                ++totals.step_cuts;
                AssertThrow(
                  cuts <= max_step_cuts,
                  dealii::ExcMessage(
                    "The inflation of the calibration did not converge at " +
                    dealii::Utilities::to_string(Units::kPa_to_mmHg(next)) +
                    " mmHg after " + std::to_string(max_step_cuts) +
                    " step cuts (" + one_line_message(e) +
                    "). The parameters may be too soft for this pressure: "
                    "raise Calibration / Lower bounds."));
                step *= 0.5;
              }
          }
        p    = target;
        V[j] = problem.cavity_volume();

        if (derivatives)
          {
            // Forward differences, warm-started from the solution at p.
            for (unsigned int i = 0; i < n; ++i)
              {
                std::vector<double> perturbed = values;
                perturbed[i] *= 1 + h;
                law.set(rebuilder.build(perturbed));
                try
                  {
                    count(problem.solve(target, 0.0));
                  }
                catch (const ExcNewtonDidNotConverge &e)
                  {
                    AssertThrow(false,
                                dealii::ExcMessage(
                                  "A finite-difference solve of the "
                                  "calibration failed (" +
                                  one_line_message(e) +
                                  "): reduce Calibration / Finite difference "
                                  "step."));
                  }
                ++totals.perturbed_solves;
                (*derivatives)[j * n + i] =
                  (problem.cavity_volume() - V[j]) / (h * values[i]);
                problem.restore();
              }
            law.set(rebuilder.build(values));
          }
      }
    logger.detail() << "    inflation " << totals.inflations << ": "
                    << totals.forward_solves << " solves so far" << std::endl;
    return V;
  }
} // namespace systole::Inverse
