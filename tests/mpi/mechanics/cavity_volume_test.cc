#include <deal.II/base/mpi.h>

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
