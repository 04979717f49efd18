#pragma once

#include <string>
#include <utility>

/// @file
/// The active-tension extension point: a model of the fibre tension T_a of
/// one quadrature point, driven by time and the cell's calcium (or by an
/// activation time, for the prescribed models), the fibre stretch and its
/// rate. The tension enters the second Piola-Kirchhoff stress as
/// T_a f0 x f0 (Materials::add_active_stress).
///
/// How to add a tension model:
/// 1. write materials/<model>.{h,cc} deriving from TensionModel, with a
///    nested Parameters struct (declare/parse in subsection "Active tension /
///    <name>", units in every help text, bounds checked in parse) and a
///    static `model_name`, which it passes to this base's constructor with
///    its drive and number of states;
/// 2. add one entry to the table in materials/tension_factory.cc;
/// 3. add tests/unit/materials/<model>_test.cc: the resting state is at rest
///    (zero tension), an independent value (a steady state, a closed form),
///    and dT/dλ of one step against central differences (observed order 2).

namespace systole::Materials
{
  /// What drives a tension model.
  enum class TensionDrive
  {
    activation_time, ///< a prescribed curve started at an activation time
    calcium          ///< the intracellular calcium of a cell model
  };

  /// The inputs of one time step of a tension model at one point, from the
  /// accepted state at time - time_step to @p time.
  struct TensionInput
  {
    double time      = 0; ///< end of the step [ms]
    double time_step = 0; ///< [ms] (> 0 for models with states)
    /// Intracellular calcium at the end of the step [µM] (calcium-driven
    /// models).
    double calcium = 0;
    /// Activation time of the point in the current beat [ms] (NaN: not
    /// activated; activation-time driven models).
    double activation_time = 0;
    double stretch         = 1; ///< fibre stretch λ = |F f0| at the end [-]
    /// λ at the start of the step (the accepted state) [-]. The stretch
    /// rate is taken as dλ/dt = (λ - λ_n)/Δt, so that dT/dλ of the step
    /// includes the rate's dependence on λ (the consistent tangent).
    double previous_stretch = 1;
  };

  /// The outputs of one step.
  struct TensionOutput
  {
    double tension = 0; ///< T_a [kPa] (second Piola-Kirchhoff, along f0)
    /// dT_a/dλ of the step [kPa]: the total derivative at fixed accepted
    /// state, calcium and Δt, with dλ/dt = (λ - λ_n)/Δt.
    double dtension_dstretch = 0;
  };

  /// An active-tension model: stateless itself (immutable after
  /// construction, thread safe); the caller owns n_states() values per
  /// point. A step reads the accepted state and writes a trial state, so
  /// that Newton iterations and cut steps can repeat it from the same
  /// accepted state; the caller keeps the trial state when the step is
  /// accepted ("accept step") and drops it otherwise.
  class TensionModel
  {
  public:
    virtual ~TensionModel() = default;

    /// Name used in the parameter file ("Active tension / Model").
    const std::string &
    name() const
    {
      return model_name;
    }

    /// What drives the model.
    TensionDrive
    drive() const
    {
      return model_drive;
    }

    /// Number of state values per point (0: the tension is a function of
    /// the inputs).
    unsigned int
    n_states() const
    {
      return model_n_states;
    }

    /// The resting state (n_states() values).
    virtual void
    initial_state(double *state) const = 0;

    /// One step: from @p accepted (n_states() values at time - time_step)
    /// and @p in, the state at time (@p trial, n_states() values; may not
    /// alias @p accepted) and @p out.
    virtual void
    step(const double       *accepted,
         const TensionInput &in,
         double             *trial,
         TensionOutput      &out) const = 0;

    /// The tension of a state without stepping, at stretch @p stretch [kPa].
    virtual double
    tension_of_state(const double *state, const double stretch) const = 0;

    /// Time from a point's activation to the start of its tension rise [ms]
    /// (a prescribed curve's onset; 0 for a model that rises from the
    /// activation or the calcium transient). The heartbeat starts the beat's
    /// isovolumetric contraction no earlier than the earliest activation
    /// plus this delay.
    virtual double
    onset_delay() const
    {
      return 0;
    }

  protected:
    /// A model's identity, fixed on construction: its name, what drives it
    /// and its number of state values per point.
    TensionModel(std::string        name,
                 const TensionDrive drive,
                 const unsigned int n_states)
      : model_name(std::move(name))
      , model_drive(drive)
      , model_n_states(n_states)
    {}

  private:
    std::string  model_name;
    TensionDrive model_drive;
    unsigned int model_n_states;
  };
} // namespace systole::Materials
