#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/linear_algebra.h"
#include "geometry/cell_kind.h"
#include "geometry/mesh.h"
#include "mechanics/cavity_volume.h"
#include "support/cup_mesh.h"
#include "support/finite_differences.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <map>
#include <memory>
#include <vector>

using namespace systole;
using test_support::cup_base;
using test_support::cup_cavity;

namespace
{
  /// A displacement field on @p tria: its DoF handler, mapping and vectors.
  struct Field
  {
    Field(const dealii::Triangulation<3, 3> &tria, const unsigned int degree)
      : kind(tria)
      , fe(*kind.lagrange(degree), 3)
      , dof_handler(tria)
      , mapping(kind.mapping(tria, degree))
      , n_points(degree + 2)
    {
      dof_handler.distribute_dofs(fe);
      owned = dof_handler.locally_owned_dofs();
      dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    }

    /// The interpolant of @p f plus @p h times that of @p g (ghosted).
    LA::MPI::Vector
    interpolate(const dealii::Function<3> &f,
                const double               h = 0.0,
                const dealii::Function<3> *g = nullptr) const
    {
      LA::MPI::Vector owned_u(owned, MPI_COMM_WORLD);
      dealii::VectorTools::interpolate(*mapping, dof_handler, f, owned_u);
      if (g != nullptr)
        {
          LA::MPI::Vector d(owned, MPI_COMM_WORLD);
          dealii::VectorTools::interpolate(*mapping, dof_handler, *g, d);
          owned_u.add(h, d);
        }
      LA::MPI::Vector u(owned, relevant, MPI_COMM_WORLD);
      u = owned_u;
      return u;
    }

    Geometry::CellKind                     kind;
    dealii::FESystem<3>                    fe;
    dealii::DoFHandler<3>                  dof_handler;
    std::unique_ptr<dealii::Mapping<3, 3>> mapping;
    unsigned int                           n_points;
    dealii::IndexSet                       owned, relevant;
  };

  /// The cavity volume of the cup deformed by x = X + d(X), computed from
  /// the deformed vertices alone (serial): the divergence theorem with the
  /// field (x_0, 0, 0) on the closed surface made of the cavity's faces
  /// (bilinear quadrilaterals, integrated exactly with 2 x 2 Gauss points,
  /// or flat triangles) and the triangles (c, b, a) over each rim edge a->b,
  /// c the mean of the deformed rim vertices (the vertices of cavity faces
  /// on the top z = 2). Shares no code with CavityVolume: no finite element,
  /// no mapping, no Nanson, and the lid's triangles contribute.
  double
  independent_volume(const dealii::Triangulation<3, 3> &tria,
                     const dealii::Function<3>         &d)
  {
    const auto deformed = [&](const dealii::Point<3> &X) {
      dealii::Point<3> x = X;
      for (unsigned int k = 0; k < 3; ++k)
        x[k] += d.value(X, k);
      return x;
    };
    const auto flux = [](const dealii::Point<3>     &x,
                         const dealii::Tensor<1, 3> &area) {
      return x[0] * area[0];
    };
    std::map<unsigned int, dealii::Point<3>>                   rim;
    std::vector<std::pair<dealii::Point<3>, dealii::Point<3>>> rim_edges;
    double                                                     volume = 0;
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() == cup_cavity)
          {
            const unsigned int            n = face->n_vertices();
            std::vector<dealii::Point<3>> X(n), x(n);
            for (unsigned int v = 0; v < n; ++v)
              {
                X[v] = face->vertex(v);
                x[v] = deformed(X[v]);
              }
            // The parametric normal at the centre against the wall's
            // outward normal N: the cavity's normal is -N.
            const dealii::Tensor<1, 3> parametric =
              n == 3 ? dealii::cross_product_3d(X[1] - X[0], X[2] - X[0])
                     : dealii::cross_product_3d(X[1] - X[0] + X[3] - X[2],
                                                X[2] - X[0] + X[3] - X[1]);
            const double sign =
              parametric * (face->center() - cell->center()) > 0 ? -1.0 : 1.0;
            if (n == 3)
              volume +=
                sign *
                flux((x[0] + x[1] + x[2]) / 3.0,
                     0.5 * dealii::cross_product_3d(x[1] - x[0], x[2] - x[0]));
            else
              {
                const double g[2] = {0.5 - 0.5 / std::sqrt(3.0),
                                     0.5 + 0.5 / std::sqrt(3.0)};
                for (const double s : g)
                  for (const double t : g)
                    {
                      const dealii::Point<3> y =
                        x[0] + s * (x[1] - x[0]) + t * (x[2] - x[0]) +
                        s * t * (x[3] - x[2] - x[1] + x[0]);
                      const dealii::Tensor<1, 3> y_s =
                        (x[1] - x[0]) + t * (x[3] - x[2] - x[1] + x[0]);
                      const dealii::Tensor<1, 3> y_t =
                        (x[2] - x[0]) + s * (x[3] - x[2] - x[1] + x[0]);
                      volume += 0.25 * sign *
                                flux(y, dealii::cross_product_3d(y_s, y_t));
                    }
              }
            // The boundary of the face, counter-clockwise about its
            // parametric normal; reversed when that is -n_cav.
            const std::vector<unsigned int> loop =
              n == 3 ? std::vector<unsigned int>{0, 1, 2}
                     : std::vector<unsigned int>{0, 1, 3, 2};
            for (unsigned int i = 0; i < n; ++i)
              {
                unsigned int a = loop[i], b = loop[(i + 1) % n];
                if (sign < 0)
                  std::swap(a, b);
                const bool on_top_a = std::abs(X[a][2] - 2.0) < 1e-12;
                const bool on_top_b = std::abs(X[b][2] - 2.0) < 1e-12;
                if (on_top_a)
                  rim[face->vertex_index(a)] = x[a];
                if (on_top_a && on_top_b)
                  rim_edges.emplace_back(x[a], x[b]);
              }
          }
    dealii::Point<3> c;
    for (const auto &[index, x] : rim)
      c += x / static_cast<double>(rim.size());
    for (const auto &[a, b] : rim_edges)
      volume +=
        flux((a + b + c) / 3.0, 0.5 * dealii::cross_product_3d(b - c, a - c));
    return volume;
  }

  /// A field that vanishes on the Land ventricle's base plane z = 5.
  class BaseFixed : public dealii::Function<3>
  {
  public:
    BaseFixed()
      : dealii::Function<3>(3)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return 0.1 * (5.0 - p[2]) * std::sin(0.3 * p[0] + 0.4 * (c + 1)) *
             std::cos(0.2 * p[1] + 0.15 * p[2]);
    }
  };
} // namespace

