// The mechanics coupled two-way with the Land tension model: the tangent
// with dT/dlambda against central differences of the residual, and the
// accepted states against the model stepped point by point.
#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>

#include "base/logger.h"
#include "geometry/mesh.h"
#include "materials/guccione.h"
#include "materials/land.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem.h"
#include "mechanics/problem_checks.h"
#include "support/mechanics_fixture.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <sstream>

using namespace systole;

namespace
{
  /// A smooth displacement with fibre stretches of a few per cent.
  class Stretching : public dealii::Function<3>
  {
  public:
    explicit Stretching(const double size)
      : dealii::Function<3>(3)
      , size(size)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return size * (std::sin(0.3 * p[0] + 0.2 * c) *
                       std::cos(0.25 * p[1] - 0.1 * p[2] + c) +
                     (c == 0 ? 0.05 * p[0] : 0.0));
    }

  private:
    double size;
  };

  /// u = (lambda - 1) x e_x: fibre stretch lambda along x.
  class Uniaxial : public dealii::Function<3>
  {
  public:
    explicit Uniaxial(const double lambda)
      : dealii::Function<3>(3)
      , lambda(lambda)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return c == 0 ? (lambda - 1) * p[0] : 0.0;
    }

  private:
    double lambda;
  };

  /// test_support::Wobble scaled by @p scale plus a uniform dilation u =
  /// epsilon X.
  class DilatedWobble : public dealii::Function<3>
  {
  public:
    DilatedWobble(const double scale, const double epsilon)
      : dealii::Function<3>(3)
      , scale(scale)
      , epsilon(epsilon)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return scale * wobble.value(p, c) + epsilon * p[c];
    }

  private:
    test_support::Wobble wobble;
    double               scale, epsilon;
  };
} // namespace

TEST_CASE("The mechanics tangent with Land tension at a non-trivial state is "
          "the derivative of the residual",
          "[mechanics][fd][active]")
{
  std::ostringstream sink;
  Logger             logger(MPI_COMM_WORLD, sink);

  Materials::Guccione::Parameters guccione;
  guccione.C    = 2;
  guccione.b_f  = 8;
  guccione.b_t  = 2;
  guccione.b_fs = 4;
  const Materials::Guccione      law(guccione);
  const Materials::VolumetricLaw volumetric(
    Materials::VolumetricLaw::Form::simo_taylor,
    100.0);
  const Fibres::FibreField fibres = test_support::rotating_fibres();
  const Materials::Land    land(Materials::Land::Parameters{});

  Geometry::Parameters geometry;
  geometry.type      = Geometry::Parameters::Type::box;
  geometry.box_upper = dealii::Point<3>(10, 1, 1);
  geometry.box_cells = {{5, 2, 2}};
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto names = Geometry::create_mesh(geometry, tria);

  // Without and with a cross-fibre part (its tangent is not symmetric).
  for (const Materials::CrossFibreFractions cross :
       {Materials::CrossFibreFractions{0.0, 0.0},
        Materials::CrossFibreFractions{0.4, 0.2}})
    for (const auto incompressibility :
         {Mechanics::Incompressibility::penalty,
          Mechanics::Incompressibility::incompressible})
      {
        Mechanics::Parameters params;
        params.incompressibility  = incompressibility;
        params.fixed_boundaries   = {"x_min"};
        params.pressure_boundary  = "z_min";
        params.robin_boundaries   = {"x_max"};
        params.robin_stiffness    = 0.2;
        params.linear_solver      = "direct";
        params.active_cross_fibre = cross;
        Mechanics::Problem problem(
          {params, tria, names, 1, 1, law, volumetric, fibres, logger});
        INFO(problem.discretization_name()
             << ", cross-fibre fractions " << cross.sheet << ", "
             << cross.normal);
        problem.set_tension_model(&land);
        // 60 ms of activation (steps of 2 ms, calcium 1 µM) at a first
        // deformation; then one step to a second one (the stretch rate
        // distorts the cross-bridges).
        problem.set_displacement(Stretching(0.25));
        problem.set_calcium(1.0);
        for (unsigned int k = 1; k <= 30; ++k)
          {
            problem.set_tension_step(2.0 * k, 2.0);
            problem.accept_tension_step();
          }
        problem.set_displacement(Stretching(0.3));
        problem.set_tension_step(62.0, 2.0);
        if (params.mixed())
          systole::Mechanics::ProblemChecks::set_pressure_field(problem, 2.0);

        // The model's tension is non-trivial and varies between points.
        const auto   tensions = problem.model_tensions();
        double       low = 1e9, high = -1e9;
        unsigned int n = 0;
        for (const auto &cell : tensions)
          for (const double t : cell)
            {
              low  = std::min(low, t);
              high = std::max(high, t);
              ++n;
            }
        INFO("Land tensions " << low << " to " << high << " kPa at " << n
                              << " points");
        CHECK(n > 0);
        CHECK(high > 10.0);
        CHECK(high - low > 1.0);

        const double e1 =
          systole::Mechanics::ProblemChecks::tangent_error(problem,
                                                           0.5,
                                                           0.0,
                                                           1e-3);
        const double e2 =
          systole::Mechanics::ProblemChecks::tangent_error(problem,
                                                           0.5,
                                                           0.0,
                                                           5e-4);
        INFO("tangent error " << e1 << " at h, " << e2 << " at h/2");
        CHECK(e2 < 1e-5);
        CHECK(std::log2(e1 / e2) == Approx(2.0).margin(0.2));
      }
}

