#pragma once

#include "simulation/problem_type.h"

namespace systole
{
  /// Run the "circulation" problem: the 0D model of "Circulation / Model"
  /// alone, with elastance ventricles (Circulation::Integrator: SUNDIALS
  /// ARKode, implicit, the tolerances and step limits of subsection
  /// Circulation, valve events located by root finding), for Circulation /
  /// Number of beats beats or until the EDVs are periodic (Periodicity
  /// tolerance). Writes:
  /// - /timeseries: a row at every multiple of Time / Time step and at every
  ///   beat end, exact times (steps end there): time, beat, every state and
  ///   output in clinical units (lv_volume_mL, lv_pressure_mmHg,
  ///   aortic_valve_flow_mL_per_s, ...), the phase of each cavity
  ///   (lv_phase, codes of Circulation::Phase) and total_blood_volume_mL;
  /// - /events: one row per valve event (time, beat, valve index, opens,
  ///   each cavity's volume and pressure);
  /// - /summary: one row per beat (Circulation::ModelBeatRecorder: columns
  ///   prefixed per ventricle, lv_EDV_mL, lv_EF, lv_peak_pressure_mmHg, rv_...,
  ///   and max/min/mean of every pressure).
  void
  run_circulation_problem(const RunInputs &in);
} // namespace systole
