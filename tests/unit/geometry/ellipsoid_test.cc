#include <deal.II/grid/tria.h>

#include "geometry/ellipsoid.h"
#include "geometry/mesh.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace systole;

namespace
{
  /// rho^2 / r_s^2 + z^2 / r_l^2 - 1 on the spheroid of transmural coordinate
  /// t.
  double
  spheroid_residual(const Geometry::LVShape &shape,
                    const dealii::Point<3>  &p,
                    const double             t)
  {
    const double rs = shape.short_radius(t), rl = shape.long_radius(t);
    return (p[0] * p[0] + p[1] * p[1]) / (rs * rs) + p[2] * p[2] / (rl * rl) -
           1.0;
  }
} // namespace

TEST_CASE("The wall manifold maps reference points and back",
          "[geometry][analytic]")
{
  const Geometry::LVShape                 shape;
  const Geometry::EllipsoidalWallManifold manifold(shape);
  for (const double r : {1.0, 1.3, 2.0})
    for (const double theta : {0.0, 0.2, 0.9, M_PI / 2})
      for (const double phi : {0.0, 1.0, -2.5})
        {
          const dealii::Point<3> ref(r * std::sin(theta) * std::cos(phi),
                                     r * std::sin(theta) * std::sin(phi),
                                     -r * std::cos(theta));
          const dealii::Point<3> wall = manifold.push_forward(ref);
          CHECK(manifold.pull_back(wall).distance(ref) < 1e-12);
          // On the spheroid of t = r - 1, and the reference equator is the base
          // plane.
          CHECK(std::abs(spheroid_residual(shape, wall, r - 1.0)) < 1e-12);
          if (theta == M_PI / 2)
            CHECK(wall[2] == Approx(shape.base_height));
        }
}

TEST_CASE("The generated ventricle has its parts on the exact surfaces and no "
          "degenerate cells",
          "[geometry]")
{
  Geometry::Parameters params;
  params.global_refinements = 2;
  dealii::Triangulation<3> tria;
  const auto               names = Geometry::create_mesh(params, tria);
  const Geometry::LVShape  shape;

  unsigned int n_endo = 0, n_epi = 0, n_base = 0;
  for (const auto &cell : tria.active_cell_iterators())
    {
      // No collapsed cells at the apex: the shortest edge of every cell is a
      // sizeable fraction of its longest.
      double shortest = 1e300, longest = 0;
      for (unsigned int l = 0; l < 12; ++l)
        {
          const double length = cell->line(l)->diameter();
          shortest            = std::min(shortest, length);
          longest             = std::max(longest, length);
        }
      CHECK(shortest > 0.1 * longest);
      CHECK(cell->measure() > 0);

      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          for (const unsigned int v : face->vertex_indices())
            {
              const auto &p = face->vertex(v);
              if (face->boundary_id() == names.id("endocardium"))
                CHECK(std::abs(spheroid_residual(shape, p, 0.0)) < 1e-12);
              else if (face->boundary_id() == names.id("epicardium"))
                CHECK(std::abs(spheroid_residual(shape, p, 1.0)) < 1e-12);
              else
                CHECK(p[2] == Approx(shape.base_height));
            }
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            n_endo += face->boundary_id() == names.id("endocardium");
            n_epi += face->boundary_id() == names.id("epicardium");
            n_base += face->boundary_id() == names.id("base");
          }
    }
  // 8 x 3 x 1 coarse cells: 20 endocardial faces, 8 basal faces; times 4^2.
  CHECK(n_endo == 20 * 16);
  CHECK(n_epi == 20 * 16);
  CHECK(n_base == 8 * 16);
}

TEST_CASE("A mesh without a needed boundary part is a clear error",
          "[geometry]")
{
  Geometry::Parameters params;
  params.type = Geometry::Parameters::Type::box;
  dealii::Triangulation<3> tria;
  const auto               names = Geometry::create_mesh(params, tria);
  CHECK_THROWS_WITH(names.id("endocardium"),
                    Catch::Contains("no boundary part named 'endocardium'") &&
                      Catch::Contains("x_min"));
}
