#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/tria.h>

#include "fibres/biventricular.h"
#include "fibres/fibre_field.h"
#include "geometry/boundary_names.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "support/angle_statistics.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

using namespace systole;

namespace
{
  constexpr double deg = M_PI / 180;

  using Stats = test_support::ErrorSamples;

  using test_support::axis_difference;

  /// (x - c)^2 / a^2 + ...: 1 on the ellipsoid of centre (@p cx, 0, 0) and
  /// semi-axes @p a, @p b, @p c.
  double
  ellipsoid(const dealii::Point<3> &x,
            const double            cx,
            const double            a,
            const double            b,
            const double            c)
  {
    return std::pow((x[0] - cx) / a, 2) + std::pow(x[1] / b, 2) +
           std::pow(x[2] / c, 2);
  }

  // The solids of meshes/biv_ellipsoid_tet.msh (meshes/README.md), only to
  // tell the septum from the free walls.
  double
  lv_cavity(const dealii::Point<3> &x)
  {
    return ellipsoid(x, 0, 17, 17, 40);
  }
  double
  lv_outer(const dealii::Point<3> &x)
  {
    return ellipsoid(x, 0, 22, 22, 45);
  }
  double
  rv_outer(const dealii::Point<3> &x)
  {
    return ellipsoid(x, 10, 32, 23, 43);
  }
  double
  rv_cavity(const dealii::Point<3> &x)
  {
    return ellipsoid(x, 10, 28, 19, 39);
  }
} // namespace

