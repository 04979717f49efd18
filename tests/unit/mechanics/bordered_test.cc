// The volume-constrained (bordered) mechanics: the Jacobian of the bordered
// system against finite differences, and the pressure-volume relation of a
// pressure-driven solve recovered by a volume-driven one.
#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>

#include "base/logger.h"
#include "geometry/mesh.h"
#include "materials/guccione.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

using namespace systole;

namespace
{
  class Wobble : public dealii::Function<3>
  {
  public:
    Wobble()
      : dealii::Function<3>(3)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return 0.6 * std::sin(0.3 * p[0] + 0.2 * c) *
             std::cos(0.25 * p[1] - 0.1 * p[2] + c);
    }
  };

  struct Setup
  {
    Setup()
      : logger(MPI_COMM_WORLD, sink)
      , law([] {
        Materials::Guccione::Parameters g;
        g.C    = 2;
        g.b_f  = 8;
        g.b_t  = 2;
        g.b_fs = 4;
        return g;
      }())
      , volumetric(Materials::VolumetricLaw::Form::simo_taylor, 100.0)
      , tria(MPI_COMM_WORLD)
    {
      names = Geometry::create_mesh(Geometry::Parameters(), tria);
      params.fixed_boundaries          = {"base"};
      params.pressure_boundary         = "endocardium";
      params.linear_solver             = "direct";
      params.newton_absolute_tolerance = 1e-10;
      fibres = [](const auto &, const auto &points, auto &bases) {
        bases.resize(points.size());
        for (unsigned int i = 0; i < points.size(); ++i)
          {
            const double a = 0.3 * points[i][2];
            bases[i].f = dealii::Tensor<1, 3>({std::cos(a), std::sin(a), 0});
            bases[i].s = dealii::Tensor<1, 3>({-std::sin(a), std::cos(a), 0});
            bases[i].n = dealii::Tensor<1, 3>({0, 0, 1});
          }
      };
    }

    std::ostringstream                              sink;
    Logger                                          logger;
    Materials::Guccione                             law;
    Materials::VolumetricLaw                        volumetric;
    dealii::parallel::distributed::Triangulation<3> tria;
    Geometry::BoundaryNames                         names;
    Mechanics::Parameters                           params;
    Fibres::FibreField                              fibres;
  };
} // namespace

TEST_CASE("The bordered Jacobian is the derivative of (R, V)",
          "[mechanics][fd]")
{
  Setup              s;
  Mechanics::Problem problem(s.params,
                             s.tria,
                             s.names,
                             2,
                             2,
                             s.law,
                             s.volumetric,
                             s.fibres,
                             s.logger);
  problem.set_displacement(Wobble());
  const auto e1 = problem.bordered_jacobian_error(2.0, 10.0, 1e-3);
  const auto e2 = problem.bordered_jacobian_error(2.0, 10.0, 5e-4);
  INFO("row errors at h: " << e1[0] << ", " << e1[1] << "; at h/2: " << e2[0]
                           << ", " << e2[1]);
  CHECK(e2[0] < 1e-6);
  CHECK(std::log2(e1[0] / e2[0]) == Approx(2.0).margin(0.2));
  // V is a cubic polynomial in u along a line: its central difference
  // matches b.d to round-off or with order 2.
  CHECK(e2[1] < 1e-7);
}

TEST_CASE("A volume-driven solve recovers the pressure of a pressure-driven "
          "one",
          "[mechanics]")
{
  Setup              s;
  Mechanics::Problem problem(s.params,
                             s.tria,
                             s.names,
                             2,
                             2,
                             s.law,
                             s.volumetric,
                             s.fibres,
                             s.logger);
  const double       V0 = problem.cavity_volume();

  // Pressure-driven: p = 1 kPa with a non-uniform active tension field.
  std::vector<std::vector<dealii::Point<3>>> points;
  problem.quadrature_points(points);
  std::vector<std::vector<double>> tension(points.size());
  for (unsigned int c = 0; c < points.size(); ++c)
    for (const auto &X : points[c])
      tension[c].push_back(5.0 + 0.2 * X[2]);
  problem.set_active_tension(tension);
  problem.solve(1.0, 0.0);
  const double V1 = problem.cavity_volume();
  REQUIRE(std::abs(V1 - V0) > 1e-3 * V0);
  problem.save();

  // Back to the reference state, then volume-driven to V1.
  problem.set_displacement(dealii::Functions::ZeroFunction<3>(3));
  double     p      = 0;
  const auto report = problem.solve_volume(V1, 0.0, p);
  INFO("Newton iterations " << report.iterations << ", p = " << p);
  CHECK(p == Approx(1.0).epsilon(1e-7));
  CHECK(std::abs(problem.cavity_volume() - V1) <= 2e-9 * V1);
  CHECK(report.iterations <= 8);

  // A nearby target: chord iterations on the factorization of the last
  // solve, no new tangent; the result is the same equilibrium as a
  // pressure-driven solve at the pressure found.
  const double V2    = V1 * 1.002;
  const auto   chord = problem.solve_volume(V2, 0.0, p);
  INFO("chord: " << chord.reused_iterations << " reused, " << chord.iterations
                 << " new-tangent iterations");
  INFO(s.sink.str().substr(
    s.sink.str().size() > 3000 ? s.sink.str().size() - 3000 : 0));
  CHECK(chord.reused_iterations > 0);
  CHECK(chord.iterations == 0);
  CHECK(std::abs(problem.cavity_volume() - V2) <= 2e-9 * V2);
  const double p2 = p;
  problem.solve(p2, 0.0);
  CHECK(problem.cavity_volume() == Approx(V2).epsilon(1e-7));
}
