// Geometry::locate_in_owned_cells on tetrahedra, where deal.II 9.4's
// searches test the unit cube.
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/reference_cell.h>
#include <deal.II/grid/tria.h>

#include "geometry/cell_kind.h"
#include "geometry/point_location.h"

#include <catch2/catch.hpp>

#include <random>

using namespace systole;

TEST_CASE("Points are located in the tetrahedron that holds them",
          "[geometry][tetrahedra]")
{
  dealii::Triangulation<3> hexes, tria;
  dealii::GridGenerator::subdivided_hyper_rectangle(hexes,
                                                    {3, 2, 2},
                                                    dealii::Point<3>(0, 0, 0),
                                                    dealii::Point<3>(3, 2, 1));
  dealii::GridGenerator::convert_hypercube_to_simplex_mesh(hexes, tria);
  const auto mapping = Geometry::CellKind(tria).mapping(tria, 1);

  std::mt19937                           rng(42);
  std::uniform_real_distribution<double> x(0, 3), y(0, 2), z(0, 1);
  std::vector<dealii::Point<3>>          points;
  for (unsigned int k = 0; k < 500; ++k)
    points.emplace_back(x(rng), y(rng), z(rng));
  // Vertices and a point 1e-3 mm outside the box (within the tolerance of
  // its boundary cell), one far outside.
  points.emplace_back(3, 2, 1);
  points.emplace_back(1.5, 1, 1.001);
  points.emplace_back(5, 5, 5);
  const auto located =
    Geometry::locate_in_owned_cells(tria, *mapping, points, 0.05);
  for (unsigned int k = 0; k + 1 < points.size(); ++k)
    {
      INFO("point " << points[k]);
      REQUIRE(located[k].outside < 0.05);
      CHECK(
        dealii::ReferenceCells::Tetrahedron.contains_point(located[k].reference,
                                                           1e-12));
      if (k < 501)
        {
          CHECK(located[k].outside < 1e-12);
          // The point is the image of its reference coordinates.
          CHECK(mapping
                  ->transform_unit_to_real_cell(located[k].cell,
                                                located[k].reference)
                  .distance(points[k]) < 1e-12);
        }
    }
  CHECK(located.back().outside == std::numeric_limits<double>::infinity());
}
