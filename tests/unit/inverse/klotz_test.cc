// Klotz et al. 2006's EDPVR against values worked out by hand from the
// formulas of Klotz et al. 2006 (Am J Physiol Heart 291:H403) and Klotz,
// Dickstein & Burkhoff 2007 (Nature Protocols 2:2152): V0 = V_m (0.6 -
// 0.006 EDP_m), with EDP_m in mmHg (independent arithmetic, each step
// written out below; ../shared/reference/physiology.md has V_m in place of
// EDP_m, a typo).
#include "inverse/klotz.h"
#include <catch2/catch.hpp>

using namespace systole;

TEST_CASE("Klotz's EDPVR matches the hand-computed curve", "[inverse][klotz]")
{
  SECTION("a small ventricle: (12 mmHg, 80 mL)")
  {
    // V0 = 80 (0.6 - 0.006 * 12) = 80 (0.6 - 0.072) = 80 * 0.528
    //    = 42.24 mL.
    // 12 / 27.78 = 0.4319654; ^(1 / 2.76) = exp(ln(0.4319654) / 2.76)
    //    = exp(-0.8394097 / 2.76) = exp(-0.3041339) = 0.7377620;
    // V30 = 42.24 + (80 - 42.24) / 0.7377620 = 42.24 + 37.76 / 0.7377620
    //     = 42.24 + 51.18181 = 93.42181 mL.
    // V(5): 5 / 27.78 = 0.1799856; ^(1 / 2.76) = exp(-1.7148784 / 2.76)
    //     = exp(-0.6213328) = 0.5372280;
    //     V(5) = 42.24 + 51.18181 * 0.5372280 = 42.24 + 27.49630
    //          = 69.73630 mL.
    const Inverse::KlotzCurve curve(12, 80);
    CHECK(curve.v0_mL() == Approx(42.24).epsilon(1e-12));
    CHECK(curve.v30_mL() == Approx(93.42181).epsilon(1e-6));
    CHECK(curve.volume_mL(5) == Approx(69.73630).epsilon(1e-6));
    CHECK(curve.volume_mL(12) == Approx(80).epsilon(1e-12));
    // The normalised curve reaches V30 at EDP = A_n = 27.78 mmHg, not at
    // 30 mmHg (the formula as quoted: V30 is its normalising volume).
    CHECK(curve.volume_mL(27.78) == Approx(curve.v30_mL()).epsilon(1e-12));
    CHECK(curve.volume_mL(30) > curve.v30_mL());
    CHECK(curve.volume_mL(0) == Approx(42.24).epsilon(1e-12));
  }
  SECTION("the default ventricle's image: (10 mmHg, 95.807 mL)")
  {
    // V0 = 95.807 (0.6 - 0.06) = 95.807 * 0.54 = 51.73578 mL.
    // 10 / 27.78 = 0.3599712; ^(1 / 2.76) = exp(-1.0217312 / 2.76)
    //    = exp(-0.3701925) = 0.6906014;
    // V30 = 51.73578 + (95.807 - 51.73578) / 0.6906014
    //     = 51.73578 + 44.07122 / 0.6906014 = 51.73578 + 63.81571
    //     = 115.55149 mL.
    // 25 / 27.78 = 0.8999280; ^(1 / 2.76) = exp(-0.1054405 / 2.76)
    //    = exp(-0.0382031) = 0.9625174;
    //    V(25) = 51.73578 + 63.81571 * 0.9625174 = 51.73578 + 61.42373
    //          = 113.15951 mL.
    // V(5) = 51.73578 + 63.81571 * 0.5372280 = 51.73578 + 34.28359
    //      = 86.01937 mL.
    const Inverse::KlotzCurve curve(10, 95.807);
    CHECK(curve.v0_mL() == Approx(51.73578).epsilon(1e-12));
    CHECK(curve.v30_mL() == Approx(115.55149).epsilon(1e-6));
    CHECK(curve.volume_mL(25) == Approx(113.15951).epsilon(1e-6));
    CHECK(curve.volume_mL(5) == Approx(86.01937).epsilon(1e-6));
    CHECK(curve.volume_mL(10) == Approx(95.807).epsilon(1e-12));
    // The inverse: EDP = A_n ((V - V0) / (V30 - V0))^B_n.
    for (const double p : {5.0, 15.0, 20.0})
      CHECK(curve.pressure_mmHg(curve.volume_mL(p)) ==
            Approx(p).epsilon(1e-12));
  }
  SECTION("a large ventricle: (20 mmHg, 250 mL), where V_m in place of "
          "EDP_m gave a negative V0")
  {
    // V0 = 250 (0.6 - 0.12) = 250 * 0.48 = 120 mL (the typo's form:
    // 250 (0.6 - 1.5) = -225 mL).
    // 20 / 27.78 = 0.7199424; ^(1 / 2.76) = exp(-0.3285840 / 2.76)
    //    = exp(-0.1190522) = 0.8877615;
    // V30 = 120 + 130 / 0.8877615 = 120 + 146.43573 = 266.43573 mL.
    const Inverse::KlotzCurve curve(20, 250);
    CHECK(curve.v0_mL() == Approx(120).epsilon(1e-12));
    CHECK(curve.v30_mL() == Approx(266.43573).epsilon(1e-6));
  }
  SECTION("0 < V0 < V_m < V30 for physiological pairs")
  {
    // V0 / V_m = 0.6 - 0.006 EDP_m lies in [0.36, 0.6) for EDP_m in (0,
    // 40] mmHg, whatever V_m; V30 > V_m for EDP_m < A_n.
    for (const double edp : {2.0, 5.0, 10.0, 20.0, 27.0, 40.0})
      for (const double edv : {40.0, 95.807, 150.0, 300.0})
        {
          const Inverse::KlotzCurve curve(edp, edv);
          CHECK(curve.v0_mL() > 0.359 * edv);
          CHECK(curve.v0_mL() < 0.6 * edv);
          if (edp < Inverse::KlotzCurve::A_n)
            CHECK(curve.v30_mL() > edv);
          // Monotone: a higher pressure gives a larger volume.
          CHECK(curve.volume_mL(0.5 * edp) < edv);
          CHECK(curve.volume_mL(1.5 * edp) > edv);
        }
  }
  SECTION("bad input is an error")
  {
    CHECK_THROWS(Inverse::KlotzCurve(0, 100));
    CHECK_THROWS(Inverse::KlotzCurve(10, -1));
    // V0 = V_m (0.6 - 0.006 EDP_m) <= 0 from 100 mmHg on.
    CHECK_THROWS(Inverse::KlotzCurve(100, 100));
  }
}
