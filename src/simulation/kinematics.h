#pragma once

#include "simulation/problem_type.h"

#include <string>
#include <vector>

namespace systole
{
  /// Prescribed motion of the "cavity volume" problem: a uniform stretch about
  /// the centre of the base, lambda(t) = 1 + A sin^2(pi t / T), so the exact
  /// cavity volume is lambda^3 V_0.
  struct KinematicsParameters
  {
    double amplitude = 0.1;   ///< A [-]
    double period    = 100.0; ///< T [ms]
    /// Boundary parts that each bound a cavity closed by the base plane.
    std::vector<std::string> cavities = {"endocardium"};

    static void
    declare(dealii::ParameterHandler &prm);
    static KinematicsParameters
    parse(const dealii::ParameterHandler &prm);

    /// lambda(t)
    double
    stretch(const double time) const;
  };

  /// Run the "cavity volume" problem: mesh, undeformed cavity volume, then the
  /// prescribed motion step by step, writing the time series (time, step,
  /// stretch, volume, volume_mL; with several cavities <part>_volume and
  /// <part>_volume_mL instead) and the displacement field to the results
  /// file.
  void
  run_cavity_volume_problem(const RunInputs &in);
} // namespace systole
