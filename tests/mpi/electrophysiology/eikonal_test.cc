#include <deal.II/base/mpi.h>

#include "support/eikonal_fixture.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>

// The eikonal times on any number of ranks equal the serial ones (the
// fixed point does not depend on the partition). Runs on 2 ranks in ctest;
// `mpirun -np 3 systole-mpi "[eikonal]"` checks 3.
TEST_CASE("The eikonal solver on several ranks equals the serial run",
          "[mpi][ep][eikonal]")
{
  for (const bool tets : {false, true})
    {
      test_support::EikonalBlock block;
      block.tetrahedra = tets;
      // The tetrahedra on fewer cells: 16 x 12 x 8 have 7 013 nodes (their
      // face centres too), more than the hexahedra's 6 175 (24 x 18 x 12
      // tetrahedra had 22 663 and took most of the test's time).
      block.cells = tets ? std::array<unsigned int, 3>{{16, 12, 8}}
                         : std::array<unsigned int, 3>{{24, 18, 12}};
      // Strong anisotropy and a source near a corner: the front crosses
      // the partition boundaries many times.
      block.v_n    = 0.1;
      block.source = dealii::Point<3>(0.3, 0.2, 0.1);
      const auto parallel =
        test_support::run_eikonal_block(block, MPI_COMM_WORLD);
      const auto serial = test_support::run_eikonal_block(block, MPI_COMM_SELF);
      REQUIRE(parallel.times.size() == serial.times.size());
      double difference = 0;
      for (unsigned int i = 0; i < serial.times.size(); ++i)
        difference =
          std::max(difference, std::abs(parallel.times[i] - serial.times[i]));
      INFO((tets ? "P1" : "Q1") << ": " << serial.times.size() << " nodes, "
                                << parallel.rounds << " exchange rounds");
      CHECK(std::isfinite(serial.max_error));
      CHECK(difference <= 1e-10);
      WARN((tets ? "P1" : "Q1")
           << " on " << dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
           << " ranks: largest difference from 1 rank " << difference << " ms, "
           << parallel.rounds << " exchange rounds");
    }
}
