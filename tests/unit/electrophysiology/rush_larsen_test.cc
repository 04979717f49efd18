// The Rush-Larsen update of the gates: exact for a gate at constant voltage,
// stable for any step, and its use after every ARKode step (the splitting of
// Monodomain and SingleCell) converges at second order.
#include "electrophysiology/rush_larsen.h"
#include "electrophysiology/single_cell.h"
#include "electrophysiology/ten_tusscher_panfilov.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace systole;
using namespace systole::Electrophysiology;

using TTP = TenTusscherPanfilov;

TEST_CASE("A Rush-Larsen step is the exact solution of a gate at constant "
          "voltage, for any step",
          "[ep][rush-larsen]")
{
  const TTP           model{TTP::Parameters()};
  const unsigned int  n = 1 + model.n_states();
  std::vector<double> y0(n);
  // A voltage clamp at -20 mV from the resting gates: every gate relaxes
  // exponentially to its value at -20 mV (f_CaSS at the resting Ca_SS).
  const double V = -20;
  y0[0]          = V;
  model.resting_state(y0.data() + 1);
  std::vector<double> steady(model.n_gates()), tau(model.n_gates());
  model.gate_rates(V, y0.data() + 1, steady.data(), tau.data());
  const double t_end = 50; // ms

  for (const double dt : {0.01, 0.25, 5.0, 50.0})
    {
      std::vector<double> y = y0;
      const unsigned int  n_steps =
        static_cast<unsigned int>(std::round(t_end / dt));
      for (unsigned int k = 0; k < n_steps; ++k)
        model.advance_gates_batch(dt, 1, n, y.data());
      INFO("dt = " << dt);
      for (unsigned int g = 0; g < model.n_gates(); ++g)
        {
          const double exact =
            steady[g] + (y0[1 + g] - steady[g]) * std::exp(-t_end / tau[g]);
          INFO("gate " << g << ", tau = " << tau[g] << " ms");
          CHECK(y[1 + g] == Approx(exact).epsilon(1e-10).margin(1e-15));
        }
      // The potential and the other states are not touched.
      CHECK(y[0] == V);
      for (unsigned int i = 1 + model.n_gates(); i < n; ++i)
        CHECK(y[i] == y0[i]);
    }
}

TEST_CASE("A Rush-Larsen step stays between the gate and its steady state",
          "[ep][rush-larsen]")
{
  // tau far below the step (the m gate at rest has tau < 0.01 ms): no
  // overshoot, where forward Euler would give 1 - 1000.
  CHECK(rush_larsen(1.0, 0.0, 1e-3, 1.0) == Approx(0.0).margin(1e-300));
  CHECK(rush_larsen(0.2, 0.8, 1e-3, 1e-3) ==
        Approx(0.8 - 0.6 * std::exp(-1.0)).epsilon(1e-15));
  for (const double dt : {1e-6, 1e-2, 1.0, 1e3})
    {
      const double s = rush_larsen(0.9, 0.1, 0.05, dt);
      CHECK(s <= 0.9);
      CHECK(s >= 0.1);
    }
}

namespace
{
  /// V [mV] of an epicardial cell at 20, 30 and 60 ms (upstroke at 10 ms)
  /// with steps of @p dt.
  std::vector<double>
  potential_samples(const double dt)
  {
    const TTP            model{TTP::Parameters()};
    SingleCell::Settings settings;
    settings.time_step = dt;
    const SingleCell::Pacing pacing; // 52 pA/pF for 1 ms at 10 ms
    SingleCell               cell(model, settings, pacing, 0.0);
    std::vector<double>      v;
    for (const double t : {20.0, 30.0, 60.0})
      {
        cell.advance(t);
        v.push_back(cell.potential());
      }
    return v;
  }
} // namespace

TEST_CASE("ARKode with Rush-Larsen gates after every step converges at "
          "second order in the potential, up to the model's switch at -40 mV",
          "[ep][rush-larsen][convergence]")
{
  // Halving the step from 0.04 ms (the fine solution at 0.0025 ms as
  // reference). The merged Strang splitting is second order (the ARK method
  // alone is third order), but the rates of the h and j gates jump where V
  // crosses -40 mV (tau_h 2.6 ms below, 0.18 ms above: the model's own
  // switch), which leaves an O(dt) error in the step that straddles it.
  // Measured: errors 3.66e-3, 8.77e-4, 2.95e-4 mV, orders 2.06, 1.57.
  const auto          reference = potential_samples(0.0025);
  std::vector<double> errors;
  for (const double dt : {0.04, 0.02, 0.01})
    {
      const auto v     = potential_samples(dt);
      double     error = 0;
      for (unsigned int i = 0; i < v.size(); ++i)
        error = std::max(error, std::abs(v[i] - reference[i]));
      errors.push_back(error);
    }
  INFO("errors " << errors[0] << " " << errors[1] << " " << errors[2]);
  CHECK(std::log2(errors[0] / errors[1]) > 1.9);
  CHECK(std::log2(errors[1] / errors[2]) > 1.4);
  // And the scheme is accurate where it matters: 3e-4 mV at 0.01 ms.
  CHECK(errors[2] < 1e-3);
}
