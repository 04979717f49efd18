#pragma once

#include "simulation/problem_type.h"

namespace systole
{
  /// Declares subsection Elastodynamics: the loads of Problem =
  /// elastodynamics as functions of time (LoadCurveParameters).
  void
  declare_elastodynamics_parameters(dealii::ParameterHandler &prm);

  /// Checks subsection Elastodynamics (builds the load curves once).
  void
  validate_elastodynamics_parameters(const dealii::ParameterHandler &prm);

  /// Run the "elastodynamics" problem: the mechanics of the parameter file
  /// with inertia (Mechanics / Density), Kelvin-Voigt viscosity, Rayleigh
  /// damping and spring-dashpot supports, integrated by the generalized-
  /// alpha method from Time / Start time to End time in steps of Time /
  /// Time step (a step whose Newton fails is halved, up to Mechanics /
  /// Maximum step cuts times; the step grows back after easy ones), under
  /// the follower pressure p(t) on Mechanics / Pressure boundary and the
  /// fibre active stress tau(t) of subsection Elastodynamics. Starts at rest
  /// in the reference configuration. One time-series row per step: loads,
  /// Newton counts, cavity volume, tracked points, kinetic, strain and
  /// support energies, the dissipated energy and the work of the loads
  /// (their time integrals by the trapezoidal rule); fields every Output /
  /// Field output interval steps.
  void
  run_elastodynamics_problem(const RunInputs &in);
} // namespace systole
