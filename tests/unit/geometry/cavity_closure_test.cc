#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include "geometry/mesh.h"
#include "geometry/mesh_file.h"
#include "support/cup_mesh.h"

#include <catch2/catch.hpp>

using namespace systole;

namespace
{
  Geometry::BoundaryNames
  cup_names()
  {
    Geometry::BoundaryNames names("the cup");
    names.add("wall", test_support::cup_wall);
    names.add("base", test_support::cup_base);
    names.add("endocardium", test_support::cup_cavity);
    return names;
  }

  /// The cup moved by x = X + WarpingDisplacement(warp, 0.3).
  void
  make_moved_cup(dealii::Triangulation<3> &tria, const double warp)
  {
    test_support::make_cup(tria, 1);
    const test_support::WarpingDisplacement d(warp, 0.3);
    dealii::GridTools::transform(
      [&](const dealii::Point<3> &X) {
        dealii::Point<3> x = X;
        for (unsigned int k = 0; k < 3; ++k)
          x[k] += d.value(X, k);
        return x;
      },
      tria);
  }
} // namespace

TEST_CASE("A flat or tilted base closes the cavity by its plane",
          "[geometry][cavity]")
{
  dealii::Triangulation<3> tria;
  test_support::make_cup(tria, 1);
  // The top tilted by 0.25 (x - 1.5), still flat.
  dealii::GridTools::transform(
    [](const dealii::Point<3> &X) {
      return dealii::Point<3>(X[0],
                              X[1],
                              X[2] + 0.25 * (X[0] - 1.5) * X[2] / 2.0);
    },
    tria);
  const auto closure =
    Geometry::cavity_closure(tria, cup_names(), "endocardium");
  REQUIRE(closure.plane.has_value());
  // The plane of the tilted top: normal along (-0.25, 0, 1) (either sign).
  const dealii::Tensor<1, 3> tilted({-0.25, 0.0, 1.0});
  CHECK(std::abs(closure.plane->normal * tilted) / tilted.norm() ==
        Approx(1.0).epsilon(1e-12));
}

TEST_CASE("A warped rim is closed by the fan and measured against its size",
          "[geometry][cavity]")
{
  dealii::Triangulation<3> tria;
  make_moved_cup(tria, 0.4);
  const auto names   = cup_names();
  const auto closure = Geometry::cavity_closure(tria, names, "endocardium");
  CHECK(!closure.plane.has_value());
  INFO("off plane " << closure.off_plane << " mm, rim size " << closure.rim_size
                    << " mm");
  // The rim square's diagonal is about 1.4 mm; a warp of amplitude 0.4 mm
  // puts it well over the warning fraction.
  CHECK(closure.rim_size > 1.4);
  CHECK(closure.off_plane > Geometry::rim_warning_fraction * closure.rim_size);
  CHECK_THROWS(Geometry::cavity_lid(tria, names, "endocardium"));
}

TEST_CASE("The benchmark's tetrahedral ventricle is closed by its endocardial "
          "ring's plane",
          "[geometry][cavity]")
{
  // meshes/arostica_benchmark_tet.msh: the Arostica et al. 2025 ventricle
  // meshed by the benchmark (a ruled base: the endocardium cut at
  // x = 90 * 5/17 mm, the epicardium at x = 97 * 5/20 mm). The base and
  // endocardial triangles of the ring are mostly faces of different
  // tetrahedra.
  dealii::Triangulation<3> tria;
  Geometry::read_gmsh(SYSTOLE_SOURCE_DIR "/meshes/arostica_benchmark_tet.msh",
                      1.0,
                      tria);
  Geometry::BoundaryNames names("the benchmark's mesh");
  names.add("endocardium", 1);
  names.add("epicardium", 2);
  names.add("base", 3);
  const auto closure = Geometry::cavity_closure(tria, names, "endocardium");
  REQUIRE(closure.plane.has_value());
  CHECK(std::abs(closure.plane->normal[0]) == Approx(1.0).epsilon(1e-9));
  CHECK(closure.plane->point[0] == Approx(90.0 * 5.0 / 17.0).epsilon(1e-8));
  // The endocardial rim's diameter, 2 r_s sin(mu_b) with cos(mu_b) = 5/17,
  // is its bounding box's diagonal over sqrt(2).
  CHECK(closure.rim_size / std::sqrt(2.0) ==
        Approx(2 * 25.0 * std::sqrt(1 - 25.0 / 289.0)).epsilon(2e-3));
}
