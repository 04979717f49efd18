#include "electrophysiology/rush_larsen.h"

#include <cmath>

namespace systole::Electrophysiology
{
  double
  rush_larsen(const double s,
              const double steady,
              const double tau,
              const double dt)
  {
    return steady + (s - steady) * std::exp(-dt / tau);
  }

} // namespace systole::Electrophysiology
