// Klotz et al. 2006's EDPVR against values worked out by hand from the
// formulas of ../shared/reference/physiology.md (independent arithmetic,
// each step written out below).
#include "inverse/klotz.h"
#include <catch2/catch.hpp>

using namespace systole;

TEST_CASE("Klotz's EDPVR matches the hand-computed curve", "[inverse][klotz]")
{
  SECTION("a small ventricle: (12 mmHg, 80 mL)")
  {
    // V0 = 80 (0.6 - 0.006 * 80) = 80 * 0.12 = 9.6 mL.
    // 12 / 27.78 = 0.4319654; ^(1 / 2.76) = 0.7377620;
    // V30 = 9.6 + (80 - 9.6) / 0.7377620 = 9.6 + 95.42372 = 105.02372 mL.
    // V(5) = 9.6 + 95.42372 * (5 / 27.78)^(1/2.76)
    //      = 9.6 + 95.42372 * 0.5372280 = 60.86429 mL.
    const Inverse::KlotzCurve curve(12, 80);
    CHECK(curve.v0_mL() == Approx(9.6).epsilon(1e-12));
    CHECK(curve.v30_mL() == Approx(105.02372).epsilon(1e-7));
    CHECK(curve.volume_mL(5) == Approx(60.86429).epsilon(1e-7));
    CHECK(curve.volume_mL(12) == Approx(80).epsilon(1e-12));
    // The normalised curve reaches V30 at EDP = A_n = 27.78 mmHg, not at
    // 30 mmHg (the formula as quoted: V30 is its normalising volume).
    CHECK(curve.volume_mL(27.78) == Approx(curve.v30_mL()).epsilon(1e-12));
    CHECK(curve.volume_mL(30) > curve.v30_mL());
    CHECK(curve.volume_mL(0) == Approx(9.6).epsilon(1e-12));
  }
  SECTION("the default ventricle: (10 mmHg, 136 mL), V0 < 0")
  {
    // V0 = 136 (0.6 - 0.816) = -29.376 mL (negative above 100 mL: the
    // regression's form).
    // 10 / 27.78 = 0.3599712; ^(1/2.76) = 0.6906014;
    // V30 = -29.376 + 165.376 / 0.6906014 = -29.376 + 239.46665 = 210.09065.
    // V(25) = -29.376 + 239.46665 * 0.9625174 = 201.11483 mL.
    const Inverse::KlotzCurve curve(10, 136);
    CHECK(curve.v0_mL() == Approx(-29.376).epsilon(1e-12));
    CHECK(curve.v30_mL() == Approx(210.09065).epsilon(1e-7));
    CHECK(curve.volume_mL(25) == Approx(201.11483).epsilon(1e-7));
    CHECK(curve.volume_mL(10) == Approx(136).epsilon(1e-12));
    // The inverse: EDP = A_n ((V - V0) / (V30 - V0))^B_n.
    for (const double p : {5.0, 15.0, 20.0})
      CHECK(curve.pressure_mmHg(curve.volume_mL(p)) ==
            Approx(p).epsilon(1e-12));
  }
  SECTION("bad input is an error")
  {
    CHECK_THROWS(Inverse::KlotzCurve(0, 100));
    CHECK_THROWS(Inverse::KlotzCurve(10, -1));
  }
}
