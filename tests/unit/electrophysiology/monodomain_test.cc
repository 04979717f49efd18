// The monodomain solver on small boxes: time-step convergence against a
// fine-step reference, anisotropy, stimulus regions, point evaluation,
// save/restore and the deformation pull-back.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/mapping_q.h>

#include "base/logger.h"
#include "electrophysiology/monodomain.h"
#include "geometry/mesh.h"
#include "support/ep_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <sstream>

using namespace systole;
using namespace systole::Electrophysiology;
using test_support::EPBox;
using test_support::run_ep_box;
using test_support::unit_vector;

namespace
{
  /// A cable along x (fibres along @p fibre), stimulated at x <= 0.5 mm.
  EPBox
  cable(const double length, const unsigned int cells, const unsigned int fibre)
  {
    EPBox box;
    box.upper = dealii::Point<3>(length, 0.25, 0.25);
    box.cells = {{cells, 1, 1}};
    box.fibre = unit_vector(fibre);
    return box;
  }

  /// An 8 x 0.5 x 0.5 mm cable of 32 x 2 x 2 cells on one rank, fibres
  /// along x, a logger that writes nowhere.
  struct CableMesh
  {
    dealii::parallel::distributed::Triangulation<3> tria{MPI_COMM_SELF};
    Geometry::BoundaryNames                         names = make_mesh(tria);
    dealii::MappingQ<3>                             mapping{1};
    Fibres::FibreField                              fibres =
      [](const auto &, const auto &points, auto &bases) {
        bases.assign(points.size(), Fibres::FibreBasis::cartesian());
      };
    std::ostringstream sink;
    Logger             logger{MPI_COMM_SELF, sink};

    static Geometry::BoundaryNames
    make_mesh(dealii::parallel::distributed::Triangulation<3> &tria)
    {
      Geometry::Parameters geometry;
      geometry.type      = Geometry::Parameters::Type::box;
      geometry.box_upper = dealii::Point<3>(8, 0.5, 0.5);
      geometry.box_cells = {{32, 2, 2}};
      return Geometry::create_mesh(geometry, tria);
    }
  };

  Parameters
  cable_parameters(const double time_step)
  {
    Parameters p = Parameters::defaults("Aliev-Panfilov");
    p.stimuli    = parse_stimuli("left: box 0 0 0 0.5 1 1 from 0 for 2 at 50");
    p.time_step  = time_step;
    p.linear_tolerance = 1e-12;
    return p;
  }
} // namespace

TEST_CASE("Monodomain activation times converge to a fine-step reference",
          "[ep][monodomain]")
{
  // 4 mm cable, h = 0.125 mm: the front reaches x = 3.5 mm after ~35 ms.
  const std::vector<dealii::Point<3>> probe = {dealii::Point<3>(3.5, 0, 0)};
  const auto                          at    = [&](const double dt) {
    return run_ep_box(cable_parameters(dt),
                      cable(4, 32, 0),
                      40,
                      5,
                      probe,
                      MPI_COMM_SELF)
      .probes.activation_time[0];
  };
  const double reference = at(0.0125);
  const double coarse    = at(0.2);
  const double medium    = at(0.1);
  INFO(std::setprecision(10)
       << "activation at x = 3.5 mm: dt 0.2 " << coarse << ", dt 0.1 " << medium
       << ", dt 0.0125 " << reference << " ms");
  REQUIRE(std::isfinite(reference));
  CHECK(reference > 20);
  CHECK(std::abs(medium - reference) < 1e-3 * reference);
  CHECK(std::abs(medium - reference) < std::abs(coarse - reference));
}

