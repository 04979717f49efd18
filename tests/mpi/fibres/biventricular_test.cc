#include <deal.II/base/mpi.h>
#include <deal.II/distributed/tria.h>

#include "fibres/biventricular.h"
#include "geometry/mesh.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <map>

using namespace systole;

namespace
{
  /// The fibre at the centre of every locally owned cell, keyed by the
  /// centre (rounded to 1e-6 mm).
  std::map<std::array<long long, 3>, dealii::Tensor<1, 3>>
  centre_fibres(const MPI_Comm comm)
  {
    Geometry::Parameters geometry;
    geometry.type      = Geometry::Parameters::Type::gmsh;
    geometry.mesh_file = SYSTOLE_SOURCE_DIR "/meshes/biv_coarse.msh";
    dealii::parallel::distributed::Triangulation<3> tria(comm);
    const auto names = Geometry::create_mesh(geometry, tria);
    Fibres::Biventricular::Parameters params;
    params.degree = 1; // the partition is the point here, not the accuracy
    const Fibres::Biventricular rule(params, tria, names);

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

TEST_CASE("Biventricular fibres on 2 ranks equal the serial ones",
          "[mpi][fibres]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);
  const auto parallel = centre_fibres(MPI_COMM_WORLD);
  const auto serial   = centre_fibres(MPI_COMM_SELF);
  // Every cell is owned by one of the ranks.
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
      // Axes: f and -f are the same fibre. CG stops at 1e-10 relative
      // residual on both partitions: the frames agree far below a degree.
      worst = std::max(worst, 1.0 - std::abs(f * it->second));
    }
  CHECK(found == parallel.size());
  worst = dealii::Utilities::MPI::max(worst, MPI_COMM_WORLD);
  CHECK(worst < 1e-10);
}
