#include <deal.II/base/mpi.h>

#include "support/purkinje_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>

// The tree is grown from the surface gathered on every rank: the same tree,
// activation and junction times of the muscle on any number of ranks.
TEST_CASE("The Purkinje tree on several ranks equals the serial one",
          "[mpi][ep][purkinje]")
{
  auto params = test_support::small_purkinje_parameters();
  // With a right bundle (the epicardium stands in for its surface).
  params.right.surface          = "epicardium";
  params.right.his_point        = dealii::Point<3>(-10, 0, 1);
  params.right.his_length       = 3;
  params.right.fascicle_angles  = {0};
  params.right.fascicle_lengths = {4};
  const auto parallel =
    test_support::run_purkinje_lv(params, 2, true, MPI_COMM_WORLD);
  const auto serial =
    test_support::run_purkinje_lv(params, 2, true, MPI_COMM_SELF);
  const auto &a = parallel.network, &b = serial.network;
  REQUIRE(a.nodes.size() == b.nodes.size());
  CHECK(parallel.n_left == serial.n_left);
  CHECK(serial.n_left < b.nodes.size());
  CHECK(a.edges == b.edges);
  CHECK(a.junctions == b.junctions);
  double position = 0, time = 0, muscle = 0;
  for (unsigned int i = 0; i < a.nodes.size(); ++i)
    {
      position = std::max(position, a.nodes[i].distance(b.nodes[i]));
      time     = std::max(time, std::abs(a.times[i] - b.times[i]));
    }
  for (unsigned int j = 0; j < a.junctions.size(); ++j)
    muscle = std::max(muscle,
                      std::abs(parallel.junction_node_time[j] -
                               serial.junction_node_time[j]));
  CHECK(position == 0);
  CHECK(time == 0);
  CHECK(muscle <= 1e-10);
}