// The shipped tetrahedral BiV (meshes/biv_ellipsoid_tet.msh: long axis z,
// base z = 10 mm, 26 161 tetrahedra of 2.1 mm), read and fully distributed
// as a run does, with Systole's part names given to the file's ids
// (EPI = 1, BASE = 2, LV = 3, RV = 4). Helix angles measured as in
// biventricular_test.cc, in a frame of the mesh alone (the facet normal and
// the long axis z projected onto the facet), on each surface of both free
// walls and of the septum; through the septum against the rule's septal law
// in the frame of the LV's ellipsoids. Measured (P1, points with the axis
// at least 30 degrees from the normal, below z = 5 mm), helix error mean /
// 95 % / max [degrees]: LV free wall endo 1.01 / 4.36 / 10.8, epi 0.78 /
// 2.89 / 10.4; RV free wall endo 1.56 / 4.55 / 9.2, epi 2.10 / 6.77 / 11.6;
// septum LV side 0.46 / 1.03 / 2.4, RV side 0.48 / 1.69 / 4.4; mid-septum
// (0.2 < d < 0.8) 0.80 / 2.39 / 11.2. The free walls' errors are those of
// grad psi against the axis (the RV is no body of revolution, and its wall
// is two 2.1 mm tetrahedra thick); the bounds leave about a factor 1.5.
TEST_CASE("Biventricular fibres on a tetrahedral BiV from its tags alone have "
          "the prescribed angles on the free walls and through the septum",
          "[fibres][biventricular][simplex]")
{
  Geometry::Parameters geometry;
  geometry.type      = Geometry::Parameters::Type::gmsh;
  geometry.mesh_file = SYSTOLE_SOURCE_DIR "/meshes/biv_ellipsoid_tet.msh";
  const auto mesh = Geometry::create_distributed_mesh(geometry, MPI_COMM_WORLD);
  const dealii::Triangulation<3> &tria = *mesh.tria;
  Geometry::BoundaryNames         names("the test's name table");
  names.add("epicardium", 1);
  names.add("base", 2);
  names.add("lv_endocardium", 3);
  names.add("rv_endocardium", 4);
  const Geometry::CellKind kind(tria);
  REQUIRE(kind.simplex());

  Fibres::Biventricular::Parameters params;
  // Doste et al. 2019-like: the ventricles differ.
  params.lv_alpha_endo = 60 * deg;
  params.lv_alpha_epi  = -60 * deg;
  params.rv_alpha_endo = 80 * deg;
  params.rv_alpha_epi  = -25 * deg;
  params.lv_beta_endo  = -20 * deg;
  params.rv_beta_endo  = 0;
  params.septum_alpha  = 0;
  // P1 keeps the test short (7070 DOFs per solve, 3 s; P2: 45 788, 16 s,
  // with the same errors within 0.2 degrees on average).
  params.degree = 1;
  const Fibres::Biventricular rule(params, tria, names);
  INFO(rule.summary());

  const auto              mapping = kind.mapping(tria, 1);
  const auto              fe      = kind.lagrange(1);
  dealii::FEValues<3>     cells(*mapping,
                            *fe,
                            kind.cell_quadrature(2),
                            dealii::update_quadrature_points);
  dealii::FEFaceValues<3> faces(*mapping,
                                *fe,
                                kind.face_quadrature(2),
                                dealii::update_quadrature_points |
                                  dealii::update_normal_vectors);

  std::map<std::string, Stats>                  helix, transmural;
  Stats                                         septum;
  std::vector<Fibres::FibreBasis>               bases;
  std::vector<Fibres::BiventricularCoordinates> coordinates;
  const auto lv_endo = names.id("lv_endocardium"),
             rv_endo = names.id("rv_endocardium"), epi = names.id("epicardium");
  const dealii::Tensor<1, 3> axis({0.0, 0.0, 1.0});
  // The helix angle of @p f [degrees] in the frame of the wall normal e_t
  // and the axis projected onto the wall; NaN near the apices (the wall
  // nearly normal to the axis).
  const auto helix_angle = [&axis](const dealii::Tensor<1, 3> &f,
                                   const dealii::Tensor<1, 3> &e_t) {
    const dealii::Tensor<1, 3> l = axis - (axis * e_t) * e_t;
    if (l.norm() < 0.5)
      return std::nan("");
    const dealii::Tensor<1, 3> e_l = l / l.norm();
    return Fibres::helix_angle(f, dealii::cross_product_3d(e_l, e_t), e_l) /
           deg;
  };
  // The septal law of the rule, in the LV's orientation [degrees].
  const auto septal_alpha = [&params](const double d) {
    return (d <= 0.5
              ? params.lv_alpha_endo +
                  2 * d * (params.septum_alpha - params.lv_alpha_endo)
              : params.septum_alpha +
                  (2 * d - 1) * (-params.rv_alpha_endo - params.septum_alpha)) /
           deg;
  };
  unsigned int n_points = 0;
  for (const auto &cell : tria.active_cell_iterators())
    if (cell->is_locally_owned())
      {
        cells.reinit(cell);
        REQUIRE_NOTHROW(rule(cell, cells.get_quadrature_points(), bases));
        rule.coordinates(cell, cells.get_quadrature_points(), coordinates);
        for (unsigned int q = 0; q < bases.size(); ++q)
          {
            REQUIRE_NOTHROW(Fibres::validate(bases[q], "test", 1e-12));
            ++n_points;
            // Mid-septum: between the cavities, away from the junctions and
            // the base, in the frame of the LV's (nearly concentric)
            // ellipsoids.
            const auto &x = cells.quadrature_point(q);
            const auto &c = coordinates[q];
            if (c.depth > 0.2 && c.depth < 0.8 && c.phi_epi < 0.05 &&
                x[2] < 0 && lv_cavity(x) > 1 && lv_outer(x) < 1)
              {
                const dealii::Tensor<1, 3> g({2 * x[0] / (17 * 17),
                                              2 * x[1] / (17 * 17),
                                              2 * x[2] / (40 * 40)});
                const double h = helix_angle(bases[q].f, g / g.norm());
                if (std::isfinite(h))
                  septum.add(axis_difference(h, septal_alpha(c.depth)));
              }
          }
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() != names.id("base"))
            {
              const auto id = cell->face(f)->boundary_id();
              faces.reinit(cell, f);
              rule(cell, faces.get_quadrature_points(), bases);
              rule.coordinates(cell,
                               faces.get_quadrature_points(),
                               coordinates);
              for (const unsigned int q : faces.quadrature_point_indices())
                {
                  const auto &x = faces.quadrature_point(q);
                  const auto &c = coordinates[q];
                  // Out of the cavity into the wall on the endocardia, out
                  // of the heart on the epicardium.
                  const dealii::Tensor<1, 3> e_t = id == epi
                                                     ? faces.normal_vector(q)
                                                     : -faces.normal_vector(q);
                  std::string                where;
                  double                     alpha = 0;
                  if (id == lv_endo)
                    {
                      transmural["endocardia"].add(c.phi_epi);
                      transmural["LV endocardium"].add(c.phi_lv - 1);
                      // Septal where the RV cavity lies beyond the 5 mm
                      // LV wall.
                      const dealii::Point<3> beyond = x + 8.0 * e_t;
                      where = rv_cavity(beyond) < 0.95  ? "septum, LV side"
                              : rv_outer(beyond) > 1.05 ? "LV free wall endo"
                                                        : "";
                      alpha = params.lv_alpha_endo;
                    }
                  else if (id == rv_endo)
                    {
                      transmural["endocardia"].add(c.phi_epi);
                      transmural["RV endocardium"].add(c.phi_rv - 1);
                      // On the LV's outer ellipsoid: the septum.
                      const double on_lv = std::abs(lv_outer(x) - 1),
                                   on_rv = std::abs(rv_cavity(x) - 1);
                      where = on_lv < 0.03 && on_rv > 0.1 ? "septum, RV side"
                              : on_rv < 0.03 && on_lv > 0.1
                                ? "RV free wall endo"
                                : "";
                      alpha = params.rv_alpha_endo;
                    }
                  else
                    {
                      transmural["epicardium"].add(c.phi_epi - 1);
                      where = c.depth < 0.05   ? "LV free wall epi"
                              : c.depth > 0.95 ? "RV free wall epi"
                                               : "";
                      alpha = c.depth < 0.05 ? params.lv_alpha_epi
                                             : params.rv_alpha_epi;
                    }
                  // Away from the base ring.
                  if (where.empty() || x[2] > 5)
                    continue;
                  const double h = helix_angle(bases[q].f, e_t);
                  if (std::isfinite(h))
                    helix[where].add(axis_difference(h, alpha / deg));
                }
            }
      }
  CHECK(n_points == cells.get_quadrature().size() * tria.n_active_cells());
  for (const auto &[where, s] : transmural)
    {
      INFO(where << ": largest deviation from the Dirichlet value " << s.max());
      CHECK(s.max() < 1e-8);
    }
  for (const std::string where : {"LV free wall endo",
                                  "LV free wall epi",
                                  "RV free wall endo",
                                  "RV free wall epi",
                                  "septum, LV side",
                                  "septum, RV side"})
    {
      const Stats &h = helix[where];
      INFO("P" << params.degree << ", " << where << ": " << h.n()
               << " points, helix error mean " << h.mean() << ", 95% "
               << h.percentile(0.95) << ", max " << h.max() << " degrees");
      REQUIRE(h.n() > 1000);
      CHECK(h.mean() < 3.0);
      CHECK(h.percentile(0.95) < 9.0);
      CHECK(h.max() < 16.0);
    }
  INFO("P" << params.degree << ", mid-septum: " << septum.n()
           << " points, helix error mean " << septum.mean() << ", 95% "
           << septum.percentile(0.95) << ", max " << septum.max());
  REQUIRE(septum.n() > 1000);
  CHECK(septum.mean() < 1.5);
  CHECK(septum.percentile(0.95) < 4.0);
}
