#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>

#include "fibres/biventricular.h"
#include "fibres/fibre_field.h"
#include "geometry/mesh.h"
#include "support/angle_statistics.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

using namespace systole;

namespace
{
  constexpr double deg = M_PI / 180;

  /// A random rotation frame (seeded).
  Fibres::FibreBasis
  random_frame(std::mt19937 &rng)
  {
    std::normal_distribution<double> normal(0.0, 1.0);
    Fibres::Quaternion               q;
    double                           norm = 0;
    for (double &c : q)
      {
        c = normal(rng);
        norm += c * c;
      }
    for (double &c : q)
      c /= std::sqrt(norm);
    return Fibres::basis(q);
  }

  /// @p b turned by @p angle about the unit axis @p axis (Rodrigues).
  dealii::Tensor<1, 3>
  rotate(const dealii::Tensor<1, 3> &v,
         const dealii::Tensor<1, 3> &axis,
         const double                angle)
  {
    return std::cos(angle) * v +
           std::sin(angle) * dealii::cross_product_3d(axis, v) +
           (1 - std::cos(angle)) * (axis * v) * axis;
  }

  Fibres::FibreBasis
  rotate(const Fibres::FibreBasis   &b,
         const dealii::Tensor<1, 3> &axis,
         const double                angle)
  {
    return {rotate(b.f, axis, angle),
            rotate(b.s, axis, angle),
            rotate(b.n, axis, angle)};
  }

  /// Same axes (each vector up to its sign).
  bool
  same_axes(const Fibres::FibreBasis &a,
            const Fibres::FibreBasis &b,
            const double              tolerance)
  {
    return std::abs(std::abs(a.f * b.f) - 1) < tolerance &&
           std::abs(std::abs(a.s * b.s) - 1) < tolerance &&
           std::abs(std::abs(a.n * b.n) - 1) < tolerance;
  }

  /// Rotation angle between two quaternions [rad], in [0, pi].
  double
  angle_between(const Fibres::Quaternion &a, const Fibres::Quaternion &b)
  {
    double c = 0;
    for (unsigned int i = 0; i < 4; ++i)
      c += a[i] * b[i];
    return 2 * std::acos(std::min(1.0, std::abs(c)));
  }

  using test_support::axis_difference;
} // namespace

TEST_CASE("Quaternions of frames round-trip", "[fibres][bislerp]")
{
  std::mt19937 rng(42);
  for (unsigned int k = 0; k < 100; ++k)
    {
      const Fibres::FibreBasis b    = random_frame(rng);
      const Fibres::FibreBasis back = Fibres::basis(Fibres::quaternion(b));
      CHECK((back.f - b.f).norm() < 1e-12);
      CHECK((back.s - b.s).norm() < 1e-12);
      CHECK((back.n - b.n).norm() < 1e-12);
      CHECK_NOTHROW(Fibres::validate(b, "random frame", 1e-12));
    }
}

TEST_CASE("Slerp hits its endpoints, stays unit and takes the shortest arc",
          "[fibres][bislerp]")
{
  std::mt19937 rng(7);
  for (unsigned int k = 0; k < 50; ++k)
    {
      const auto q0 = Fibres::quaternion(random_frame(rng));
      const auto q1 = Fibres::quaternion(random_frame(rng));
      // The shorter arc: at most pi of rotation, whichever sign q1 has.
      const double theta = angle_between(q0, q1);
      REQUIRE(theta <= M_PI + 1e-12);
      Fibres::Quaternion minus_q1;
      for (unsigned int i = 0; i < 4; ++i)
        minus_q1[i] = -q1[i];
      for (const double t : {0.0, 0.25, 0.5, 0.8, 1.0})
        {
          const auto   q  = Fibres::slerp(q0, q1, t);
          const auto   qm = Fibres::slerp(q0, minus_q1, t);
          const double norm =
            std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
          CHECK(norm == Approx(1.0).epsilon(1e-14));
          // Constant angular speed along the shortest arc.
          CHECK(angle_between(q0, q) == Approx(t * theta).margin(1e-9));
          CHECK(angle_between(q, q1) == Approx((1 - t) * theta).margin(1e-9));
          CHECK(angle_between(q, qm) == Approx(0.0).margin(1e-7));
        }
      CHECK(angle_between(Fibres::slerp(q0, q1, 0.0), q0) < 1e-7);
      CHECK(angle_between(Fibres::slerp(q0, q1, 1.0), q1) < 1e-7);
    }
}