TEST_CASE("The conduction velocity ratio along/across the fibres is "
          "sqrt(sigma_l/sigma_t)",
          "[ep][monodomain]")
{
  // The same cable with the fibres along it and across it. Far from the
  // stimulus and from the sealed end the front travels at a constant speed
  // c ~ sqrt(D), measured between x = 2 and x = 5 mm of an 8 mm cable.
  const std::vector<dealii::Point<3>> probes = {dealii::Point<3>(2, 0, 0),
                                                dealii::Point<3>(5, 0, 0)};
  const Parameters                    p      = cable_parameters(0.1);
  const auto velocity = [&](const unsigned int fibre, const double end) {
    const auto r =
      run_ep_box(p, cable(8, 64, fibre), end, 10, probes, MPI_COMM_SELF);
    return 3.0 / (r.probes.activation_time[1] - r.probes.activation_time[0]);
  };
  const double along  = velocity(0, 50);
  const double across = velocity(1, 130);
  INFO("CV along " << along << " mm/ms, across " << across << " mm/ms");
  // Travelling-wave speed of the Aliev-Panfilov upstroke (w ~ 0 ahead of
  // the front): c = sqrt(D k / (2 T)) (1 - 2a).
  const double c = std::sqrt(p.diffusivity_l() * 8 / (2 * 12.9)) * 0.7;
  CHECK(along == Approx(c).epsilon(0.03));
  CHECK(along / across ==
        Approx(std::sqrt(p.sigma_l / p.sigma_t)).epsilon(0.03));
}

TEST_CASE("A surface stimulus is the layer along its boundary part",
          "[ep][monodomain]")
{
  // The layer within 0.75 mm of x_min holds the same nodes as the box
  // x <= 0.75 mm: the runs agree exactly, and the front is plane.
  EPBox box;
  box.upper        = dealii::Point<3>(3, 1, 1);
  box.cells        = {{12, 4, 4}};
  box.fibre        = unit_vector(0);
  Parameters layer = cable_parameters(0.1);
  Parameters brick = layer;
  layer.stimuli    = parse_stimuli("l: surface x_min 0.75 from 0 for 2 at 50");
  brick.stimuli    = parse_stimuli("b: box 0 0 0 0.75 1 1 from 0 for 2 at 50");
  const std::vector<dealii::Point<3>> probes = {dealii::Point<3>(2.5, 0, 0),
                                                dealii::Point<3>(2.5, 1, 1),
                                                dealii::Point<3>(2.5, .4, .6)};
  const auto a = run_ep_box(layer, box, 40, 10, probes, MPI_COMM_SELF);
  const auto b = run_ep_box(brick, box, 40, 10, probes, MPI_COMM_SELF);
  REQUIRE(std::isfinite(a.probes.activation_time[0]));
  for (unsigned int i = 0; i < 3; ++i)
    {
      CHECK(a.probes.activation_time[i] == b.probes.activation_time[i]);
      CHECK(a.probes.activation_time[i] ==
            Approx(a.probes.activation_time[0]).epsilon(1e-10));
    }
  CHECK(a.summary.activated_fraction == 1.0);
  CHECK(a.summary.total > 0);
  CHECK(a.summary.fraction_time <= a.summary.last);
}

