#pragma once

#include "simulation/problem_type.h"

#include <string>
#include <utility>
#include <vector>

namespace systole
{
  /// Subsection Calibration: which passive parameters to fit, to what.
  struct CalibrationParameters
  {
    /// Entries of subsection Material / <Passive law> to fit (1 to 4).
    std::vector<std::string> parameters;
    /// Bounds of the fitted scale factors (fitted value / file value).
    std::vector<double> lower, upper;
    /// "pressure-volume pairs", "Klotz" or "synthetic".
    std::string target;
    /// (p [mmHg], V [mL]) of Target = pressure-volume pairs.
    std::vector<std::pair<double, double>> pairs;
    /// Pressures [mmHg] of Target = Klotz and synthetic.
    std::vector<double> pressures_mmHg;
    double              klotz_edp_mmHg = 10;
    double              klotz_edv_mL   = 0; ///< 0: the model's own
    std::vector<double> synthetic_values;   ///< the truth (entry units)
    double              synthetic_noise        = 0;
    unsigned int        noise_seed             = 42;
    double              finite_difference_step = 1e-3;
    double              pressure_step_mmHg     = 2.5;
    unsigned int        max_iterations         = 30;
    /// "given" (the mesh is the reference) or "unloaded" (the mesh is the
    /// image at Unloading / Image pressure).
    std::string reference          = "given";
    double      residual_tolerance = 0; ///< on |r| (relative residuals)

    /// Declares subsection Calibration.
    static void
    declare(dealii::ParameterHandler &prm);

    /// Parses and validates it (one clear message per bad entry).
    static CalibrationParameters
    parse(const dealii::ParameterHandler &prm);
  };

  /// Run the "calibration" problem: fit the passive parameters of subsection
  /// Calibration by bounded least squares (PETSc TAO, Gauss-Newton with
  /// finite-difference derivatives) to a target end-diastolic
  /// pressure-volume relation, each evaluation a pressure inflation of the
  /// mechanics (Inverse::PassiveInflation). The residuals are relative,
  /// V_model / V_target - 1. Writes /timeseries (one row per inflation),
  /// /calibration/parameters, /calibration/edpvr, /calibration/fit and
  /// /statistics.
  void
  run_calibration_problem(const RunInputs &in);
} // namespace systole
