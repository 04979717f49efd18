#include "electrophysiology/action_potential.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace systole::Electrophysiology
{
  void
  ActionPotentialRecorder::start(const double onset,
                                 const double v_mV,
                                 const double calcium_uM)
  {
    times.assign(1, onset);
    potentials.assign(1, v_mV);
    peak_calcium = calcium_uM;
  }


  void
  ActionPotentialRecorder::add(const double t,
                               const double v_mV,
                               const double calcium_uM)
  {
    times.push_back(t);
    potentials.push_back(v_mV);
    // NaN (no calcium) stays NaN.
    peak_calcium =
      std::isnan(calcium_uM) ? calcium_uM : std::max(peak_calcium, calcium_uM);
  }


  BeatSummary
  ActionPotentialRecorder::summary() const
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    BeatSummary  b{nan, nan, nan, peak_calcium};
    if (potentials.empty())
      return b;
    b.resting_potential_mV = potentials.front();
    const auto peak = std::max_element(potentials.begin(), potentials.end());
    b.peak_potential_mV = *peak;
    const double level  = b.resting_potential_mV +
                         0.1 * (b.peak_potential_mV - b.resting_potential_mV);
    const auto crossing = [&](const std::size_t i) {
      // Between samples i - 1 and i.
      const double w =
        (level - potentials[i - 1]) / (potentials[i] - potentials[i - 1]);
      return times[i - 1] + w * (times[i] - times[i - 1]);
    };
    const std::size_t i_peak = peak - potentials.begin();
    std::size_t       up     = 0;
    for (std::size_t i = 1; i <= i_peak; ++i)
      if (potentials[i - 1] <= level && potentials[i] > level)
        {
          up = i;
          break;
        }
    if (up == 0)
      return b;
    for (std::size_t i = i_peak + 1; i < potentials.size(); ++i)
      if (potentials[i - 1] > level && potentials[i] <= level)
        {
          b.APD90_ms = crossing(i) - crossing(up);
          break;
        }
    return b;
  }
} // namespace systole::Electrophysiology
