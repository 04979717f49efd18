#pragma once

#include <vector>

namespace systole
{
  class Logger;
}

namespace systole::Mechanics
{
  class Problem;
}

namespace systole::Inverse
{
  class AdjustableLaw;
  class LawRebuilder;

  /// The cost of the inflations so far.
  struct InflationCounts
  {
    unsigned int inflations        = 0; ///< calls of volumes()
    unsigned int load_steps        = 0; ///< converged steps of the ramps
    unsigned int step_cuts         = 0;
    unsigned int forward_solves    = 0; ///< Newton solves (all of them)
    unsigned int perturbed_solves  = 0; ///< of those, the FD solves
    unsigned int newton_iterations = 0; ///< with a new tangent
    unsigned int chord_iterations  = 0; ///< on an earlier factorization
  };

  /// The end-diastolic pressure-volume relation of a passive ventricle as a
  /// function of some of its law's parameters: a pressure inflation from
  /// the reference (zero displacement), load-stepped as Problem = mechanics
  /// (secant predictor where it lowers the residual, halving a step whose
  /// Newton fails), through every target pressure, the cavity volume at each.
  ///
  /// Derivatives by forward differences in parameter space, at each target
  /// pressure: after the converged solve there, every parameter in turn is
  /// scaled by (1 + h) and the same pressure solved again, warm-started from
  /// the converged displacement (and with the linear solver's last
  /// factorization, Mechanics / Reuse factorization); then the displacement
  /// goes back to the unperturbed solution and the ramp continues. A
  /// perturbed solve needs one or two Newton iterations.
  class PassiveInflation
  {
  public:
    /// @param[in] pressures target pressures [kPa], ascending, > 0
    /// @param[in] max_step largest pressure increment of the ramp [kPa]
    PassiveInflation(Mechanics::Problem        &problem,
                     AdjustableLaw             &law,
                     const LawRebuilder        &rebuilder,
                     const std::vector<double> &pressures,
                     const double               max_step,
                     const unsigned int         max_step_cuts,
                     Logger                    &logger);

    /// The cavity volumes [mm^3] at the target pressures with the law's
    /// entries set to @p values; with @p derivatives, also dV_i/dvalue_j
    /// [mm^3 per unit of the entry] (row-major, pressures x values), by
    /// forward differences of relative step @p h. Collective. Throws
    /// ExcMessage when the ramp fails after the step cuts.
    std::vector<double>
    volumes(const std::vector<double> &values,
            std::vector<double>       *derivatives,
            const double               h);

    const InflationCounts &
    counts() const
    {
      return totals;
    }

  private:
    Mechanics::Problem &problem;
    AdjustableLaw      &law;
    const LawRebuilder &rebuilder;
    std::vector<double> pressures;
    double              max_step;
    unsigned int        max_step_cuts;
    Logger             &logger;
    InflationCounts     totals;
  };
} // namespace systole::Inverse
