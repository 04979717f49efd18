#include "electrophysiology/aliev_panfilov.h"

#include <cmath>
#include <cstddef>

namespace systole::Electrophysiology
{
  const std::vector<RealEntry<AlievPanfilovParameters>> &
  AlievPanfilovParameters::entries()
  {
    using dealii::Patterns::Double;
    using P                                      = AlievPanfilovParameters;
    static const std::vector<RealEntry<P>> table = {
      {"k",
       &P::k,
       Double(0.0),
       "Excitation rate k of the cubic -k u (u - a)(u - 1). Units: -. Source: "
       "physiology.md (Aliev and Panfilov 1996), 8."},
      {"a",
       &P::a,
       Double(0.0, 0.5),
       "Excitation threshold a of the dimensionless potential "
       "u = (V + 80 mV)/100 mV. Units: -. Source: physiology.md, "
       "0.15; must lie in (0, 0.5) for a travelling upstroke."},
      {"epsilon_0",
       &P::epsilon_0,
       Double(0.0),
       "Recovery rate at rest. Units: -. Source: physiology.md, 0.002."},
      {"mu_1",
       &P::mu_1,
       Double(0.0),
       "Recovery parameter mu_1 of eps(u, w) = eps_0 + mu_1 w / (u + mu_2). "
       "Units: -. Source: physiology.md, 0.2."},
      {"mu_2",
       &P::mu_2,
       Double(0.0),
       "Recovery parameter mu_2 (> 0). Units: -. Source: physiology.md, 0.3."},
      {"Time unit",
       &P::time_unit,
       Double(0.0),
       "Time T that scales the dimensionless model to physical time "
       "(T du/dt = ...). Units: ms. Source: physiology.md, 12.9 ms."}};
    return table;
  }


  void
  AlievPanfilovParameters::validate() const
  {
    const auto positive = [](const double value, const std::string &entry) {
      AssertThrow(std::isfinite(value) && value > 0,
                  dealii::ExcMessage("Electrophysiology / Aliev-Panfilov / " +
                                     entry + " must be > 0."));
    };
    positive(k, "k");
    positive(mu_2, "mu_2");
    positive(time_unit, "Time unit");
    AssertThrow(a > 0 && a < 0.5,
                dealii::ExcMessage(
                  "Electrophysiology / Aliev-Panfilov / a = " +
                  dealii::Patterns::Tools::to_string(a) +
                  " must lie in (0, 0.5): otherwise no wave propagates."));
    AssertThrow(epsilon_0 >= 0 && mu_1 >= 0,
                dealii::ExcMessage("Electrophysiology / Aliev-Panfilov / "
                                   "epsilon_0 and mu_1 must be >= 0."));
  }


  void
  AlievPanfilov::resting_state(double *state) const
  {
    state[0] = 0.0;
  }

  double
  AlievPanfilov::ionic_current(const double u, const double *state) const
  {
    return (params.k * u * (u - params.a) * (u - 1.0) + u * state[0]) /
           params.time_unit;
  }

  void
  AlievPanfilov::state_rhs(const double  u,
                           const double *state,
                           double       *rhs) const
  {
    const double w = state[0];
    // u + mu_2 > 0 as long as u > -mu_2 = -0.3 (V > -110 mV): the potential
    // never undershoots that far.
    const double epsilon =
      params.epsilon_0 + params.mu_1 * w / (u + params.mu_2);
    rhs[0] =
      epsilon * (-w - params.k * u * (u - params.a - 1.0)) / params.time_unit;
  }
} // namespace systole::Electrophysiology
