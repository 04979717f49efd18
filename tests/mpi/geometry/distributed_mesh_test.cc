#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/distributed/tria_base.h>

#include "geometry/distributed_mesh.h"
#include "geometry/mid_edge_nodes.h"

#include <catch2/catch.hpp>

#include <vector>

using namespace systole;

// deal.II 9.4's fully distributed load() reads the cell data of rank 0 on
// every rank; create_distributed_mesh() must give each cell its own.
TEST_CASE("A tetrahedral mesh saved on 2 ranks loads with the cell data of "
          "each cell",
          "[mpi][geometry][simplex]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);
  Geometry::Parameters params;
  params.type            = Geometry::Parameters::Type::box;
  params.box_lower       = dealii::Point<3>(0, 0, 0);
  params.box_upper       = dealii::Point<3>(3, 2, 1);
  params.box_cells       = {{3, 2, 1}};
  params.tetrahedra      = true;
  const std::string file = "distributed_mesh_test.mesh";

  using Cell   = dealii::Triangulation<3>::cell_iterator;
  using Status = dealii::Triangulation<3>::CellStatus;
  using Range  = boost::iterator_range<std::vector<char>::const_iterator>;
  {
    const auto saved =
      Geometry::create_distributed_mesh(params, MPI_COMM_WORLD);
    REQUIRE(saved.tria->n_locally_owned_active_cells() > 0);
    saved.tria->register_data_attach(
      [](const Cell &cell, const Status) {
        const dealii::Point<3> x = cell->center();
        return dealii::Utilities::pack(std::vector<double>{x[0], x[1], x[2]},
                                       false);
      },
      /*returns_variable_size_data=*/false);
    saved.tria->save(file);
  }
  const auto loaded =
    Geometry::create_distributed_mesh(params, MPI_COMM_WORLD, file);
  const unsigned int handle = loaded.tria->register_data_attach(
    [](const Cell &, const Status) { return std::vector<char>(); },
    false);
  double       largest = 0;
  unsigned int n_cells = 0;
  loaded.tria->notify_ready_to_unpack(
    handle,
    [&](const Cell &cell, const Status, const Range &range) {
      const auto x =
        dealii::Utilities::unpack<std::vector<double>>(range.begin(),
                                                       range.end(),
                                                       false);
      REQUIRE(x.size() == 3);
      largest =
        std::max(largest,
                 cell->center().distance(dealii::Point<3>(x[0], x[1], x[2])));
      ++n_cells;
    });
  CHECK(n_cells == loaded.tria->n_locally_owned_active_cells());
  CHECK(largest == 0.0);
}

TEST_CASE("A second-order tetrahedral mesh loads with its mid-edge nodes",
          "[mpi][geometry][simplex]")
{
  Geometry::Parameters params;
  params.type            = Geometry::Parameters::Type::gmsh;
  params.mesh_file       = SYSTOLE_SOURCE_DIR "/meshes/lv_ellipsoid_tet_p2.msh";
  const std::string file = "distributed_mesh_test_p2.mesh";
  std::size_t       n_nodes = 0;
  {
    const auto saved =
      Geometry::create_distributed_mesh(params, MPI_COMM_WORLD);
    REQUIRE(Geometry::mid_edge_nodes(*saved.tria) != nullptr);
    n_nodes = Geometry::mid_edge_nodes(*saved.tria)->n_nodes();
    saved.tria->save(file);
  }
  const auto loaded =
    Geometry::create_distributed_mesh(params, MPI_COMM_WORLD, file);
  const auto *manifold = Geometry::mid_edge_nodes(*loaded.tria);
  REQUIRE(manifold != nullptr);
  CHECK(manifold->n_nodes() == n_nodes);
}
