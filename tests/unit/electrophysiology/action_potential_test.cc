// The beat measures of the cell problem on a trace with known values.
#include "electrophysiology/action_potential.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole::Electrophysiology;

TEST_CASE("A trapezoidal action potential has the APD90 of its 90 % level",
          "[ep][action-potential]")
{
  // Rest -80 mV at the onset t = 10 ms, linear upstroke to +20 mV at 11 ms,
  // plateau to 300 ms, linear repolarisation to -80 mV at 400 ms; sampled
  // every 0.25 ms. The 90 % level -70 mV is crossed at 10.1 and 390 ms.
  const auto V = [](const double t) {
    if (t <= 11)
      return -80 + 100 * (t - 10);
    if (t <= 300)
      return 20.0;
    if (t <= 400)
      return 20 - (t - 300);
    return -80.0;
  };
  ActionPotentialRecorder recorder;
  recorder.start(10, V(10), 0.1);
  for (double t = 10.25; t <= 600; t += 0.25)
    recorder.add(t, V(t), 0.1 + 0.9 * std::exp(-std::pow((t - 50) / 20, 2)));
  const BeatSummary b = recorder.summary();
  CHECK(b.resting_potential_mV == -80);
  CHECK(b.peak_potential_mV == 20);
  CHECK(b.APD90_ms == Approx(390 - 10.1).epsilon(1e-12));
  CHECK(b.peak_calcium_uM == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("A beat without an upstroke has no APD90", "[ep][action-potential]")
{
  // The potential only decays from the onset on: the peak is the onset's
  // value, so the 90 % level is never crossed upwards.
  ActionPotentialRecorder recorder;
  recorder.start(0, -75, std::nan(""));
  for (double t = 1; t <= 100; t += 1)
    recorder.add(t, -80 + 5 * std::exp(-t / 10), std::nan(""));
  const BeatSummary b = recorder.summary();
  CHECK(std::isnan(b.APD90_ms));
  CHECK(std::isnan(b.peak_calcium_uM));
  CHECK(b.peak_potential_mV == -75);
}
