#include "electrophysiology/ionic_model.h"

#include "electrophysiology/rush_larsen.h"

#include <vector>

namespace systole::Electrophysiology
{
  void
  IonicModel::rhs_batch(const unsigned int n_points,
                        const unsigned int stride,
                        const double      *y,
                        double            *f) const
  {
    for (unsigned int i = 0; i < n_points; ++i)
      {
        const double *yi = y + std::size_t(i) * stride;
        double       *fi = f + std::size_t(i) * stride;
        fi[0]            = -ionic_current_and_state_rhs(yi[0], yi + 1, fi + 1);
      }
  }


  void
  IonicModel::ionic_current_batch(const unsigned int n_points,
                                  const unsigned int stride,
                                  const double      *y,
                                  const double       dv,
                                  double            *current) const
  {
    for (unsigned int i = 0; i < n_points; ++i)
      {
        const double *yi = y + std::size_t(i) * stride;
        current[i]       = ionic_current(yi[0] + dv, yi + 1);
      }
  }


  void
  IonicModel::advance_gates_batch(const double       dt,
                                  const unsigned int n_points,
                                  const unsigned int stride,
                                  double            *y) const
  {
    const unsigned int n = n_gates();
    if (n == 0)
      return;
    std::vector<double> steady(n), tau(n);
    for (unsigned int i = 0; i < n_points; ++i)
      {
        double *point = y + std::size_t(i) * stride;
        gate_rates(point[0], point + 1, steady.data(), tau.data());
        for (unsigned int g = 0; g < n; ++g)
          point[1 + g] = rush_larsen(point[1 + g], steady[g], tau[g], dt);
      }
  }
} // namespace systole::Electrophysiology
