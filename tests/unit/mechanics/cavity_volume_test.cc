#include "support/lv_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using test_support::land_cavity_volume;
using test_support::stretched_land_cavity_volume;

TEST_CASE(
  "The Land ventricle's exact cavity volume is the benchmark's 2492.13 mm^3",
  "[mechanics][analytic]")
{
  // benchmarks.md gives the exact value to two decimals.
  CHECK(land_cavity_volume() == Approx(2492.13).margin(0.005));
}

TEST_CASE("The cavity volume converges to the exact value under refinement",
          "[mechanics][convergence]")
{
  // MappingQ2 on the exact ellipsoidal manifold: the surface error falls like
  // h^3 pointwise; the volume error, an integral of it, like h^4.
  std::vector<double> errors;
  for (unsigned int level = 0; level < 4; ++level)
    {
      const double volume =
        stretched_land_cavity_volume(level, 1.0, 1, 2, MPI_COMM_WORLD);
      errors.push_back(std::abs(volume - land_cavity_volume()) /
                       land_cavity_volume());
      INFO("level " << level << ": V = " << volume << ", relative error "
                    << errors.back());
      CHECK(std::isfinite(volume));
    }
  for (unsigned int level = 1; level < errors.size(); ++level)
    {
      const double order = std::log2(errors[level - 1] / errors[level]);
      INFO("level " << level << ": observed order " << order);
      CHECK(order > 3.5); // observed: 4.0 at every level
    }
  CHECK(errors.back() < 1e-4);
}

TEST_CASE("A uniform stretch multiplies the discrete cavity volume by lambda^3",
          "[mechanics][analytic]")
{
  // With Q2 elements on a MappingQ2 geometry the interpolant of
  // u = (lambda - 1)(X - x_base) is exact on the mapped cells, so the deformed
  // discrete cavity is a copy of the undeformed one scaled about a point of the
  // lid: its volume is lambda^3 times as large, up to round-off.
  for (const double lambda : {0.8, 1.1, 1.3})
    {
      const double v0 =
        stretched_land_cavity_volume(1, 1.0, 2, 2, MPI_COMM_WORLD);
      const double v =
        stretched_land_cavity_volume(1, lambda, 2, 2, MPI_COMM_WORLD);
      CHECK(v == Approx(lambda * lambda * lambda * v0).epsilon(1e-10));
    }
}