TEST_CASE("Accepted Land states in the mechanics equal the model stepped at "
          "the points' stretch",
          "[mechanics][active]")
{
  // Uniaxial fibre stretch lambda along x (fibres along x): every point
  // must hold the state of one Land cell stepped at that stretch.
  std::ostringstream              sink;
  Logger                          logger(MPI_COMM_WORLD, sink);
  Materials::Guccione::Parameters guccione;
  const Materials::Guccione       law(guccione);
  const Materials::VolumetricLaw  volumetric(
    Materials::VolumetricLaw::Form::simo_taylor,
    100.0);
  const Fibres::FibreField fibres =
    [](const auto &, const auto &points, auto &bases) {
      bases.assign(points.size(), Fibres::FibreBasis::cartesian());
    };
  const Materials::Land land(Materials::Land::Parameters{});
  Geometry::Parameters  geometry;
  geometry.type      = Geometry::Parameters::Type::box;
  geometry.box_upper = dealii::Point<3>(4, 1, 1);
  geometry.box_cells = {{2, 1, 1}};
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto            names = Geometry::create_mesh(geometry, tria);
  Mechanics::Parameters params;
  params.fixed_boundaries = {"x_min"};
  params.linear_solver    = "direct";
  Mechanics::Problem problem(
    {params, tria, names, 1, 1, law, volumetric, fibres, logger});
  problem.set_tension_model(&land);

  using State = std::array<double, Materials::Land::n_state_values>;
  State s, next;
  land.initial_state(s.data());
  double                   lambda_n = 1.0;
  Materials::TensionOutput out;
  for (unsigned int k = 1; k <= 40; ++k)
    {
      const double t      = 2.5 * k;
      const double lambda = 1.0 + 0.1 * std::sin(t / 40);
      problem.set_displacement(Uniaxial(lambda));
      const double ca = 0.2 + 0.8 * std::exp(-std::pow((t - 40) / 20, 2));
      problem.set_calcium(ca);
      problem.set_tension_step(t, 2.5);
      problem.accept_tension_step();
      Materials::TensionInput in;
      in.time             = t;
      in.time_step        = 2.5;
      in.calcium          = ca;
      in.stretch          = lambda;
      in.previous_stretch = lambda_n;
      land.step(s.data(), in, next.data(), out);
      s        = next;
      lambda_n = lambda;
    }
  // The next step's tension at every point (stretch unchanged).
  problem.set_tension_step(102.5, 2.5);
  Materials::TensionInput in;
  in.time_step = 2.5;
  in.calcium   = 0.6;
  problem.set_calcium(in.calcium);
  in.stretch          = lambda_n;
  in.previous_stretch = lambda_n;
  land.step(s.data(), in, next.data(), out);
  CHECK(out.tension > 1.0);
  for (const auto &cell : problem.model_tensions())
    for (const double t : cell)
      CHECK(t == Approx(out.tension).epsilon(1e-10));
}

TEST_CASE("The bordered Jacobian of the heartbeat with Land tension is the "
          "derivative of (R, V)",
          "[mechanics][fd][active]")
{
  // The heartbeat's system: the ventricle with its cavity volume as a
  // constraint (one cavity, or two), the Land states of 60 ms of activation
  // at a first deformation, then a step to a second one, so that the
  // tension, its stretch and its stretch-rate dependence all enter.
  const Materials::Land land(Materials::Land::Parameters{});
  for (const unsigned int n_cavities : {1u, 2u})
    {
      test_support::VentricleMechanics s;
      if (n_cavities == 2)
        s.use_two_cavities();
      const auto problem = s.problem();
      problem->set_tension_model(&land);
      // Fibre stretches within about 0.9 to 1.1: away from the kinks of
      // Land's length dependence at 0.87 and 1.2.
      problem->set_displacement(DilatedWobble(0.3, 0.0));
      problem->set_calcium(1.0);
      for (unsigned int k = 1; k <= 30; ++k)
        {
          problem->set_tension_step(2.0 * k, 2.0);
          problem->accept_tension_step();
        }
      // The next iterate stretches every fibre further (a uniform dilation
      // of 2 % more): the distortions ζ_s, ζ_w are positive
      // everywhere, away from the kinks of the model's |ζ_w| and max(ζ_s,
      // 0) (at a kink the derivative is one-sided, and a central
      // difference across it is only first order).
      problem->set_displacement(DilatedWobble(0.3, 0.02));
      problem->set_tension_step(62.0, 2.0);

      double high = 0;
      for (const auto &cell : problem->model_tensions())
        for (const double t : cell)
          high = std::max(high, t);
      INFO(n_cavities << " cavities; largest Land tension " << high << " kPa");
      CHECK(high > 10.0);

      dealii::Vector<double> pressures(n_cavities);
      pressures[0] = 2.0;
      if (n_cavities == 2)
        pressures[1] = 0.5;
      // (No uniform tension: the Land tension is the active one.)
      const auto e1 =
        systole::Mechanics::ProblemChecks::bordered_jacobian_error(*problem,
                                                                   pressures,
                                                                   0.0,
                                                                   5e-4);
      const auto e2 =
        systole::Mechanics::ProblemChecks::bordered_jacobian_error(*problem,
                                                                   pressures,
                                                                   0.0,
                                                                   2.5e-4);
      INFO("row errors at h: " << e1[0] << ", " << e1[1]
                               << "; at h/2: " << e2[0] << ", " << e2[1]);
      CHECK(e2[0] < 1e-6);
      CHECK(std::log2(e1[0] / e2[0]) == Approx(2.0).margin(0.2));
      CHECK(e2[1] < 1e-7);
    }
}
