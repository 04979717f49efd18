#include <deal.II/base/mpi.h>

#include "support/cup_mesh.h"
#include "support/lv_fixture.h"

#include <catch2/catch.hpp>

TEST_CASE("The cavity volume on 2 ranks equals the serial value",
          "[mpi][mechanics]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);
  const double parallel =
    test_support::stretched_land_cavity_volume(2, 1.2, 1, 2, MPI_COMM_WORLD);
  const double serial =
    test_support::stretched_land_cavity_volume(2, 1.2, 1, 2, MPI_COMM_SELF);
  // Summation order differs between the two partitions: round-off only.
  CHECK(parallel == Approx(serial).epsilon(1e-12));
}

TEST_CASE("The rim-fan cavity on 2 ranks equals the serial one",
          "[mpi][mechanics][cavity]")
{
  // Also run by hand on 3 ranks.
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) >= 2);
  const auto parallel = test_support::fan_cavity_study(2, MPI_COMM_WORLD);
  const auto serial   = test_support::fan_cavity_study(2, MPI_COMM_SELF);
  // Each rim vertex counted once: the apex c is the same point.
  CHECK(parallel.n_rim_vertices == serial.n_rim_vertices);
  CHECK(parallel.volume == Approx(serial.volume).epsilon(1e-12));
  CHECK(parallel.derivative == Approx(serial.derivative).epsilon(1e-12));
}