TEST_CASE("Monodomain state: point evaluation, save and restore, pull-back",
          "[ep][monodomain]")
{
  CableMesh cable_mesh;
  auto &[tria, names, mapping, fibres, sink, logger] = cable_mesh;
  Parameters params                                  = cable_parameters(0.1);
  params.pull_back                                   = true;
  Monodomain ep(params, tria, mapping, fibres, names, logger);
  CHECK(ep.n_dofs() == 33 * 3 * 3);

  ep.advance(12);
  CHECK(ep.time() == 12);
  CHECK(ep.statistics().steps == 120);

  // evaluate() at the vertices of a cell is values_at_points() there.
  const auto                  cell = tria.begin_active();
  PointValues                 at_vertices;
  const dealii::QTrapezoid<3> vertices;
  ep.evaluate(cell, vertices, at_vertices);
  std::vector<dealii::Point<3>> points;
  for (unsigned int v = 0; v < 8; ++v)
    points.push_back(cell->vertex(v));
  const auto global = ep.values_at_points(points);
  for (unsigned int q = 0; q < vertices.size(); ++q)
    {
      // QTrapezoid's points are the vertices in deal.II's order.
      CHECK(at_vertices.potential[q] ==
            Approx(global.potential[q]).epsilon(1e-12));
      CHECK(at_vertices.activation_time[q] ==
            Approx(global.activation_time[q]).epsilon(1e-12));
      // The stimulated end has fired: depolarised and activated early.
      CHECK(at_vertices.potential[q] > -20);
      CHECK(at_vertices.activation_time[q] < 2.5);
    }

  // Save, advance, restore, advance again: the same state.
  ep.save();
  ep.advance(30);
  const auto first = ep.values_at_points({dealii::Point<3>(2, 0.25, 0.25)});
  ep.restore();
  CHECK(ep.time() == 12);
  ep.advance(30);
  const auto again = ep.values_at_points({dealii::Point<3>(2, 0.25, 0.25)});
  CHECK(again.potential[0] == first.potential[0]);
  CHECK(again.activation_time[0] == first.activation_time[0]);

  // Pull-back: an isochoric stretch lambda along the fibres,
  // F = diag(lambda, lambda^-1/2, lambda^-1/2), divides the reference
  // diffusivity along x by lambda^2, so the front crosses the reference
  // cable lambda times slower (the same speed over a lambda times longer
  // deformed cable).
  const auto activation_delay = [&](const double lambda) {
    Monodomain stretched(params, tria, mapping, fibres, names, logger);
    dealii::Tensor<2, 3> F;
    F[0][0] = lambda;
    F[1][1] = F[2][2] = 1 / std::sqrt(lambda);
    stretched.set_deformation_gradients(
      std::vector<std::vector<dealii::Tensor<2, 3>>>(tria.n_active_cells(),
                                                     {F}));
    stretched.advance(70);
    const auto v = stretched.values_at_points(
      {dealii::Point<3>(2, 0, 0), dealii::Point<3>(5, 0, 0)});
    return v.activation_time[1] - v.activation_time[0];
  };
  CHECK(activation_delay(1.2) / activation_delay(1.0) ==
        Approx(1.2).epsilon(0.03));
}

TEST_CASE("With a stimulus period, the latest activation time of a cell waits "
          "for all its nodes",
          "[ep][monodomain]")
{
  // A Mitchell-Schaeffer cable stimulated at x = 0 every 600 ms, stopped
  // while the second beat's wave crosses it: behind the front the cells hold
  // the second upstroke, ahead of it the first; the cell with nodes of both
  // beats has no latest activation time (their interpolant would be a time
  // in between, when nothing happened).
  CableMesh cable_mesh;
  auto &[tria, names, mapping, fibres, sink, logger] = cable_mesh;
  Parameters params = Parameters::defaults("Mitchell-Schaeffer");
  params.stimuli = parse_stimuli("left: box 0 0 0 0.5 1 1 from 0 for 2 at 50");
  params.stimulus_period = 600;
  params.time_step       = 0.1;
  Monodomain ep(params, tria, mapping, fibres, names, logger);
  ep.advance(612);

  const dealii::QGauss<3> centre(1);
  PointValues             values;
  unsigned int            first_beat = 0, second_beat = 0, crossing = 0;
  for (const auto &cell : tria.active_cell_iterators())
    {
      ep.evaluate(cell, centre, values);
      INFO("cell at x = " << cell->center()[0] << " mm");
      REQUIRE(values.activation_time[0] < 60); // all fired in beat 1
      const double latest = values.latest_activation_time[0];
      if (std::isnan(latest))
        ++crossing;
      else if (latest < 60)
        ++first_beat;
      else
        {
          CHECK(latest > 600);
          CHECK(latest < 612);
          ++second_beat;
        }
    }
  CHECK(first_beat > 0);
  CHECK(second_beat > 0);
  CHECK(crossing > 0);
  CHECK(crossing <= 8); // one cell across x: 2 x 2 cells of the cable
}

