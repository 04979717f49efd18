#pragma once

#include "simulation/problem_type.h"

namespace systole
{
  /// Run the "electrophysiology" problem: the monodomain model alone
  /// (subsection Electrophysiology) on the mesh of subsection Geometry with
  /// the fibres of subsection Fibres, from Time / Start time to End time.
  /// Every Time / Time step it writes a time-series row (time, activated
  /// volume fraction, ARKode steps and CG iterations of the interval, the
  /// potential at the probes, and their calcium `<probe>_calcium_uM` for a
  /// model with calcium); every Output / Field output interval rows the
  /// potential and activation-time fields; at the end one /summary row
  /// (first, last, total and 90 % activation times, the probes' activation
  /// times, cost counters) and a log line with the EP cost per step and DOF.
  void
  run_electrophysiology_problem(const RunInputs &in);
} // namespace systole
