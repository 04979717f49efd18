#pragma once

#include "circulation/phase.h"

/// @file
/// Plain records the CardiacCycle hands to its observer: one per accepted
/// step and one per valve event. Internal units (kPa, ms, mm^3, mm^3/ms).

namespace systole::Circulation
{
  /// The state at the end of one accepted integrator step (or the initial
  /// state, with step_size 0).
  struct StepRecord
  {
    double       time = 0; ///< [ms]
    unsigned int beat = 0; ///< beat k covers [k T, (k+1) T)
    /// Phase during the step that ends here: at a valve event this is the
    /// phase before the event (the Transition carries the new one).
    Phase  phase    = Phase::filling;
    double pressure = 0; ///< cavity pressure p [kPa]
    double volume   = 0; ///< cavity volume V [mm^3]
    /// Q_ao [mm^3/ms] (1 mm^3/ms = 1 mL/s); 0 unless ejecting.
    double aortic_outflow = 0;
    /// Q_mv [mm^3/ms]; 0 unless filling (may be slightly negative before
    /// the contraction onset arms the mitral closure).
    double mitral_inflow = 0;
    /// Net outflow Q_ao - Q_mv = -dV/dt [mm^3/ms].
    double flow = 0;
    /// Distal (Windkessel capacitor) pressure p_ar [kPa].
    double arterial_pressure = 0;
    /// Aortic root pressure p_ar + R_s Q_ao [kPa].
    double aortic_pressure = 0;
    /// Length of the step that ends here [ms].
    double step_size = 0;
    /// Integral of Q_ao from time 0 [mm^3].
    double cumulative_aortic_outflow = 0;
    /// Integral of Q_mv from time 0 [mm^3].
    double cumulative_mitral_inflow = 0;
  };

  /// A valve event, located in time by root finding.
  struct Transition
  {
    double       time              = 0; ///< [ms]
    unsigned int beat              = 0;
    Phase        from              = Phase::filling;
    Phase        to                = Phase::filling;
    double       pressure          = 0; ///< cavity pressure [kPa]
    double       volume            = 0; ///< cavity volume [mm^3]
    double       arterial_pressure = 0; ///< p_ar [kPa]
  };
} // namespace systole::Circulation