TEST_CASE("The monodomain exposes the ionic model's calcium at any point",
          "[ep][monodomain][ttp]")
{
  CableMesh cable_mesh;
  auto &[tria, names, mapping, fibres, sink, logger] = cable_mesh;
  Parameters params = Parameters::defaults("ten Tusscher-Panfilov");
  params.stimuli = parse_stimuli("left: box 0 0 0 0.5 1 1 from 0 for 2 at 50");
  params.time_step = 0.05;
  Monodomain ep(params, tria, mapping, fibres, names, logger);
  const std::vector<dealii::Point<3>> near_and_far =
    {dealii::Point<3>(0.25, 0.25, 0.25), dealii::Point<3>(7.75, 0.25, 0.25)};

  // At rest: the model's initial Ca_i, 0.126 µM.
  auto values = ep.values_at_points(near_and_far);
  CHECK(values.calcium_uM[0] == Approx(0.126));
  CHECK(values.calcium_uM[1] == Approx(0.126));

  // The stimulated end fires first; its calcium transient (peak about
  // 1 µM some 30 ms after the upstroke in the single cell) is well under
  // way at 40 ms, while the far end rests until the front arrives.
  ep.advance(3);
  values = ep.values_at_points(near_and_far);
  CHECK(values.potential[0] > 0);
  CHECK(values.calcium_uM[1] == Approx(0.126).epsilon(0.01));
  ep.advance(40);
  values = ep.values_at_points(near_and_far);
  CHECK(values.calcium_uM[0] > 0.5);
  CHECK(values.calcium_uM[0] < 1.2);

  // evaluate() in a cell agrees with values_at_points() at its vertices.
  const auto                  cell = tria.begin_active();
  PointValues                 at_vertices;
  const dealii::QTrapezoid<3> vertices;
  ep.evaluate(cell, vertices, at_vertices);
  std::vector<dealii::Point<3>> points;
  for (unsigned int v = 0; v < 8; ++v)
    points.push_back(cell->vertex(v));
  const auto global = ep.values_at_points(points);
  for (unsigned int q = 0; q < vertices.size(); ++q)
    CHECK(at_vertices.calcium_uM[q] ==
          Approx(global.calcium_uM[q]).epsilon(1e-12));

  // A model without calcium gives NaN.
  Monodomain phenomenological(cable_parameters(0.1),
                              tria,
                              mapping,
                              fibres,
                              names,
                              logger);
  CHECK(
    std::isnan(phenomenological.values_at_points(near_and_far).calcium_uM[0]));
}

TEST_CASE("A consistent mass conducts a ten Tusscher-Panfilov front closer "
          "to its converged speed on coarse cables than the lumped one",
          "[ep][monodomain]")
{
  // A cable of the Niederer et al. 2011 tissue (fibres along it, sigma_l =
  // 0.1334 mS/mm): the sharp ten Tusscher-Panfilov upstroke is not resolved
  // by cells of 0.5 mm, and a mass lumped at the nodes slows it
  // (Krishnamoorthi et al. 2013), more than the consistent mass does. The
  // reference is the speed both reach on cells of 1/40 mm.
  const std::vector<dealii::Point<3>> probes = {dealii::Point<3>(2, 0, 0),
                                                dealii::Point<3>(5, 0, 0)};
  Parameters p = Parameters::defaults("ten Tusscher-Panfilov");
  p.stimuli    = parse_stimuli("left: box 0 0 0 0.5 1 1 from 0 for 2 at 50");
  p.time_step  = 0.02;
  p.linear_tolerance = 1e-10;
  const auto speed   = [&](const bool consistent, const unsigned int cells) {
    p.consistent_mass = consistent;
    const auto r =
      run_ep_box(p, cable(6, cells, 0), 15, 5, probes, MPI_COMM_SELF);
    return 3.0 / (r.probes.activation_time[1] - r.probes.activation_time[0]);
  };
  const double       reference_lumped = speed(false, 240);
  const double       reference        = speed(true, 240);
  std::ostringstream table;
  table << "h = 0.025 mm: CV lumped " << reference_lumped << ", consistent "
        << reference << " mm/ms; ";
  std::vector<double> lumped, consistent;
  for (const unsigned int cells : {12u, 24u, 60u})
    {
      lumped.push_back(speed(false, cells) / reference - 1);
      consistent.push_back(speed(true, cells) / reference - 1);
      table << "h = " << 6.0 / cells << " mm: CV/CV_ref - 1 lumped "
            << lumped.back() << ", consistent " << consistent.back() << "; ";
    }
  INFO(table.str());
  CHECK(std::abs(reference_lumped / reference - 1) < 0.01);
  for (unsigned int i = 0; i < 3; ++i)
    CHECK(std::abs(consistent[i]) < std::abs(lumped[i]));
}

