#pragma once

#include <deal.II/lac/vector.h>

#include "circulation/model.h"

#include <functional>
#include <memory>
#include <vector>

namespace systole::Circulation
{
  /// Integrates a 0D circulation Model on its own with SUNDIALS ARKode
  /// (ARKStep, implicit diagonally implicit Runge-Kutta of the chosen order,
  /// adaptive steps) through the project's ARKode adapter
  /// (Electrophysiology::ImexIntegrator, no explicit part):
  /// - Newton's method on the stage equations with the model's analytic
  ///   Jacobian df/dy of every Newton iterate; the stage systems
  ///   (I - gamma J) x = b are solved exactly (dense LU, the state is small);
  /// - valve events located by ARKode's root finding on
  ///   Model::valve_indicators() (both directions), each reported with its
  ///   time and state;
  /// - steps end exactly at the end time of every advance() (ARKode's stop
  ///   time), so output times are exact, not interpolated;
  /// - the absolute tolerance of state i is Settings::absolute_volume_tolerance
  ///   / StateInfo::volume_scale (a volume, the pressure that it would put
  ///   into a compliance, the flow that would carry it in 1 ms).
  /// The step update y_n+1 = y_n + h sum b_i f(z_i) keeps every linear
  /// invariant of f, so the closed loop conserves the blood volume to
  /// round-off whatever the tolerance.
  ///
  /// The state lives in a PETSc vector on MPI_COMM_SELF (the adapter's
  /// vectors; every rank integrates the same loop); the callbacks copy it
  /// to and from the Model's dealii::Vector.
  class Integrator
  {
  public:
    struct Settings
    {
      double relative_tolerance = 1e-6;
      /// Absolute tolerance of volumes [mm^3]; see the class documentation.
      double absolute_volume_tolerance = 1.0;
      double max_step                  = 10.0; ///< [ms]
      double initial_step              = 0.5;  ///< [ms]
      /// Order of the DIRK method, 2 to 5 (ARKode's default tables: 5 is
      /// ARK5(4)8L[2]SA's implicit part, stiffly accurate and L-stable).
      unsigned int order = 5;
    };

    /// A valve opened or closed (its indicator changed sign).
    struct Event
    {
      double                 time;  ///< [ms]
      unsigned int           valve; ///< index into Model::valves()
      bool                   opens; ///< else it closes
      dealii::Vector<double> state; ///< y at the event
    };

    struct Statistics
    {
      unsigned long steps                          = 0;
      unsigned long rhs_evaluations                = 0;
      unsigned long jacobian_evaluations           = 0;
      unsigned long linear_solves                  = 0;
      unsigned long error_test_failures            = 0;
      unsigned long nonlinear_convergence_failures = 0;
    };

    /// The pressures [kPa] of the external cavities at time t (size
    /// n_cavities(), entries of elastance cavities ignored). A model with
    /// external cavities needs it (prescribed pressures: tests, or a 3D
    /// ventricle frozen over a step); the Newton Jacobian then ignores their
    /// dependence on the state.
    using ExternalPressures =
      std::function<void(const double t, dealii::Vector<double> &p_ext)>;

    /// Starts at (@p t0, @p y0). @p model must outlive this object.
    Integrator(const Model                  &model,
               const Settings               &settings,
               const double                  t0,
               const dealii::Vector<double> &y0,
               const ExternalPressures      &external_pressures = {});
    ~Integrator();

    Integrator(const Integrator &) = delete;
    Integrator &
    operator=(const Integrator &) = delete;

    /// Advance to exactly @p t_end (> time()). Returns the valve events in
    /// (time(), t_end], in order (several valves at one time by index); a
    /// sign change found only at t_end is reported there. Throws
    /// ExcMessage when ARKode fails, with its message.
    std::vector<Event>
    advance(const double t_end);

    /// Current time [ms].
    double
    time() const;

    /// State at time().
    const dealii::Vector<double> &
    state() const;

    /// Which valves are open at time() (from the events; initially from the
    /// sign of the indicators).
    const std::vector<bool> &
    valves_open() const;

    /// The external pressures at @p t (zeros without a callback).
    void
    external_pressures(const double t, dealii::Vector<double> &p_ext) const;

    Statistics
    statistics() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Circulation
