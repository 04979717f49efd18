#pragma once

#include <string>

namespace systole::Electrophysiology
{
  /// A phenomenological or biophysical ionic model: the membrane current and
  /// the ODEs of the model's state variables (gates, concentrations) at one
  /// point. The potential v is in the model's own units (dimensionless for
  /// the phenomenological models); to_mV() maps it to millivolts for output
  /// and for the parameters given in mV (activation threshold). Time is in
  /// ms: a model with its own time unit (Aliev-Panfilov) scales its rates.
  ///
  /// The monodomain solver owns the per-point data (v and the states, all
  /// nodal, in one ARKode state vector) and calls the model point by point:
  /// @f[ \frac{dv}{dt} = \nabla\cdot(D\nabla v) - I_{ion}(v, s)
  ///       + \frac{I_{stim}}{\chi C_m A},\qquad
  ///     \frac{ds}{dt} = g(v, s), @f]
  /// with A = potential_scale_mV() (mV per model unit), so that a stimulus
  /// current density I_stim [µA/mm³] acts as in the dimensional equation
  /// χ (C_m ∂V/∂t + I_ion) = ∇·(σ∇V) + I_stim.
  ///
  /// Implementations are immutable after construction and thread safe.
  ///
  /// How to add a model:
  /// 1. write electrophysiology/<model>.{h,cc} deriving from this class, with
  ///    a nested Parameters struct (declare/parse, units in every help text,
  ///    bounds checked in parse) and a static `model_name`;
  /// 2. add one line to the table in electrophysiology/ionic_factory.cc;
  /// 3. add tests/unit/electrophysiology/<model>_test.cc: the resting state
  ///    is a fixed point, a supra-threshold stimulus gives an upstroke, a
  ///    sub-threshold one decays.
  class IonicModel
  {
  public:
    virtual ~IonicModel() = default;

    /// Name used in the parameter file ("Electrophysiology / Ionic model").
    virtual std::string
    name() const = 0;

    /// Number of state variables besides the potential.
    virtual unsigned int
    n_states() const = 0;

    /// Resting potential [model units].
    virtual double
    resting_potential() const = 0;

    /// The resting values of the n_states() state variables.
    virtual void
    resting_state(double *state) const = 0;

    /// Ionic current I_ion(v, s) [model units / ms]: dv/dt = -I_ion without
    /// diffusion and stimulus.
    virtual double
    ionic_current(const double v, const double *state) const = 0;

    /// ds/dt = g(v, s) of the n_states() state variables [1/ms].
    virtual void
    state_rhs(const double v, const double *state, double *rhs) const = 0;

    /// Millivolts per model unit of potential (A above).
    virtual double
    potential_scale_mV() const = 0;

    /// Potential [mV] at v = 0.
    virtual double
    potential_offset_mV() const = 0;

    /// v [model units] -> V [mV].
    double
    to_mV(const double v) const
    {
      return potential_offset_mV() + potential_scale_mV() * v;
    }

    /// V [mV] -> v [model units].
    double
    from_mV(const double V) const
    {
      return (V - potential_offset_mV()) / potential_scale_mV();
    }
  };
} // namespace systole::Electrophysiology
