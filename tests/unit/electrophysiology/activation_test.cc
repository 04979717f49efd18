// Activation times: upstroke crossings located by linear interpolation, and
// the volume-weighted summary.
#include "electrophysiology/activation.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace systole::Electrophysiology;

TEST_CASE("Activation is the linearly interpolated upward threshold crossing",
          "[ep][activation]")
{
  ActivationTracker tracker(4, 0.5);
  // Point 0 ramps v = t / 4 (crosses at t = 2), point 1 crosses exactly at
  // a sample, point 2 goes down through the threshold, point 3 never
  // crosses.
  const auto sample = [](const double t) {
    return std::vector<double>{t / 4,
                               t < 3 ? 0.0 : (t == 3 ? 0.5 : 1.0),
                               1.0 - t / 4,
                               0.2};
  };
  for (double t = 0; t < 8; t += 1)
    tracker.update(t, sample(t).data(), t + 1, sample(t + 1).data());
  CHECK(tracker.first()[0] == Approx(2.0).epsilon(1e-14));
  CHECK(tracker.first()[1] == Approx(3.0).epsilon(1e-14));
  CHECK(std::isnan(tracker.first()[2]));
  CHECK(std::isnan(tracker.first()[3]));

  // Inside a step: v from 0.2 to 0.8 over [10, 10.5] crosses at 10.25.
  ActivationTracker   one(1, 0.5);
  std::vector<double> a{0.2}, b{0.8};
  one.update(10, a.data(), 10.5, b.data());
  CHECK(one.first()[0] == Approx(10.25));
}

TEST_CASE("A second beat updates the latest, not the first activation",
          "[ep][activation]")
{
  ActivationTracker   tracker(1, 0.5);
  std::vector<double> rest{0.0}, up{1.0};
  tracker.update(0, rest.data(), 1, up.data());     // beat 1 at 0.5
  tracker.update(1, up.data(), 400, rest.data());   // repolarises
  tracker.update(800, rest.data(), 801, up.data()); // beat 2 at 800.5
  CHECK(tracker.first()[0] == Approx(0.5));
  CHECK(tracker.latest()[0] == Approx(800.5));
}

TEST_CASE("The activation summary weights points by volume", "[ep][activation]")
{
  // Weights 1, 1, 2, 6 activated at 1, 2, 3, 4 ms: 10 % by 1 ms, 20 % by 2,
  // 40 % by 3, 100 % by 4.
  const std::vector<double> weights{1, 1, 2, 6};
  std::vector<double>       times{1, 2, 3, 4};
  auto s = summarize_activation(times, weights, 0.9, MPI_COMM_SELF);
  CHECK(s.activated_fraction == Approx(1.0));
  CHECK(s.first == 1);
  CHECK(s.last == 4);
  CHECK(s.total == Approx(3.0));
  CHECK(s.fraction_time == Approx(4.0).margin(1e-8));
  CHECK(
    summarize_activation(times, weights, 0.4, MPI_COMM_SELF).fraction_time ==
    Approx(3.0).margin(1e-8));
  CHECK(
    summarize_activation(times, weights, 0.15, MPI_COMM_SELF).fraction_time ==
    Approx(2.0).margin(1e-8));

  // The heavy point never activates: 40 % active, no total, no 90 % time.
  times[3] = std::nan("");
  s        = summarize_activation(times, weights, 0.9, MPI_COMM_SELF);
  CHECK(s.activated_fraction == Approx(0.4));
  CHECK(s.last == 3);
  CHECK(std::isnan(s.total));
  CHECK(std::isnan(s.fraction_time));
}
