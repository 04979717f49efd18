// The load ODEs of the Arostica et al. 2025 benchmark (simulation/
// load_curves.h) against closed forms where the switches are saturated
// (f = 0 before systole, f = 1 on the systolic plateau: then both ODEs are
// linear with constant coefficients), and the RK4 sub-stepping against
// itself with a tenfold finer step over the whole cycle. The whole curves
// are also checked against SciPy's solve_ivp by the run test
// run.elastodynamics_arostica_loads
// (tests/runs/checks/check_elastodynamics.py).
#include "simulation/load_curves.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole;

namespace
{
  ArosticaActivation
  activation(const double t_sys)
  {
    ArosticaActivation a; // the benchmark's a_max, a_min, t_dias, gamma
    a.t_sys = t_sys;
    return a;
  }
} // namespace

TEST_CASE("Arostica pressure: the closed form before systole",
          "[simulation][loads]")
{
  // sigma_mid 16 kPa, sigma_pre 7 kPa/s, alpha_pre 5 /s, alpha_mid 1 /s.
  const ArosticaPressure curve(16, 7e-3, 5e-3, 1e-3, activation(170));
  // Before t_sys - 10 gamma the activation is a_min, g_pre = 1: b = a_min +
  // alpha_pre + alpha_mid = -24 /s < 0, so dp/dt = -|b| p + sigma_pre and
  // p = sigma_pre / |b| (1 - exp(-|b| t)).
  const double b = -30e-3 + 5e-3 + 1e-3;
  for (const double t : {10.0, 50.0, 100.0})
    {
      const double exact = 7e-3 / std::abs(b) * (1 - std::exp(b * t));
      INFO("t = " << t << " ms: " << curve.value(t) << " kPa, exact " << exact);
      CHECK(curve.value(t) == Approx(exact).epsilon(1e-9));
    }
}

TEST_CASE("Arostica active stress: the closed form on the systolic plateau",
          "[simulation][loads]")
{
  ArosticaActiveStress curve(150, activation(160));
  // Zero before systole (a = a_min < 0 and tau(0) = 0).
  CHECK(curve.value(100) == Approx(0).margin(1e-12));
  // From 220 ms to 420 ms, f = 1 to 1e-5 (tanh of 12 switch widths), so
  // dtau/dt = a_max (sigma_0 - tau): tau(t) = sigma_0 + (tau(220) - sigma_0)
  // exp(-a_max (t - 220)).
  curve.accept(220);
  const double tau_220 = curve.value(220);
  REQUIRE(tau_220 > 10);
  const double exact = 150 + (tau_220 - 150) * std::exp(-5e-3 * 200);
  INFO("tau(220 ms) = " << tau_220 << " kPa, tau(420 ms) = " << curve.value(420)
                        << " kPa, closed form " << exact);
  CHECK(curve.value(420) == Approx(exact).epsilon(1e-6));
  // accept() continues from the accepted state: the same value as one
  // integration from 0.
  const ArosticaActiveStress fresh(150, activation(160));
  CHECK(curve.value(600) == Approx(fresh.value(600)).epsilon(1e-12));
}

TEST_CASE("Arostica loads: RK4 with 0.01 ms steps is converged",
          "[simulation][loads]")
{
  // The curves advanced 1 ms at a time (accept()) against the same RK4
  // with steps ten times smaller (pieces of 0.001 ms, one step each): far
  // below the digits of the benchmark's curves.
  ArosticaPressure     pressure(16, 7e-3, 5e-3, 1e-3, activation(170));
  ArosticaActiveStress tension(150, activation(160));
  double               p_fine = 0, tau_fine = 0, largest_p = 0, largest_tau = 0;
  double               peak_p = 0, peak_tau = 0;
  for (unsigned int i = 0; i < 1000; ++i)
    {
      for (unsigned int k = 0; k < 1000; ++k)
        {
          const double a = i + 0.001 * k, b = i + 0.001 * (k + 1);
          p_fine   = pressure.integrate(a, p_fine, b);
          tau_fine = tension.integrate(a, tau_fine, b);
        }
      const double t1 = i + 1.0;
      pressure.accept(t1);
      tension.accept(t1);
      largest_p = std::max(largest_p, std::abs(p_fine - pressure.value(t1)));
      largest_tau =
        std::max(largest_tau, std::abs(tau_fine - tension.value(t1)));
      peak_p   = std::max(peak_p, pressure.value(t1));
      peak_tau = std::max(peak_tau, tension.value(t1));
    }
  INFO("largest difference: pressure "
       << largest_p << " kPa, active stress " << largest_tau << " kPa; peaks "
       << peak_p << " kPa, " << peak_tau << " kPa");
  // (About 2e-9 of the peaks: where a(t) and b(t) change sign, |a| and
  // max(a, 0) have kinks that RK4 resolves only to second order.)
  CHECK(largest_p < 1e-8 * peak_p);
  CHECK(largest_tau < 1e-8 * peak_tau);
  // The plateaus the ODEs relax to: p towards sigma_mid + sigma_pre / b
  // (16.6 kPa), tau towards sigma_0 (150 kPa), both below them.
  CHECK(peak_p > 12);
  CHECK(peak_p < 16.7);
  CHECK(peak_tau > 100);
  CHECK(peak_tau < 150);
}
