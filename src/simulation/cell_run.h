#pragma once

#include "simulation/problem_type.h"

namespace systole
{
  /// Run the "cell" problem: one cell of Electrophysiology / Ionic model
  /// (its subsection), paced as subsection Cell says and integrated with the
  /// entries of subsection Electrophysiology (Time step, ARKode order, ...),
  /// from Time / Start time to End time (Electrophysiology::SingleCell).
  /// Every Time / Time step a /timeseries row (time, beat, potential_mV,
  /// calcium_uM: NaN for a model without calcium); at the end of every beat
  /// a /summary row (beat, resting_potential_mV, peak_potential_mV,
  /// APD90_ms, peak_calcium_uM, arkode_steps), measured on every ARKode step
  /// (Electrophysiology::ActionPotentialRecorder).
  void
  run_cell_problem(const RunInputs &in);
} // namespace systole