TEST_CASE("Bislerp turns a frame about a common axis the short way",
          "[fibres][bislerp]")
{
  std::mt19937             rng(3);
  const Fibres::FibreBasis a = random_frame(rng);
  SECTION("an angle below 90 degrees is interpolated linearly")
  {
    const Fibres::FibreBasis b = rotate(a, a.s, 40 * deg);
    for (const double t : {0.0, 0.3, 0.5, 1.0})
      CHECK(same_axes(Fibres::bislerp(a, b, t),
                      rotate(a, a.s, t * 40 * deg),
                      1e-10));
  }
  SECTION("170 degrees about an axis of the frame is -10 degrees for axes")
  {
    // b's axes equal a's turned by -10 degrees (f and n flip sign).
    const Fibres::FibreBasis b = rotate(a, a.s, 170 * deg);
    CHECK(
      same_axes(Fibres::bislerp(a, b, 0.5), rotate(a, a.s, -5 * deg), 1e-10));
    // Plain slerp of the same frames would turn the long way (85 degrees).
    const Fibres::FibreBasis long_way = Fibres::basis(
      Fibres::slerp(Fibres::quaternion(a), Fibres::quaternion(b), 0.5));
    CHECK(!same_axes(long_way, rotate(a, a.s, -5 * deg), 1e-3));
  }
  SECTION("the endpoints: a's axes at t = 0, b itself at t = 1")
  {
    const Fibres::FibreBasis b = random_frame(rng);
    CHECK(same_axes(Fibres::bislerp(a, b, 0.0), a, 1e-10));
    const Fibres::FibreBasis end = Fibres::bislerp(a, b, 1.0);
    CHECK((end.f - b.f).norm() < 1e-10);
    CHECK((end.s - b.s).norm() < 1e-10);
    for (const double t : {0.2, 0.7})
      CHECK_NOTHROW(Fibres::validate(Fibres::bislerp(a, b, t), "bislerp"));
  }
}

namespace
{
  struct BiVFixture
  {
    BiVFixture()
      : tria(MPI_COMM_WORLD)
    {
      Geometry::Parameters geometry;
      geometry.type      = Geometry::Parameters::Type::gmsh;
      geometry.mesh_file = SYSTOLE_SOURCE_DIR "/meshes/biv_coarse.msh";
      names              = std::make_unique<Geometry::BoundaryNames>(
        Geometry::create_mesh(geometry, tria));
    }

    dealii::parallel::distributed::Triangulation<3> tria;
    std::unique_ptr<Geometry::BoundaryNames>        names;
  };
} // namespace

