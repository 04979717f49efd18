#pragma once

#include "simulation/problem_type.h"

namespace systole
{
  /// Run the "heartbeat" problem: the left ventricle beats, coupled to a
  /// Windkessel afterload. The cavity volume V is a state of the circulation
  /// ODE (Circulation::CardiacCycle, SUNDIALS ARKode with root finding for
  /// the valve events); every evaluation of its right-hand side solves the
  /// mechanics at (t, V) with the cavity pressure as the Lagrange multiplier
  /// of the volume constraint (Mechanics::Problem::solve_volume), under the
  /// Bestel active tension of the time. Writes one time-series row per
  /// accepted step, one /events row per valve event and one /summary row per
  /// beat.
  void
  run_heartbeat_problem(const RunInputs &in);
} // namespace systole
