#include <deal.II/base/mpi.h>
#include <deal.II/distributed/tria.h>

#include "fibres/arostica.h"
#include "geometry/mesh.h"
#include "support/lv_fixture.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <map>

using namespace systole;

namespace
{
  /// The fibre at the centre of every locally owned cell of the refined
  /// Arostica ventricle, keyed by the centre (rounded to 1e-6 mm).
  std::map<std::array<long long, 3>, dealii::Tensor<1, 3>>
  centre_fibres(const MPI_Comm comm)
  {
    const Geometry::Parameters geometry = test_support::arostica_geometry(1);
    dealii::parallel::distributed::Triangulation<3> tria(comm);
    const auto             names = Geometry::create_mesh(geometry, tria);
    const Fibres::Arostica rule(Fibres::Arostica::Parameters(),
                                geometry.lv_shape,
                                tria,
                                names);

    std::map<std::array<long long, 3>, dealii::Tensor<1, 3>> result;
    std::vector<Fibres::FibreBasis>                          bases;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const dealii::Point<3> x = cell->center();
          rule(cell, {x}, bases);
          result[{{std::llround(x[0] * 1e6),
                   std::llround(x[1] * 1e6),
                   std::llround(x[2] * 1e6)}}] = bases[0].f;
        }
    return result;
  }
} // namespace

TEST_CASE("Arostica fibres on 2 ranks equal the serial ones", "[mpi][fibres]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);
  const auto         parallel = centre_fibres(MPI_COMM_WORLD);
  const auto         serial   = centre_fibres(MPI_COMM_SELF);
  const unsigned int n_owned =
    dealii::Utilities::MPI::sum<unsigned int>(parallel.size(), MPI_COMM_WORLD);
  CHECK(n_owned == serial.size());
  double       worst = 0;
  unsigned int found = 0;
  for (const auto &[key, f] : parallel)
    {
      const auto it = serial.find(key);
      if (it == serial.end())
        continue;
      ++found;
      // The fibres have a sign here: compare the vectors.
      worst = std::max(worst, (f - it->second).norm());
    }
  CHECK(found == parallel.size());
  worst = dealii::Utilities::MPI::max(worst, MPI_COMM_WORLD);
  INFO("largest difference " << worst);
  CHECK(worst < 1e-6);
}