TEST_CASE("The shipped BiV mesh has its four parts and no inverted cell",
          "[geometry][biventricular]")
{
  BiVFixture                                   mesh;
  std::map<dealii::types::boundary_id, double> area;
  for (const std::string part :
       {"lv_endocardium", "rv_endocardium", "epicardium", "base"})
    {
      REQUIRE(mesh.names->has(part));
      area[mesh.names->id(part)] = 0;
    }
  const dealii::MappingQ<3> mapping(1);
  const dealii::FE_Q<3>     fe(1);
  // Corners and 3 x 3 x 3 Gauss points.
  dealii::FEValues<3>     corners(mapping,
                              fe,
                              dealii::QTrapezoid<3>(),
                              dealii::update_JxW_values);
  dealii::FEValues<3>     gauss(mapping,
                            fe,
                            dealii::QGauss<3>(3),
                            dealii::update_JxW_values);
  dealii::FEFaceValues<3> faces(mapping,
                                fe,
                                dealii::QGauss<2>(2),
                                dealii::update_JxW_values);
  unsigned int            n_inverted = 0, n_cells = 0;
  for (const auto &cell : mesh.tria.active_cell_iterators())
    {
      ++n_cells;
      bool inverted = false;
      for (auto *values : {&corners, &gauss})
        {
          values->reinit(cell);
          for (const unsigned int q : values->quadrature_point_indices())
            inverted = inverted || !(values->JxW(q) > 0);
        }
      n_inverted += inverted ? 1 : 0;
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            REQUIRE(area.count(cell->face(f)->boundary_id()) == 1);
            faces.reinit(cell, f);
            for (const unsigned int q : faces.quadrature_point_indices())
              area[cell->face(f)->boundary_id()] += faces.JxW(q);
          }
    }
  CHECK(n_cells == 12332); // the count gmsh reports (meshes/README.md)
  CHECK(n_inverted == 0);
  // Every part is there with a sensible area [mm^2]: the LV cavity's surface
  // below the base is near that of its ellipsoid (about 7000 mm^2), the base
  // ring a few hundred.
  CHECK(area[mesh.names->id("lv_endocardium")] > 5000);
  CHECK(area[mesh.names->id("lv_endocardium")] < 8000);
  CHECK(area[mesh.names->id("rv_endocardium")] > 4000);
  CHECK(area[mesh.names->id("epicardium")] >
        area[mesh.names->id("lv_endocardium")]);
  CHECK(area[mesh.names->id("base")] > 100);
}