TEST_CASE("On tetrahedra (P1) the front speed converges under refinement",
          "[ep][monodomain][tetrahedra]")
{
  // The cable of the test above split into tetrahedra (24 per cell, P1 with
  // the vertex-lumped mass), cells of 0.5, 0.25 and 0.125 mm along it,
  // against Q1 hexahedra of 1/32 mm (the reference) and of the same cells.
  const std::vector<dealii::Point<3>> probes = {dealii::Point<3>(2, 0, 0),
                                                dealii::Point<3>(5, 0, 0)};
  const Parameters                    p      = cable_parameters(0.1);
  const auto velocity = [&](const unsigned int cells, const bool tets) {
    EPBox box      = cable(8, cells, 0);
    box.tetrahedra = tets;
    const auto r   = run_ep_box(p, box, 60, 10, probes, MPI_COMM_SELF);
    return 3.0 / (r.probes.activation_time[1] - r.probes.activation_time[0]);
  };
  const double        reference = velocity(256, false);
  std::vector<double> tet_error, hex_error;
  for (const unsigned int cells : {16u, 32u, 64u})
    {
      tet_error.push_back(velocity(cells, true) / reference - 1);
      hex_error.push_back(velocity(cells, false) / reference - 1);
    }
  INFO("CV " << reference << " mm/ms (Q1, h = 1/32 mm); relative errors at "
             << "h = 0.5, 0.25, 0.125 mm: P1 tetrahedra " << tet_error[0]
             << ", " << tet_error[1] << ", " << tet_error[2]
             << "; Q1 hexahedra " << hex_error[0] << ", " << hex_error[1]
             << ", " << hex_error[2]);
  // Measured: -1.25, -0.60, -0.22 % (tetrahedra), -2.81, -1.19, -0.51 %
  // (hexahedra): both slower than the reference, the error shrinking with
  // h; the split cells, with their face and centre nodes, about half the
  // hexahedra's error.
  CHECK(std::abs(tet_error[1]) < 0.6 * std::abs(tet_error[0]));
  CHECK(std::abs(tet_error[2]) < 0.6 * std::abs(tet_error[1]));
  CHECK(std::abs(tet_error[2]) < 0.004);
  for (unsigned int k = 0; k < 3; ++k)
    CHECK(std::abs(tet_error[k]) < std::abs(hex_error[k]));
}

TEST_CASE("The monodomain refuses P2 on tetrahedra",
          "[ep][monodomain][tetrahedra]")
{
  Parameters p   = cable_parameters(0.1);
  p.degree       = 2;
  EPBox box      = cable(2, 4, 0);
  box.tetrahedra = true;
  CHECK_THROWS_WITH(run_ep_box(p, box, 1, 1, {}, MPI_COMM_SELF),
                    Catch::Contains("Electrophysiology / Polynomial degree = "
                                    "2 needs hexahedra"));
}
