#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/petsc_vector.h>

#include "base/linear_algebra.h"
#include "geometry/ellipsoid.h"
#include "geometry/mesh.h"
#include "mechanics/cavity_volume.h"
#include "support/lv_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace systole;

namespace
{
  // The benchmark's surfaces (Arostica et al. 2025) in its frame, written
  // out here rather than taken from LVShape::arostica().
  constexpr double rs_endo = 25.0, rl_endo = 90.0, rs_epi = 35.0, rl_epi = 97.0;
  const double     x_endo = rl_endo * std::cos(std::acos(5.0 / 17.0));
  const double     x_epi  = rl_epi * std::cos(std::acos(5.0 / 20.0));

  /// (y^2 + z^2)/r_s^2 + x^2/r_l^2 - 1: zero on the spheroid (long axis x).
  double
  residual(const dealii::Point<3> &p, const double rs, const double rl)
  {
    return (p[1] * p[1] + p[2] * p[2]) / (rs * rs) + p[0] * p[0] / (rl * rl) -
           1.0;
  }

  /// Exact cavity volume: the prolate cap of the endocardial spheroid from the
  /// apex x = -r_l to the cut x_b, pi r_s^2/r_l^2 [r_l^2 x - x^3/3].
  double
  exact_volume()
  {
    const auto primitive = [](const double x) {
      return rl_endo * rl_endo * x - x * x * x / 3.0;
    };
    return M_PI * rs_endo * rs_endo / (rl_endo * rl_endo) *
           (primitive(x_endo) - primitive(-rl_endo));
  }

  /// The undeformed cavity volume by the mechanics' path (CavityVolume,
  /// closed by Geometry::cavity_lid), Q1 and MappingQ2.
  double
  cavity_volume(const unsigned int refinements)
  {
    dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
    const auto                                      names =
      Geometry::create_mesh(test_support::arostica_geometry(refinements), tria);
    const auto lid = Geometry::cavity_lid(tria, names, "endocardium");
    // The lid is the endocardial cut plane x = x_endo.
    CHECK(std::abs(std::abs(lid.normal[0]) - 1.0) < 1e-12);
    CHECK(lid.point[0] == Approx(x_endo).epsilon(1e-12));

    const dealii::FESystem<3> fe(dealii::FE_Q<3>(1), 3);
    dealii::DoFHandler<3>     dof_handler(tria);
    dof_handler.distribute_dofs(fe);
    const dealii::MappingQ<3> mapping(2);
    dealii::IndexSet          relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    // A new ghosted vector is zero: the undeformed cavity.
    const LA::MPI::Vector         u(dof_handler.locally_owned_dofs(),
                            relevant,
                            MPI_COMM_WORLD);
    const Mechanics::CavityVolume cavity(names.id("endocardium"), lid);
    return cavity.volume(mapping, dof_handler, u, 4);
  }
} // namespace

TEST_CASE("The exact cavity of the Arostica ventricle is the benchmark's "
          "168.29 mL",
          "[geometry][analytic]")
{
  CHECK(x_endo == Approx(26.47).margin(0.005));
  CHECK(x_epi == Approx(24.25).margin(1e-12));
  CHECK(exact_volume() == Approx(168290.0).margin(5.0)); // mm^3
}

TEST_CASE("The Arostica ventricle lies on its surfaces in the benchmark's "
          "frame, with a ruled base",
          "[geometry]")
{
  dealii::Triangulation<3> tria;
  const auto               names =
    Geometry::create_mesh(test_support::arostica_geometry(2), tria);
  const double rho_endo =
    rs_endo * std::sqrt(1.0 - std::pow(x_endo / rl_endo, 2));
  const double rho_epi = rs_epi * std::sqrt(1.0 - std::pow(x_epi / rl_epi, 2));

  double       worst_endo = 0, worst_epi = 0, worst_base = 0, min_x = 1e300;
  double       s_min = 1e300, s_max = -1e300;
  unsigned int n_base_inner = 0;
  for (const auto &cell : tria.active_cell_iterators())
    {
      CHECK(cell->measure() > 0);
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          for (const unsigned int v : face->vertex_indices())
            {
              const auto &p = face->vertex(v);
              min_x         = std::min(min_x, p[0]);
              if (face->boundary_id() == names.id("endocardium"))
                {
                  worst_endo =
                    std::max(worst_endo,
                             std::abs(residual(p, rs_endo, rl_endo)));
                  CHECK(p[0] <= x_endo + 1e-9);
                }
              else if (face->boundary_id() == names.id("epicardium"))
                {
                  worst_epi =
                    std::max(worst_epi, std::abs(residual(p, rs_epi, rl_epi)));
                  CHECK(p[0] <= x_epi + 1e-9);
                }
              else
                {
                  REQUIRE(face->boundary_id() == names.id("base"));
                  // On the segment between the two cut rings in the point's
                  // meridional plane (rho, x).
                  const double rho   = std::hypot(p[1], p[2]);
                  const double d_rho = rho_epi - rho_endo, d_x = x_epi - x_endo;
                  const double s =
                    ((rho - rho_endo) * d_rho + (p[0] - x_endo) * d_x) /
                    (d_rho * d_rho + d_x * d_x);
                  const double off = std::hypot(rho - rho_endo - s * d_rho,
                                                p[0] - x_endo - s * d_x);
                  worst_base       = std::max(worst_base, off);
                  s_min            = std::min(s_min, s);
                  s_max            = std::max(s_max, s);
                  n_base_inner += (s > 0.1 && s < 0.9);
                }
            }
    }
  INFO("largest residuals: endo " << worst_endo << ", epi " << worst_epi
                                  << ", base off its segment " << worst_base
                                  << " mm");
  CHECK(worst_endo < 1e-12);
  CHECK(worst_epi < 1e-12);
  CHECK(worst_base < 1e-9);
  // The base spans the segments from ring to ring, and has vertices inside.
  CHECK(s_min == Approx(0.0).margin(1e-12));
  CHECK(s_max == Approx(1.0).margin(1e-12));
  CHECK(n_base_inner > 0);
  // Apex at -x: the epicardial apex x = -97 mm.
  CHECK(min_x == Approx(-rl_epi).epsilon(1e-12));
  // The base is not a plane: the plane fit refuses it.
  CHECK_THROWS_WITH(Geometry::boundary_plane(tria, names.id("base"), "base"),
                    Catch::Contains("is not planar"));
}

TEST_CASE("The Arostica cavity volume converges at order 4 to the exact value",
          "[geometry][convergence]")
{
  // Q1 displacement, MappingQ2 on the exact manifold, the lid the endocardial
  // cut plane: the volume error falls like h^4, as on the Land ventricle.
  std::vector<double> errors;
  for (unsigned int level = 0; level < 3; ++level)
    {
      const double v = cavity_volume(level);
      errors.push_back(std::abs(v - exact_volume()) / exact_volume());
      INFO("level " << level << ": V = " << v << " mm^3, relative error "
                    << errors.back());
      CHECK(std::isfinite(v));
    }
  for (unsigned int level = 1; level < errors.size(); ++level)
    {
      const double order = std::log2(errors[level - 1] / errors[level]);
      INFO("level " << level << ": observed order " << order);
      CHECK(order > 3.5);
    }
  CHECK(errors.back() < 1e-4);
}