namespace
{
  /// Runs check(tria, 2) in one section per cup: the hexahedral cup (Q2 on
  /// MappingQ2) and the tetrahedral one (P2).
  template <typename Check>
  void
  on_both_cups(const Check &check)
  {
    SECTION("hexahedra, Q2 on MappingQ2")
    {
      dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
      test_support::make_cup(tria, 1);
      check(tria, 2);
    }
    SECTION("tetrahedra, P2")
    {
      dealii::Triangulation<3> tria;
      test_support::make_tet_cup(tria, 0);
      check(tria, 2);
    }
  }
} // namespace

TEST_CASE("The rim-fan volume of a warped rim equals the volume of the closed "
          "polyhedral surface",
          "[mechanics][cavity][analytic]")
{
  const test_support::WarpingDisplacement d(0.15, 0.3);
  SECTION("hexahedra, Q1")
  {
    dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
    test_support::make_cup(tria, 1);
    const Field                   field(tria, 1);
    const Mechanics::CavityVolume cavity(tria, cup_cavity, cup_base);
    CHECK(cavity.closure() == Mechanics::CavityVolume::Closure::rim_fan);
    CHECK(cavity.n_rim_vertices() == 8);
    const double volume   = cavity.volume(*field.mapping,
                                        field.dof_handler,
                                        field.interpolate(d),
                                        field.n_points);
    const double expected = independent_volume(tria, d);
    // The plane lid of the undeformed top closes a different volume.
    const Mechanics::CavityVolume flat_lid(cup_cavity,
                                           {dealii::Point<3>(0, 0, 2),
                                            dealii::Tensor<1, 3>({0, 0, 1})});
    const double                  flat = flat_lid.volume(*field.mapping,
                                        field.dof_handler,
                                        field.interpolate(d),
                                        field.n_points);
    INFO(std::setprecision(16)
         << "fan " << volume << " mm^3, polyhedron " << expected
         << " mm^3, relative difference "
         << std::abs(volume - expected) / std::abs(expected)
         << "; plane z = 2: " << flat << " mm^3");
    CHECK(std::abs(volume - expected) < 1e-10 * std::abs(expected));
    CHECK(std::abs(volume - flat) > 1e-3);
  }
  SECTION("tetrahedra, P1")
  {
    dealii::Triangulation<3> tria;
    test_support::make_tet_cup(tria, 1);
    const Field                   field(tria, 1);
    const Mechanics::CavityVolume cavity(tria, cup_cavity, cup_base);
    CHECK(field.kind.simplex());
    const double volume   = cavity.volume(*field.mapping,
                                        field.dof_handler,
                                        field.interpolate(d),
                                        field.n_points);
    const double expected = independent_volume(tria, d);
    INFO(std::setprecision(16)
         << "fan " << volume << " mm^3, polyhedron " << expected
         << " mm^3, relative difference "
         << std::abs(volume - expected) / std::abs(expected) << ", "
         << cavity.n_rim_vertices() << " rim vertices");
    CHECK(std::abs(volume - expected) < 1e-10 * std::abs(expected));
  }
}

