#pragma once

#include <limits>
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
  /// nodal, in one ARKode state vector) and evaluates the model over all its
  /// points at once (the batched functions below, one call per right-hand
  /// side; their defaults loop over the per-point functions):
  /// @f[ \frac{dv}{dt} = \nabla\cdot(D\nabla v) - I_{ion}(v, s)
  ///       + \frac{I_{stim}}{\chi C_m A},\qquad
  ///     \frac{ds}{dt} = g(v, s), @f]
  /// with A = potential_scale_mV() (mV per model unit), so that a stimulus
  /// current density I_stim [µA/mm³] acts as in the dimensional equation
  /// χ (C_m ∂V/∂t + I_ion) = ∇·(σ∇V) + I_stim.
  ///
  /// **Gates.** A model may declare its first n_gates() states as gating
  /// variables, ds_i/dt = (s_inf,i(v, s) - s_i)/tau_i(v, s), and give s_inf
  /// and tau in gate_rates(). The solvers then advance those states by the
  /// Rush-Larsen update (rush_larsen.h: exact for v and the other states
  /// frozen over the step, so unconditionally stable however fast the gate)
  /// between the ARKode steps of v and the other states, and state_rhs()
  /// leaves the gates' entries at 0. Without gates (n_gates() = 0, the
  /// default) ARKode integrates every state.
  ///
  /// **Batches.** rhs_batch(), ionic_current_batch() and
  /// advance_gates_batch() evaluate n points stored one after the other in
  /// the solvers' interleaved layout (point i at y + i stride: v, then the
  /// n_states() states). The defaults call the per-point functions point by
  /// point (a virtual call each); a model whose cost matters overrides them
  /// with loops the compiler vectorizes (ten Tusscher-Panfilov: the same
  /// expressions to round-off, tests/unit/electrophysiology/
  /// ionic_batch_test.cc). The solvers (Monodomain, SingleCell) call only
  /// the batched functions.
  ///
  /// Implementations are immutable after construction and thread safe.
  ///
  /// How to add a model:
  /// 1. write electrophysiology/<model>.{h,cc} deriving from this class, with
  ///    a nested Parameters struct (declare/parse, units in every help text,
  ///    bounds checked in parse) and a static `model_name`; put the gates
  ///    first and give their rates if the model has fast gates;
  /// 2. add one line to the table in electrophysiology/ionic_factory.cc;
  /// 3. add tests/unit/electrophysiology/<model>_test.cc: the resting state
  ///    is a fixed point, a supra-threshold stimulus gives an upstroke, a
  ///    sub-threshold one decays;
  /// 4. if its cost matters, override the batched functions (a loop without
  ///    the virtual call; for a biophysical model a vectorized kernel as
  ///    ten_tusscher_panfilov_batch.cc) and compare them with the per-point
  ///    ones in tests/unit/electrophysiology/ionic_batch_test.cc.
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

    /// ds/dt = g(v, s) of the n_states() state variables [1/ms]; the
    /// entries of the n_gates() gates are set to 0 (they advance by
    /// Rush-Larsen from gate_rates()).
    virtual void
    state_rhs(const double v, const double *state, double *rhs) const = 0;

    /// I_ion(v, s) (the return value) and state_rhs() in one call, for
    /// models whose currents enter both (the default calls the two).
    virtual double
    ionic_current_and_state_rhs(const double  v,
                                const double *state,
                                double       *rhs) const
    {
      state_rhs(v, state, rhs);
      return ionic_current(v, state);
    }

    /// Number of gating variables: the states 0 ... n_gates() - 1.
    virtual unsigned int
    n_gates() const
    {
      return 0;
    }

    /// Steady state @p steady [-] and time constant @p tau [ms] of each of
    /// the n_gates() gates at (v, s): ds_i/dt = (steady_i - s_i)/tau_i.
    virtual void
    gate_rates(const double /*v*/,
               const double * /*state*/,
               double * /*steady*/,
               double * /*tau*/) const
    {}

    /// f = (-I_ion(v, s), g(v, s)) at each of @p n_points points: point i
    /// reads y + i @p stride (v, then the n_states() states) and writes
    /// f + i @p stride (the gates' entries 0), as
    /// ionic_current_and_state_rhs() point by point (the default).
    /// @p stride >= 1 + n_states().
    virtual void
    rhs_batch(const unsigned int n_points,
              const unsigned int stride,
              const double      *y,
              double            *f) const;

    /// current[i] = I_ion(v_i + @p dv, s_i) at each of @p n_points points
    /// (layout as rhs_batch()), as ionic_current() point by point (the
    /// default).
    virtual void
    ionic_current_batch(const unsigned int n_points,
                        const unsigned int stride,
                        const double      *y,
                        const double       dv,
                        double            *current) const;

    /// The Rush-Larsen step of @p dt [ms] of the n_gates() gates of each of
    /// @p n_points points in place (layout as rhs_batch()), the rates at the
    /// point's v and states: s <- s_inf + (s - s_inf) e^{-dt/tau}, as
    /// gate_rates() and rush_larsen() point by point (the default; nothing
    /// without gates).
    virtual void
    advance_gates_batch(const double       dt,
                        const unsigned int n_points,
                        const unsigned int stride,
                        double            *y) const;

    /// Whether the model has an intracellular calcium concentration
    /// (calcium_uM()), the input of a calcium-driven tension model.
    virtual bool
    has_calcium() const
    {
      return false;
    }

    /// Free cytosolic calcium concentration [µM] of @p state; NaN for a
    /// model without calcium.
    virtual double
    calcium_uM(const double * /*state*/) const
    {
      return std::numeric_limits<double>::quiet_NaN();
    }

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
