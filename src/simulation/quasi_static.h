#pragma once

#include "simulation/problem_type.h"

namespace systole
{
  /// Run the "mechanics" problem: build the mesh, ramp the pressure and the
  /// active tension from zero to their full values in load steps (halving a
  /// step whose Newton solve fails), and write one time-series row per
  /// converged step (load fraction, loads, Newton iterations, cavity volume,
  /// tracked points) and the displacement field.
  void
  run_quasi_static_problem(const RunInputs &in);
} // namespace systole
