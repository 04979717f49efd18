#include "electrophysiology/rush_larsen.h"

#include <cmath>
#include <vector>

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


  void
  advance_gates(const IonicModel  &model,
                const double       dt,
                const unsigned int n_points,
                const unsigned int stride,
                double            *y)
  {
    const unsigned int n_gates = model.n_gates();
    if (n_gates == 0)
      return;
    std::vector<double> steady(n_gates), tau(n_gates);
    for (unsigned int i = 0; i < n_points; ++i)
      {
        double *point = y + i * stride;
        model.gate_rates(point[0], point + 1, steady.data(), tau.data());
        for (unsigned int g = 0; g < n_gates; ++g)
          point[1 + g] = rush_larsen(point[1 + g], steady[g], tau[g], dt);
      }
  }
} // namespace systole::Electrophysiology
