#pragma once

#include "electrophysiology/two_variable_model.h"

namespace systole::Electrophysiology
{
  /// Subsection "Electrophysiology / Mitchell-Schaeffer". Defaults:
  /// physiology.md (Mitchell and Schaeffer 2003).
  struct MitchellSchaefferParameters
    : TwoVariableParameters<MitchellSchaefferParameters>
  {
    static constexpr const char *model_name = "Mitchell-Schaeffer";

    double tau_in    = 0.3;   ///< [ms]
    double tau_out   = 6.0;   ///< [ms]
    double tau_open  = 120.0; ///< [ms]
    double tau_close = 150.0; ///< [ms]
    double v_gate    = 0.13;  ///< [-], in (0, 1)

    /// The entries, their patterns and help: one table for declare() and
    /// parse().
    static const std::vector<RealEntry<MitchellSchaefferParameters>> &
    entries();

    /// Throws ExcMessage naming the entry if a value is out of range.
    void
    validate() const;
  };

  /// The Mitchell-Schaeffer model (Mitchell and Schaeffer 2003, Bull. Math.
  /// Biol. 65:767) with the normalised potential v in [0, 1]:
  /// @f[ \frac{dv}{dt} = \frac{h v^2 (1 - v)}{\tau_{in}}
  ///                    - \frac{v}{\tau_{out}} @f]
  /// and dh/dt = (1 − h)/τ_open for v < v_gate, −h/τ_close otherwise.
  /// So I_ion = v/τ_out − h v²(1 − v)/τ_in [1/ms]. Rest: v = 0, h = 1. One
  /// state variable (the gate h). Output in mV uses the same convention as
  /// Aliev-Panfilov, V = 100 v − 80 mV (the model itself is normalised).
  class MitchellSchaeffer : public TwoVariableModel<MitchellSchaefferParameters>
  {
  public:
    using TwoVariableModel::TwoVariableModel;

    void
    resting_state(double *state) const override;

    double
    ionic_current(const double v, const double *state) const override;

    void
    state_rhs(const double v, const double *state, double *rhs) const override;
  };
} // namespace systole::Electrophysiology
