// Geometry::CellKind's rules for the lumped mass and the surface stimuli, and
// its projection into the reference cell, on hexahedra and tetrahedra.
#include <deal.II/base/geometry_info.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/reference_cell.h>
#include <deal.II/grid/tria.h>

#include "geometry/cell_kind.h"

#include <catch2/catch.hpp>

#include <random>

using namespace systole;

TEST_CASE("On tetrahedra the nodal rule is row-sum lumping of the P1 mass",
          "[geometry][lumped]")
{
  // A distorted box of tetrahedra: for every cell the nodal rule gives each
  // vertex a quarter of the volume, the row sums of the consistent mass.
  dealii::Triangulation<3> tria;
  dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(
    tria,
    {2, 1, 1},
    dealii::Point<3>(0, 0, 0),
    dealii::Point<3>(2, 1, 1));
  dealii::GridTools::distort_random(0.2, tria, false, 42);

  const Geometry::CellKind kind(tria);
  REQUIRE(kind.simplex());
  const auto            fe      = kind.lagrange(1);
  const auto            mapping = kind.mapping(tria, 1);
  const auto            nodal   = kind.nodal_quadrature(1);
  const auto            gauss   = kind.cell_quadrature(2);
  dealii::FEValues<3>   lumped(*mapping,
                             *fe,
                             nodal,
                             dealii::update_values | dealii::update_JxW_values);
  dealii::FEValues<3>   exact(*mapping,
                            *fe,
                            gauss,
                            dealii::update_values | dealii::update_JxW_values);
  dealii::DoFHandler<3> dofs(tria);
  dofs.distribute_dofs(*fe);
  double total = 0, volume_total = 0;
  for (const auto &cell : dofs.active_cell_iterators())
    {
      lumped.reinit(cell);
      exact.reinit(cell);
      double volume = 0;
      for (unsigned int q = 0; q < gauss.size(); ++q)
        volume += exact.JxW(q);
      volume_total += volume;
      for (unsigned int i = 0; i < 4; ++i)
        {
          double diagonal = 0, row_sum = 0;
          for (unsigned int q = 0; q < nodal.size(); ++q)
            diagonal += lumped.shape_value(i, q) * lumped.JxW(q);
          for (unsigned int j = 0; j < 4; ++j)
            for (unsigned int q = 0; q < gauss.size(); ++q)
              row_sum += exact.shape_value(i, q) * exact.shape_value(j, q) *
                         exact.JxW(q);
          CHECK(diagonal > 0);
          CHECK(diagonal == Approx(volume / 4).epsilon(1e-12));
          CHECK(diagonal == Approx(row_sum).epsilon(1e-12));
          total += diagonal;
        }
    }
  CHECK(total == Approx(volume_total).epsilon(1e-12));
  CHECK_THROWS_WITH(kind.nodal_quadrature(2),
                    Catch::Contains("needs degree 1"));
}

TEST_CASE("Face sample points are the vertices, edge midpoints and centre",
          "[geometry]")
{
  dealii::Triangulation<3> tets, hexes;
  dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(
    tets,
    {1, 1, 1},
    dealii::Point<3>(0, 0, 0),
    dealii::Point<3>(1, 1, 1));
  dealii::GridGenerator::hyper_cube(hexes);
  const auto on_triangle = Geometry::CellKind(tets).face_sample_points();
  const auto on_square   = Geometry::CellKind(hexes).face_sample_points();
  CHECK(on_triangle.size() == 7);
  for (const auto &p : on_triangle.get_points())
    CHECK(dealii::ReferenceCells::Triangle.contains_point(p, 1e-14));
  CHECK(on_square.get_points() == dealii::QGaussLobatto<2>(3).get_points());
}

TEST_CASE("Points outside the reference cell are moved into it", "[geometry]")
{
  dealii::Triangulation<3> tets, hexes;
  dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(
    tets,
    {1, 1, 1},
    dealii::Point<3>(0, 0, 0),
    dealii::Point<3>(1, 1, 1));
  dealii::GridGenerator::hyper_cube(hexes);
  const Geometry::CellKind tet(tets), hex(hexes);

  // Inside: unchanged (bit for bit).
  const dealii::Point<3> inside(0.2, 0.3, 0.1);
  CHECK(tet.project_to_reference_cell(inside) == inside);
  CHECK(hex.project_to_reference_cell(inside) == inside);

  // Outside a face, an edge, a vertex: clamped barycentric coordinates,
  // renormalised.
  const dealii::Point<3> below(-0.1, 0.5, 0.2);
  const dealii::Point<3> moved = tet.project_to_reference_cell(below);
  CHECK(moved.distance(dealii::Point<3>(0, 0.5 / 1.1, 0.2 / 1.1)) < 1e-14);
  CHECK(tet.project_to_reference_cell(dealii::Point<3>(1.2, 0.1, 0))
          .distance(dealii::Point<3>(1 / 1.1, 0.1 / 1.1, 0)) < 1e-14);
  CHECK(tet.project_to_reference_cell(dealii::Point<3>(-0.1, -0.2, -0.3))
          .distance(dealii::Point<3>(0, 0, 0)) < 1e-14);
  std::mt19937                           rng(42);
  std::uniform_real_distribution<double> coordinate(-0.3, 1.3);
  for (unsigned int k = 0; k < 200; ++k)
    {
      const dealii::Point<3> p(coordinate(rng),
                               coordinate(rng),
                               coordinate(rng));
      CHECK(dealii::ReferenceCells::Tetrahedron
              .contains_point(tet.project_to_reference_cell(p), 1e-14));
      CHECK(hex.project_to_reference_cell(p) ==
            dealii::GeometryInfo<3>::project_to_unit_cell(p));
    }
}
