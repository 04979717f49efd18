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


  void
  advance_gates(const IonicModel  &model,
                const double       dt,
                const unsigned int n_points,
                const unsigned int stride,
                double            *y)
  {
    model.advance_gates_batch(dt, n_points, stride, y);
  }
} // namespace systole::Electrophysiology