TEST_CASE("Without a base, the rim is the boundary edges of the cavity part",
          "[mechanics][cavity]")
{
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  test_support::make_cup(tria, 1);
  const Field field(tria, 2);
  const auto  u = field.interpolate(test_support::WarpingDisplacement(0.2, 0));
  const Mechanics::CavityVolume with_base(tria, cup_cavity, cup_base);
  const Mechanics::CavityVolume own_edges(tria,
                                          cup_cavity,
                                          dealii::numbers::invalid_boundary_id);
  CHECK(own_edges.n_rim_vertices() == with_base.n_rim_vertices());
  CHECK(own_edges.volume(*field.mapping, field.dof_handler, u, 4) ==
        Approx(with_base.volume(*field.mapping, field.dof_handler, u, 4))
          .epsilon(1e-14));
}

TEST_CASE("dV/du of the rim fan is the finite-difference derivative of V for "
          "a moving, warped rim",
          "[mechanics][cavity][fd]")
{
  const test_support::WarpingDisplacement u0(0.15, 0.3);
  const test_support::WarpingDisplacement d(0.3, 1.1); // moves the rim
  const auto check = [&](const dealii::Triangulation<3, 3> &tria,
                         const unsigned int                 degree) {
    const Field                   field(tria, degree);
    const Mechanics::CavityVolume cavity(tria, cup_cavity, cup_base);
    LA::MPI::Vector               dV_du(field.owned, MPI_COMM_WORLD);
    cavity.derivative(*field.mapping,
                      field.dof_handler,
                      field.interpolate(u0),
                      field.n_points,
                      dV_du);
    LA::MPI::Vector direction(field.owned, MPI_COMM_WORLD);
    dealii::VectorTools::interpolate(*field.mapping,
                                     field.dof_handler,
                                     d,
                                     direction);
    const double exact = dV_du * direction;

    // V(u0 + h d) is a cubic in h (c and x linear, cof F quadratic): the
    // central difference's error is h^2 V'''/6, order 2 exactly.
    test_support::FdStudy study;
    for (const double h : {0.2, 0.1, 0.05})
      {
        const auto volume = [&](const double s) {
          return cavity.volume(*field.mapping,
                               field.dof_handler,
                               field.interpolate(u0, s, &d),
                               field.n_points);
        };
        study.steps.push_back(h);
        study.errors.push_back(
          std::abs((volume(h) - volume(-h)) / (2 * h) - exact) /
          std::abs(exact));
      }
    INFO("degree " << degree << ", dV/du . d = " << exact << "\n"
                   << study.describe());
    for (const double order : study.observed_orders())
      CHECK(order == Approx(2.0).margin(0.05));
    CHECK(study.errors.back() < 1e-3);
  };
  on_both_cups(check);
}

TEST_CASE("For a planar rim the fan gives the plane lid's volume",
          "[mechanics][cavity][analytic]")
{
  // The Land ventricle, base z = 5 held in place: the rim's vertex mean lies
  // in the lid plane, so the cone is the plane lid.
  Geometry::Parameters                            geometry;
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto names = Geometry::create_mesh(geometry, tria);
  const auto lid   = Geometry::boundary_plane(tria, names.id("base"), "base");
  const dealii::FESystem<3> fe(dealii::FE_Q<3>(2), 3);
  dealii::DoFHandler<3>     dof_handler(tria);
  dof_handler.distribute_dofs(fe);
  const dealii::MappingQ<3> mapping(2);
  dealii::IndexSet          relevant;
  dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
  const auto     &owned = dof_handler.locally_owned_dofs();
  LA::MPI::Vector u_owned(owned, MPI_COMM_WORLD);
  dealii::VectorTools::interpolate(mapping, dof_handler, BaseFixed(), u_owned);
  LA::MPI::Vector u(owned, relevant, MPI_COMM_WORLD);
  u = u_owned;

  const Mechanics::CavityVolume plane(names.id("endocardium"), lid);
  const Mechanics::CavityVolume fan(tria,
                                    names.id("endocardium"),
                                    names.id("base"));
  const double v_plane = plane.volume(mapping, dof_handler, u, 4);
  const double v_fan   = fan.volume(mapping, dof_handler, u, 4);
  INFO(std::setprecision(16)
       << "plane " << v_plane << " mm^3, fan " << v_fan
       << " mm^3, relative difference " << std::abs(v_fan - v_plane) / v_plane);
  CHECK(v_fan == Approx(v_plane).epsilon(1e-12));

  // Along a field that holds the base the derivatives agree too.
  LA::MPI::Vector b_plane(owned, MPI_COMM_WORLD), b_fan(owned, MPI_COMM_WORLD);
  plane.derivative(mapping, dof_handler, u, 4, b_plane);
  fan.derivative(mapping, dof_handler, u, 4, b_fan);
  CHECK(b_fan * u_owned == Approx(b_plane * u_owned).epsilon(1e-12));
}

