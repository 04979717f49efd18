#include "electrophysiology/mitchell_schaeffer.h"

#include <cmath>
#include <cstddef>

namespace systole::Electrophysiology
{
  const std::vector<RealEntry<MitchellSchaefferParameters>> &
  MitchellSchaefferParameters::entries()
  {
    using dealii::Patterns::Double;
    using P                                      = MitchellSchaefferParameters;
    static const std::vector<RealEntry<P>> table = {
      {"tau_in",
       &P::tau_in,
       Double(0.0),
       "Time constant of the inward (depolarising) current. Units: ms. "
       "Source: physiology.md, 0.3 ms."},
      {"tau_out",
       &P::tau_out,
       Double(0.0),
       "Time constant of the outward (repolarising) current. Units: ms. "
       "Source: physiology.md, 6 ms."},
      {"tau_open",
       &P::tau_open,
       Double(0.0),
       "Time constant of the gate opening (v < v_gate). Units: ms. Source: "
       "physiology.md, 120 ms."},
      {"tau_close",
       &P::tau_close,
       Double(0.0),
       "Time constant of the gate closing (v >= v_gate); sets the action "
       "potential duration. Units: ms. Source: physiology.md, 150 ms."},
      {"v_gate",
       &P::v_gate,
       Double(0.0, 1.0),
       "Gate switching potential of the normalised v. Units: -. Source: "
       "physiology.md, 0.13."}};
    return table;
  }


  void
  MitchellSchaefferParameters::validate() const
  {
    for (const auto &[value, entry] :
         {std::pair<double, const char *>{tau_in, "tau_in"},
          {tau_out, "tau_out"},
          {tau_open, "tau_open"},
          {tau_close, "tau_close"}})
      AssertThrow(std::isfinite(value) && value > 0,
                  dealii::ExcMessage(
                    std::string("Electrophysiology / Mitchell-Schaeffer / ") +
                    entry + " must be > 0."));
    AssertThrow(v_gate > 0 && v_gate < 1,
                dealii::ExcMessage("Electrophysiology / Mitchell-Schaeffer / "
                                   "v_gate must lie in (0, 1)."));
    // The resting state v = 0 is excitable only if the peak of the
    // depolarising current beats the repolarising one: max over v of
    // v (1 - v) / tau_in = 1 / (4 tau_in) > 1 / tau_out.
    AssertThrow(4 * tau_in < tau_out,
                dealii::ExcMessage(
                  "Electrophysiology / Mitchell-Schaeffer: tau_out must "
                  "exceed 4 tau_in, otherwise the tissue is not excitable."));
  }


  void
  MitchellSchaeffer::resting_state(double *state) const
  {
    state[0] = 1.0;
  }

  double
  MitchellSchaeffer::ionic_current(const double v, const double *state) const
  {
    return v / params.tau_out - state[0] * v * v * (1.0 - v) / params.tau_in;
  }

  void
  MitchellSchaeffer::state_rhs(const double  v,
                               const double *state,
                               double       *rhs) const
  {
    const double h = state[0];
    rhs[0] =
      v < params.v_gate ? (1.0 - h) / params.tau_open : -h / params.tau_close;
  }
} // namespace systole::Electrophysiology
