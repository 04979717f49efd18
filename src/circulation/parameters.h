#pragma once

#include <deal.II/base/parameter_handler.h>

#include "circulation/windkessel.h"

namespace systole::Circulation
{
  /// The beats and the adaptive time steps of the circulation and heartbeat
  /// problems (subsection "Circulation"; Parameters::steps), in internal
  /// units. The heartbeat's stepper takes them as they are
  /// (HeartbeatStepper::Settings); the circulation problem's integrator the
  /// tolerances and steps. The defaults are the parameter file's.
  struct StepControl
  {
    /// Length of one beat [ms].
    double period = 800.0;
    /// Largest number of beats to run.
    unsigned int n_max_beats = 4;
    /// The run stops after beat k >= 1 when |EDV_k - EDV_(k-1)| / EDV_(k-1)
    /// is below this (0: never, run n_max_beats).
    double periodicity_tolerance = 0.01;

    /// Relative tolerance of the adaptive steps (the circulation problem's
    /// ODE integrator; the heartbeat's BDF error and pressure curvature).
    double relative_tolerance = 1e-4;
    /// Absolute tolerance of volumes [mm^3]; that of p_ar is this / C.
    double absolute_volume_tolerance = Units::mL_to_mm3(1e-3);
    /// Absolute tolerance of the 3D cavity pressures [kPa] (heartbeat).
    double absolute_pressure_tolerance = Units::mmHg_to_kPa(0.1);
    /// How long after a valve event the step that crosses it may end [ms]
    /// (heartbeat).
    double event_time_tolerance = 0.1;
    /// How far the displacement predictor of the next coupled step may miss
    /// [mm] (heartbeat: CoupledVentricles::predictor_error(); 0: not
    /// controlled).
    double displacement_tolerance = 0.25;
    /// The Newton iterations with a new tangent a coupled step aims at
    /// (heartbeat: CoupledVentricles::last_tangent_iterations(); 0: not
    /// controlled).
    unsigned int newton_iterations_target = 3;
    /// Largest step [ms].
    double max_step = 10.0;
    /// First step, and the step after every valve event [ms].
    double initial_step = 0.5;
    /// Failed solves of the ventricles in a row (each halves the step)
    /// before the run stops (heartbeat; not a parameter-file entry).
    unsigned int max_step_cuts = 10;
  };

  /// Settings of the 0D circulation (subsection "Circulation"), in internal
  /// units (kPa, ms, mm^3). The parameter file gives pressures in mmHg,
  /// volumes in mL, resistances in mmHg s/mL and compliances in mL/mmHg;
  /// parse() converts them once. The default member values equal the
  /// parameter-file defaults, so tests can build a Parameters directly.
  struct Parameters
  {
    Windkessel::Parameters windkessel;

    /// R_mv [kPa ms/mm^3]: Q_mv = (p_at - p) / R_mv while the mitral valve is
    /// open.
    double mitral_valve_resistance = resistance_from_mmHg_s_per_mL(0.0075);
    /// p_at [kPa], constant.
    double atrial_pressure = Units::mmHg_to_kPa(10.0);
    /// p_ar(0) [kPa].
    double initial_arterial_pressure = Units::mmHg_to_kPa(80.0);

    /// The beats and the time steps.
    StepControl steps;

    static void
    declare(dealii::ParameterHandler &prm);

    /// Reads subsection "Circulation", converts to internal units and
    /// validates; throws ExcMessage naming the entry for invalid values.
    static Parameters
    parse(const dealii::ParameterHandler &prm);

    /// Throws ExcMessage naming the entry ("Circulation / Compliance ...") if
    /// a value is out of range. parse() calls it; call it yourself on a
    /// Parameters built in code.
    void
    validate() const;
  };
} // namespace systole::Circulation