TEST_CASE("Biventricular fibres have the prescribed angles on each surface",
          "[fibres][biventricular]")
{
  BiVFixture                        mesh;
  Fibres::Biventricular::Parameters params;
  // Doste et al. 2019-like: the ventricles differ.
  params.lv_alpha_endo = 60 * deg;
  params.lv_alpha_epi  = -60 * deg;
  params.rv_alpha_endo = 80 * deg;
  params.rv_alpha_epi  = -25 * deg;
  params.lv_beta_endo  = -20 * deg;
  params.rv_beta_endo  = 0;
  // Q1 keeps the test short (16k DOFs per solve instead of 113k).
  params.degree = 1;
  const Fibres::Biventricular rule(params, mesh.tria, *mesh.names);

  const dealii::MappingQ<3> mapping(1);
  const dealii::FE_Q<3>     fe(1);
  dealii::FEValues<3>       cells(mapping,
                            fe,
                            dealii::QGauss<3>(2),
                            dealii::update_quadrature_points);
  dealii::FEFaceValues<3>   faces(mapping,
                                fe,
                                dealii::QGauss<2>(2),
                                dealii::update_quadrature_points |
                                  dealii::update_normal_vectors);

  // Helix and sheet angles [degree] measured in a frame of the mesh alone:
  // the face normal and the long axis z projected onto the face.
  struct Stats
  {
    double              sum = 0, max = 0;
    unsigned int        n = 0;
    std::vector<double> errors;
    void
    add(const double e)
    {
      sum += std::abs(e);
      max = std::max(max, std::abs(e));
      ++n;
      errors.push_back(std::abs(e));
    }
    double
    percentile(const double fraction)
    {
      std::sort(errors.begin(), errors.end());
      return errors[static_cast<std::size_t>(fraction * (errors.size() - 1))];
    }
  };
  std::map<std::string, Stats>                  helix, sheet;
  std::vector<Fibres::FibreBasis>               bases;
  std::vector<Fibres::BiventricularCoordinates> coordinates;
  unsigned int                                  n_points = 0;
  const auto lv_endo = mesh.names->id("lv_endocardium"),
             rv_endo = mesh.names->id("rv_endocardium"),
             epi     = mesh.names->id("epicardium");
  for (const auto &cell : mesh.tria.active_cell_iterators())
    {
      cells.reinit(cell);
      rule(cell, cells.get_quadrature_points(), bases);
      for (const auto &b : bases)
        {
          CHECK(std::abs(b.f.norm() - 1) < 1e-12);
          CHECK(std::abs(b.f * b.s) < 1e-12);
          CHECK((dealii::cross_product_3d(b.f, b.s) - b.n).norm() < 1e-12);
          ++n_points;
        }
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            cell->face(f)->boundary_id() != mesh.names->id("base"))
          {
            const auto id = cell->face(f)->boundary_id();
            faces.reinit(cell, f);
            rule(cell, faces.get_quadrature_points(), bases);
            rule.coordinates(cell, faces.get_quadrature_points(), coordinates);
            for (const unsigned int q : faces.quadrature_point_indices())
              {
                const auto &x = faces.quadrature_point(q);
                // Out of the cavity into the wall on the endocardia, out of
                // the heart on the epicardium.
                const dealii::Tensor<1, 3> e_t =
                  id == epi ? faces.normal_vector(q) : -faces.normal_vector(q);
                dealii::Tensor<1, 3> axis;
                axis[2]                      = 1;
                const dealii::Tensor<1, 3> l = axis - (axis * e_t) * e_t;
                // Away from the apices (wall nearly normal to the axis) and
                // the basal ring.
                if (l.norm() < 0.5 || x[2] > 15)
                  continue;
                const dealii::Tensor<1, 3> e_l = l / l.norm();
                const dealii::Tensor<1, 3> e_c =
                  dealii::cross_product_3d(e_l, e_t);
                const auto  &b = bases[q];
                const double h = std::atan2(b.f * e_l, b.f * e_c) / deg;
                // The fibre's sign matters to the sheet angle's: take the
                // one with a positive circumferential part.
                const dealii::Tensor<1, 3> f_c = b.f * e_c < 0 ? -b.f : b.f;
                const dealii::Tensor<1, 3> side =
                  dealii::cross_product_3d(f_c, e_t);
                const double beta =
                  std::atan2(b.s * side / side.norm(), b.s * e_t) / deg;
                const double d = coordinates[q].depth;
                std::string  where;
                double       alpha = 0, beta0 = 0;
                if (id == lv_endo)
                  where = "LV endocardium", alpha = params.lv_alpha_endo,
                  beta0 = params.lv_beta_endo;
                else if (id == rv_endo)
                  where = "RV endocardium", alpha = params.rv_alpha_endo,
                  beta0 = params.rv_beta_endo;
                else if (d < 0.05)
                  where = "LV epicardium", alpha = params.lv_alpha_epi,
                  beta0 = params.lv_beta_epi;
                else if (d > 0.95)
                  where = "RV epicardium", alpha = params.rv_alpha_epi,
                  beta0 = params.rv_beta_epi;
                else
                  continue; // the junctions, where the ventricles blend
                helix[where].add(axis_difference(h, alpha / deg));
                sheet[where].add(axis_difference(beta, beta0 / deg));
              }
          }
    }
  CHECK(n_points == 8 * mesh.tria.n_active_cells());
  for (const std::string where :
       {"LV endocardium", "RV endocardium", "LV epicardium", "RV epicardium"})
    {
      Stats &h = helix[where], &s = sheet[where];
      INFO(where << ": " << h.n << " points, helix error mean " << h.sum / h.n
                 << ", 95th percentile " << h.percentile(0.95) << ", max "
                 << h.max << " degrees; sheet error max " << s.max);
      REQUIRE(h.n > 100);
      // The longitudinal direction is grad psi in the rule, the long axis
      // here: they differ most near the apices and the junctions (Q1, 6 mm
      // cells: at most 17 degrees on the endocardia, 31 on the RV epicardium
      // near the junction).
      CHECK(h.sum / h.n < 3.0);
      CHECK(h.percentile(0.95) < 8.0);
      // The transmural fields are constant on their Dirichlet surfaces, so
      // their gradients are the exact face normals there: the sheet angle,
      // a rotation about f measured from the mesh's normal, is exact (this
      // checks the orientations and the sign change of the RV's angles).
      CHECK(s.max < 1e-6);
    }
}
