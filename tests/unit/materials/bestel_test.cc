// The Bestel active tension law against its closed-form solution on the
// plateaus of the activation function.
#include "materials/bestel.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole;

TEST_CASE("Bestel tension follows the exponential solutions of its plateaus",
          "[materials][active]")
{
  const Materials::Bestel::Parameters p; // physiology.md values, sigma_0 100
  const double                        period = 800;
  const Materials::Bestel             law(p, period);

  // Onset: a(t) changes sign there.
  CHECK(law.activation(law.onset()) == Approx(0.0).margin(1e-12));
  CHECK(law.onset() > p.t_sys);
  CHECK(law.onset() < p.t_sys + 3 * p.gamma);

  // Systolic plateau (f = 1 to 1e-8): tau(t) = s0 + (tau(t1) - s0)
  // exp(-a_max (t - t1)).
  const double t1 = p.t_sys + 60, t2 = p.t_dias - 60;
  const double expected =
    p.contractility +
    (law.tension(t1, 0) - p.contractility) * std::exp(-p.a_max * (t2 - t1));
  CHECK(law.tension(t2, 0) == Approx(expected).epsilon(1e-6));
  CHECK(law.tension(t2, 0) > 0.5 * p.contractility);

  // Diastolic plateau: tau decays with rate |a_min|.
  const double t3 = p.t_dias + 60, t4 = p.t_dias + 200;
  CHECK(
    law.tension(t4, 0) ==
    Approx(law.tension(t3, 0) * std::exp(p.a_min * (t4 - t3))).epsilon(1e-6));

  // Shift by the activation time, periodicity, and rest before activation.
  CHECK(law.tension(300 + 25, 25) == Approx(law.tension(300, 0)));
  CHECK(law.tension(300 + period, 0) == Approx(law.tension(300, 0)));
  CHECK(law.tension(10, 20) == 0.0);
  CHECK(law.tension(p.t_sys - 5 * p.gamma, 0) < 1e-2);
}
