// The mechanics' own matrix-free tangent against its assembled tangent on 2
// ranks (the cells of a batch and the point data of every rank's own cells).
#include <deal.II/base/mpi.h>

#include "support/matrix_free_problem.h"

#include <catch2/catch.hpp>

TEST_CASE("The mechanics' matrix-free tangent is its assembled tangent on 2 "
          "ranks",
          "[mpi][mechanics][matrix-free]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) >= 2);
  const auto d = test_support::matrix_free_problem_differences(MPI_COMM_WORLD);
  INFO("cached " << d.cached << ", single " << d.single << ", other tension "
                 << d.other_tension << ", stale " << d.stale << ", updated "
                 << d.updated << ", pressure " << d.pressure
                 << ", pressure left out " << d.pressure_left_out);
  CHECK(d.cached < 1e-10);
  CHECK(d.updated < 1e-10);
  CHECK(d.pressure < 1e-10);
  CHECK(d.pressure_left_out > 1e-4);
  CHECK(d.other_tension > 1e-3);
  CHECK(d.stale > 1e-3);
}
