#include "fibres/fibre_field.h"
#include "geometry/ellipsoid.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole;

namespace
{
  /// A wall point of the Land ventricle at transmural coordinate t and
  /// ellipsoidal coordinates (u, v).
  dealii::Point<3>
  wall_point(const Geometry::LVShape &shape,
             const double             t,
             const double             u,
             const double             v)
  {
    const double rs = shape.short_radius(t), rl = shape.long_radius(t);
    return dealii::Point<3>(rs * std::sin(u) * std::cos(v),
                            rs * std::sin(u) * std::sin(v),
                            rl * std::cos(u));
  }
} // namespace

TEST_CASE("The analytic helix rule gives valid frames with the prescribed "
          "angles, monotone through the wall",
          "[fibres]")
{
  const Geometry::LVShape     shape; // Land ventricle
  const double                deg        = M_PI / 180;
  const double                alpha_endo = GENERATE(90.0, 60.0);
  const double                alpha_epi  = -alpha_endo;
  const double                beta       = GENERATE(0.0, 20.0);
  const Fibres::AnalyticHelix helix(shape,
                                    alpha_endo * deg,
                                    alpha_epi * deg,
                                    beta * deg);
  for (const double u : {-2.8, -2.0, -1.6, -1.0})
    for (const double v : {-3.0, -1.0, 0.0, 0.5, 2.5})
      {
        double previous = 1e300;
        for (const double t : {0.0, 0.25, 0.5, 0.75, 1.0})
          {
            const auto X = wall_point(shape, t, u, v);
            const auto b = helix(X);
            CHECK_NOTHROW(Fibres::validate(b, "test point"));
            dealii::Tensor<1, 3> e_u, e_v;
            double               t_found;
            helix.local_frame(X, e_u, e_v, t_found);
            CHECK(t_found == Approx(t).margin(1e-10));
            // Helix angle against the circumferential e_v, towards the base.
            const double alpha    = Fibres::helix_angle(b.f, e_v, e_u) / deg;
            const double expected = alpha_endo + (alpha_epi - alpha_endo) * t;
            CHECK(alpha == Approx(expected).margin(1e-8));
            CHECK(alpha < previous); // decreasing from endo to epi
            previous = alpha;
            // The sheet leaves the wall normal by beta.
            const dealii::Tensor<1, 3> normal =
              dealii::cross_product_3d(e_v, e_u);
            CHECK(std::acos(std::min(1.0, b.s * normal)) / deg ==
                  Approx(beta).margin(1e-5));
          }
      }
}

TEST_CASE("The fibre validator rejects broken frames", "[fibres]")
{
  auto b = Fibres::FibreBasis::cartesian();
  CHECK_NOTHROW(Fibres::validate(b, "here"));
  auto left_handed = b;
  left_handed.n *= -1.0;
  CHECK_THROWS_WITH(Fibres::validate(left_handed, "here"),
                    Catch::Contains("right-handed"));
  auto long_fibre = b;
  long_fibre.f *= 1.1;
  CHECK_THROWS_WITH(Fibres::validate(long_fibre, "here"),
                    Catch::Contains("not a unit"));
  auto skew = b;
  skew.s    = dealii::Tensor<1, 3>({std::sqrt(0.5), std::sqrt(0.5), 0});
  CHECK_THROWS_WITH(Fibres::validate(skew, "here"),
                    Catch::Contains("orthogonal"));
  auto nan = b;
  nan.f[0] = std::nan("");
  CHECK_THROWS_WITH(Fibres::validate(nan, "here"), Catch::Contains("NaN"));
}

TEST_CASE("The analytic helix rule is defined on the axis (the apex)",
          "[fibres]")
{
  const Geometry::LVShape     shape; // Land ventricle
  const Fibres::AnalyticHelix helix(shape, M_PI / 3, -M_PI / 3, 0.0);
  for (const double z : {-17.0, -18.5, -20.0})
    {
      const dealii::Point<3> X(0, 0, z);
      CHECK_NOTHROW(Fibres::validate(helix(X), "apex point"));
    }
}