namespace
{
  /// Over the cavity faces of @p field's mesh (serial), at the displacement
  /// @p u and a fixed fan apex @p c: the fan's face vectors (sum of
  /// CavityVolume::add_fan_face's v) dotted with @p d, and its matrix M
  /// applied as d^T M e.
  std::pair<double, double>
  fan_face_terms(const Field            &field,
                 const LA::MPI::Vector  &u,
                 const LA::MPI::Vector  &d,
                 const LA::MPI::Vector  &e,
                 const dealii::Point<3> &c)
  {
    const dealii::Quadrature<2> quadrature =
      field.kind.face_quadrature(field.n_points);
    dealii::FEFaceValues<3>                      fe_face(*field.mapping,
                                    field.fe,
                                    quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_quadrature_points |
                                      dealii::update_normal_vectors |
                                      dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector     displacement(0);
    const unsigned int                           n = field.fe.n_dofs_per_cell();
    std::vector<dealii::Tensor<1, 3>>            values(quadrature.size());
    std::vector<dealii::Tensor<2, 3>>            gradients(quadrature.size());
    std::vector<dealii::types::global_dof_index> dofs(n);
    dealii::Vector<double>                       v(n);
    dealii::FullMatrix<double>                   M(n, n);
    dealii::Tensor<1, 3>                         area;
    double                                       vd = 0, dMd = 0;
    for (const auto &cell : field.dof_handler.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() == cup_cavity)
          {
            fe_face.reinit(cell, face);
            fe_face[displacement].get_function_values(u, values);
            fe_face[displacement].get_function_gradients(u, gradients);
            v = 0;
            M = 0;
            Mechanics::CavityVolume::add_fan_face(fe_face,
                                                  values,
                                                  gradients,
                                                  c,
                                                  1.0,
                                                  v,
                                                  &M,
                                                  area);
            cell->get_dof_indices(dofs);
            for (unsigned int a = 0; a < n; ++a)
              {
                vd += v(a) * d(dofs[a]);
                for (unsigned int b = 0; b < n; ++b)
                  dMd += d(dofs[a]) * M(a, b) * e(dofs[b]);
              }
          }
    return {vd, dMd};
  }
} // namespace

TEST_CASE("The rim fan's face Hessian is the derivative of its face vector",
          "[mechanics][cavity][fd]")
{
  // At a fixed apex c the fan's face terms are a function of u alone: the
  // matrix of add_fan_face (the load's tangent when the lid is loaded) must
  // be the derivative of its vector: d^T M e against the central difference
  // of v . d along e, and the other way round (M is symmetric). v is
  // quadratic in u at fixed c, so the central difference is exact up to
  // round-off.
  const test_support::WarpingDisplacement u0(0.15, 0.3);
  const test_support::WarpingDisplacement d(0.3, 1.1), e(-0.2, 0.7);
  const auto check = [&](const dealii::Triangulation<3, 3> &tria,
                         const unsigned int                 degree) {
    const Field            field(tria, degree);
    const auto             u = field.interpolate(u0);
    const auto             D = field.interpolate(d);
    const auto             E = field.interpolate(e);
    const dealii::Point<3> c(0.3, -0.2, 2.4);
    for (const bool swap : {false, true})
      {
        const auto  &first = swap ? E : D;
        const auto  &along = swap ? d : e;
        const auto  &other = swap ? D : E;
        const double exact = fan_face_terms(field, u, first, other, c).second;
        const double h     = 0.1;
        const double plus  = fan_face_terms(field,
                                           field.interpolate(u0, h, &along),
                                           first,
                                           other,
                                           c)
                              .first;
        const double minus = fan_face_terms(field,
                                            field.interpolate(u0, -h, &along),
                                            first,
                                            other,
                                            c)
                               .first;
        const double error = std::abs((plus - minus) / (2 * h) - exact);
        INFO("degree " << degree << (swap ? ", e^T M d = " : ", d^T M e = ")
                       << exact << ", FD error " << error);
        CHECK(std::abs(exact) > 1e-3);
        CHECK(error < 1e-10 * std::abs(exact) + 1e-14);
      }
  };
  on_both_cups(check);
}
