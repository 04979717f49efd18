#include <deal.II/base/mpi.h>

#include "support/ep_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole::Electrophysiology;

TEST_CASE("The monodomain on 2 ranks equals the serial run", "[mpi][ep]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);
  // A small Niederer-type slab, corner stimulus, fibres along x, surface
  // stimulus on a second face after 20 ms.
  test_support::EPBox box;
  box.upper    = dealii::Point<3>(5, 2, 1);
  box.cells    = {{20, 8, 4}};
  box.fibre    = test_support::unit_vector(0);
  Parameters p = Parameters::defaults("Mitchell-Schaeffer");
  p.stimuli    = parse_stimuli("corner: box 0 0 0 0.5 0.5 0.5 from 0 for 2 "
                               "at 50; far: surface x_max 0.3 from 20 for 2 "
                               "at 50");
  p.time_step  = 0.1;
  p.linear_tolerance                   = 1e-12;
  std::vector<dealii::Point<3>> probes = {dealii::Point<3>(5, 2, 1),
                                          dealii::Point<3>(2.5, 1, 0.5),
                                          dealii::Point<3>(0, 2, 1)};
  // A lattice of points inside cells all over the slab: some lie in cells of
  // rank 1 next to the partition boundary, whose nodes include ghosts (a
  // point is read by the lowest rank that owns a cell around it).
  for (const double x : {0.3, 1.3, 2.3, 3.3, 4.3})
    for (const double y : {0.3, 1.1, 1.7})
      for (const double z : {0.15, 0.45, 0.85})
        probes.emplace_back(x, y, z);
  const auto parallel =
    test_support::run_ep_box(p, box, 30, 5, probes, MPI_COMM_WORLD);
  const auto serial =
    test_support::run_ep_box(p, box, 30, 5, probes, MPI_COMM_SELF);
  for (unsigned int i = 0; i < probes.size(); ++i)
    {
      INFO("probe " << i);
      REQUIRE(std::isfinite(serial.probes.activation_time[i]));
      CHECK(parallel.probes.activation_time[i] ==
            Approx(serial.probes.activation_time[i]).epsilon(1e-9));
      CHECK(parallel.probes.potential[i] ==
            Approx(serial.probes.potential[i]).epsilon(1e-8).margin(1e-8));
    }
  CHECK(parallel.summary.activated_fraction ==
        Approx(serial.summary.activated_fraction).epsilon(1e-12));
  CHECK(parallel.summary.fraction_time ==
        Approx(serial.summary.fraction_time).epsilon(1e-9));
  CHECK(parallel.summary.last == Approx(serial.summary.last).epsilon(1e-9));
  CHECK(parallel.statistics.steps == serial.statistics.steps);
}

TEST_CASE("The monodomain on tetrahedra on 2 ranks equals the serial run",
          "[mpi][ep][tetrahedra]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);
  // The slab above with cells of 0.5 mm split into 24 tetrahedra each (P1,
  // fully distributed, partitioned by METIS), the same two stimuli.
  test_support::EPBox box;
  box.upper      = dealii::Point<3>(5, 2, 1);
  box.cells      = {{10, 4, 2}};
  box.fibre      = test_support::unit_vector(0);
  box.tetrahedra = true;
  Parameters p   = Parameters::defaults("Mitchell-Schaeffer");
  p.stimuli      = parse_stimuli("corner: box 0 0 0 0.5 0.5 0.5 from 0 for 2 "
                                 "at 50; far: surface x_max 0.3 from 20 for 2 "
                                 "at 50");
  p.time_step    = 0.1;
  p.linear_tolerance                   = 1e-12;
  std::vector<dealii::Point<3>> probes = {dealii::Point<3>(5, 2, 1),
                                          dealii::Point<3>(2.5, 1, 0.5),
                                          dealii::Point<3>(0, 2, 1)};
  for (const double x : {0.3, 1.3, 2.3, 3.3, 4.3})
    for (const double y : {0.3, 1.1, 1.7})
      for (const double z : {0.15, 0.45, 0.85})
        probes.emplace_back(x, y, z);
  const auto parallel =
    test_support::run_ep_box(p, box, 30, 5, probes, MPI_COMM_WORLD);
  const auto serial =
    test_support::run_ep_box(p, box, 30, 5, probes, MPI_COMM_SELF);
  CHECK(serial.summary.activated_fraction == Approx(1.0));
  for (unsigned int i = 0; i < probes.size(); ++i)
    {
      INFO("probe " << i);
      REQUIRE(std::isfinite(serial.probes.activation_time[i]));
      CHECK(parallel.probes.activation_time[i] ==
            Approx(serial.probes.activation_time[i]).epsilon(1e-9));
      CHECK(parallel.probes.potential[i] ==
            Approx(serial.probes.potential[i]).epsilon(1e-8).margin(1e-8));
    }
  CHECK(parallel.summary.last == Approx(serial.summary.last).epsilon(1e-9));
  CHECK(parallel.statistics.steps == serial.statistics.steps);
}
