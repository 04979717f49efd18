#pragma once

#include "electrophysiology/two_variable_model.h"

namespace systole::Electrophysiology
{
  /// Subsection "Electrophysiology / Aliev-Panfilov". Defaults:
  /// physiology.md (Aliev and Panfilov 1996; Göktepe and Kuhl 2009).
  struct AlievPanfilovParameters
    : TwoVariableParameters<AlievPanfilovParameters>
  {
    static constexpr const char *model_name = "Aliev-Panfilov";

    double k         = 8.0;   ///< excitation rate [-]
    double a         = 0.15;  ///< excitation threshold [-], in (0, 1/2)
    double epsilon_0 = 0.002; ///< recovery rate at rest [-]
    double mu_1      = 0.2;   ///< recovery parameter [-]
    double mu_2      = 0.3;   ///< recovery parameter [-], > 0
    double time_unit = 12.9;  ///< T [ms]

    /// The entries, their patterns and help: one table for declare() and
    /// parse().
    static const std::vector<RealEntry<AlievPanfilovParameters>> &
    entries();

    /// Throws ExcMessage naming the entry if a value is out of range.
    void
    validate() const;
  };

  /// The Aliev-Panfilov model (Aliev and Panfilov 1996, Chaos Solitons
  /// Fractals 7:293), in the form of physiology.md: with the dimensionless
  /// potential u = (V + 80 mV) / 100 mV and the time unit T = 12.9 ms,
  /// @f[ T\frac{du}{dt} = -k u (u - a)(u - 1) - u w,\qquad
  ///     T\frac{dw}{dt} = \Big(\varepsilon_0 + \frac{\mu_1 w}{u + \mu_2}\Big)
  ///                       \big(-w - k u (u - a - 1)\big). @f]
  /// So I_ion = (k u (u - a)(u - 1) + u w) / T [1/ms]. Rest: u = w = 0.
  /// One state variable (the recovery variable w).
  class AlievPanfilov : public TwoVariableModel<AlievPanfilovParameters>
  {
  public:
    using TwoVariableModel::TwoVariableModel;

    void
    resting_state(double *state) const override;

    double
    ionic_current(const double u, const double *state) const override;

    void
    state_rhs(const double u, const double *state, double *rhs) const override;
  };
} // namespace systole::Electrophysiology
