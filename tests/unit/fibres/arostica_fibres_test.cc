#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>

#include "fibres/arostica.h"
#include "fibres/fibre_field.h"
#include "geometry/ellipsoid.h"
#include "geometry/mesh.h"
#include "support/lv_fixture.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace systole;

namespace
{
  constexpr double deg = M_PI / 180;

  /// The unit tangents of the wall at a vertex, by central differences of the
  /// mesh's own manifold (independent of the generator's formulas):
  /// meridional (along the reference polar angle, apex to base) and
  /// circumferential (along the reference azimuth, right-handed about the
  /// apex-to-base axis in the generator's frame, kept by the rotation).
  void
  manifold_tangents(const Geometry::EllipsoidalWallManifold &manifold,
                    const dealii::Point<3>                  &X,
                    dealii::Tensor<1, 3>                    &e_l,
                    dealii::Tensor<1, 3>                    &e_c)
  {
    const dealii::Point<3> ref = manifold.pull_back(X);
    const double           r   = ref.norm();
    const double theta = std::atan2(std::hypot(ref[0], ref[1]), -ref[2]);
    const double phi   = std::atan2(ref[1], ref[0]);
    const auto   at    = [&](const double th, const double ph) {
      return manifold.push_forward(
        dealii::Point<3>(r * std::sin(th) * std::cos(ph),
                         r * std::sin(th) * std::sin(ph),
                         -r * std::cos(th)));
    };
    const double h = 1e-6;
    e_l            = at(theta + h, phi) - at(theta - h, phi);
    e_c            = at(theta, phi + h) - at(theta, phi - h);
    e_l /= e_l.norm();
    e_c /= e_c.norm();
  }
} // namespace

TEST_CASE("Arostica fibres: orthonormal frames with the helix angle of the "
          "benchmark on the endo- and epicardium",
          "[fibres][analytic]")
{
  const Geometry::LVShape shape = Geometry::LVShape::arostica();
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto                                      names =
    Geometry::create_mesh(test_support::arostica_geometry(1), tria);
  const Fibres::Arostica                  rule(Fibres::Arostica::Parameters(),
                              shape,
                              tria,
                              names);
  const Geometry::EllipsoidalWallManifold manifold(shape);
  const Fibres::AnalyticHelix analytic(shape, 60 * deg, -60 * deg, 0.0);

  // Interior: orthonormal, right-handed, t in [0, 1], s in the wall.
  {
    const dealii::MappingQ<3>       mapping(2);
    const dealii::FE_Q<3>           fe(1);
    dealii::FEValues<3>             fe_values(mapping,
                                  fe,
                                  dealii::QGauss<3>(2),
                                  dealii::update_quadrature_points);
    std::vector<Fibres::FibreBasis> bases;
    double                          worst = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          rule(cell, fe_values.get_quadrature_points(), bases);
          for (const auto &b : bases)
            {
              worst =
                std::max({worst,
                          std::abs(b.f.norm() - 1),
                          std::abs(b.s * b.f),
                          std::abs(b.n * b.f),
                          std::abs(b.n * b.s),
                          (dealii::cross_product_3d(b.f, b.s) - b.n).norm()});
            }
        }
    CHECK(worst < 1e-12);
  }

  // On the surfaces: at the vertices more than 3 mm off the axis, the
  // helix angle in the tangents of the manifold is +60 (endo) and -60 (epi)
  // degrees, the sheet normal is the outward wall normal, and the fibre is the
  // project's analytic rule's (same twist).
  double worst_angle = 0, worst_normal = 0, worst_analytic = 0, worst_t = 0;
  unsigned int                    n_checked = 0;
  std::vector<Fibres::FibreBasis> bases;
  std::vector<double>             t;
  for (const auto &cell : tria.active_cell_iterators())
    for (const auto &face : cell->face_iterators())
      if (face->at_boundary() && face->boundary_id() != names.id("base"))
        {
          const bool   endo = face->boundary_id() == names.id("endocardium");
          const double expected = endo ? 60.0 : -60.0;
          for (const unsigned int v : face->vertex_indices())
            {
              const dealii::Point<3> X = face->vertex(v);
              if (std::hypot(X[1], X[2]) < 3.0)
                continue;
              rule(cell, {X}, bases);
              rule.transmural(cell, {X}, t);
              worst_t = std::max(worst_t, std::abs(t[0] - (endo ? 0.0 : 1.0)));
              dealii::Tensor<1, 3> e_l, e_c;
              manifold_tangents(manifold, X, e_l, e_c);
              const double angle =
                std::atan2(bases[0].f * e_l, bases[0].f * e_c) / deg;
              worst_angle = std::max(worst_angle, std::abs(angle - expected));
              dealii::Tensor<1, 3> outward = dealii::cross_product_3d(e_c, e_l);
              outward /= outward.norm();
              worst_normal =
                std::max(worst_normal, (bases[0].n - outward).norm());
              worst_analytic =
                std::max(worst_analytic, (bases[0].f - analytic(X).f).norm());
              ++n_checked;
            }
        }
  INFO("vertices " << n_checked << ": helix angle off by " << worst_angle
                   << " degrees, sheet normal by " << worst_normal
                   << ", fibre against the analytic rule by " << worst_analytic
                   << ", t by " << worst_t);
  CHECK(n_checked > 100);
  CHECK(worst_t < 1e-10);
  CHECK(worst_angle < 1e-4);
  CHECK(worst_normal < 1e-6);
  CHECK(worst_analytic < 1e-6);
}

TEST_CASE("Arostica fibres: the pointwise rule at the benchmark's formulas",
          "[fibres][analytic]")
{
  // At mid-wall (t = 1/2) on the equator of the spheroid t: mu = -pi/2,
  // e_mu = +x, and at theta = 0 (the point (0, -r_s, 0)) e_theta = -z:
  // f = sin(0) e_mu + cos(0) e_theta = -z, n_b = e_mu x e_theta = +y
  // (inward), s = f x n_b = +x, n = -n_b = -y.
  const Geometry::LVShape shape = Geometry::LVShape::arostica();
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto                                      names =
    Geometry::create_mesh(test_support::arostica_geometry(0), tria);
  const Fibres::Arostica rule(Fibres::Arostica::Parameters(),
                              shape,
                              tria,
                              names);
  const double           rs = shape.short_radius(0.5);
  const auto             b  = rule.basis(dealii::Point<3>(0.0, -rs, 0.0), 0.5);
  CHECK((b.f - dealii::Tensor<1, 3>({0.0, 0.0, -1.0})).norm() < 1e-12);
  CHECK((b.s - dealii::Tensor<1, 3>({1.0, 0.0, 0.0})).norm() < 1e-12);
  CHECK((b.n - dealii::Tensor<1, 3>({0.0, -1.0, 0.0})).norm() < 1e-12);
  // At the endocardium (t = 0) on the equator: f = sin 60 e_mu + cos 60
  // e_theta.
  const auto e = rule.basis(dealii::Point<3>(0.0, -25.0, 0.0), 0.0);
  CHECK(
    (e.f - dealii::Tensor<1, 3>({std::sin(60 * deg), 0.0, -std::cos(60 * deg)}))
      .norm() < 1e-12);
}
