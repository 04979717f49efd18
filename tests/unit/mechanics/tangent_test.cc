#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>

#include "base/logger.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "materials/guccione.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem.h"
#include "mechanics/problem_checks.h"
#include "support/law_parameters.h"
#include "support/mechanics_fixture.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <sstream>

using namespace systole;

namespace
{
  /// The three formulations (the checks that run on all of them).
  constexpr std::array<Mechanics::Incompressibility, 3> all_formulations{
    {Mechanics::Incompressibility::penalty,
     Mechanics::Incompressibility::nearly_incompressible,
     Mechanics::Incompressibility::incompressible}};

  /// A smooth displacement of moderate size (strains of about 10 %).
  class Wobble : public dealii::Function<3>
  {
  public:
    explicit Wobble(const double size)
      : dealii::Function<3>(3)
      , size(size)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return size * std::sin(0.3 * p[0] + 0.2 * c) *
             std::cos(0.25 * p[1] - 0.1 * p[2] + c);
    }

  private:
    double size;
  };

  /// Observed order of the tangent's central-difference error between h and
  /// h/2 (2 for a consistent tangent).
  double
  observed_order(Mechanics::Problem &problem,
                 const double        pressure,
                 const double        tension,
                 const double        h)
  {
    const double e1 = systole::Mechanics::ProblemChecks::tangent_error(problem,
                                                                       pressure,
                                                                       tension,
                                                                       h);
    const double e2 = systole::Mechanics::ProblemChecks::tangent_error(problem,
                                                                       pressure,
                                                                       tension,
                                                                       h / 2);
    INFO("tangent error " << e1 << " at h, " << e2 << " at h/2");
    CHECK(e2 < 1e-5);
    return std::log2(e1 / e2);
  }
} // namespace

TEST_CASE("The mechanics tangent is the derivative of the residual",
          "[mechanics][fd]")
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
  // A rotating frame, so that the anisotropy is not aligned with the mesh.
  const Fibres::FibreField fibres = test_support::rotating_fibres();

  SECTION("Land ventricle, Q2, follower pressure on the endocardium, active "
          "tension, Robin springs on the epicardium")
  {
    Geometry::Parameters geometry; // the Land ventricle
    dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
    const auto            names = Geometry::create_mesh(geometry, tria);
    Mechanics::Parameters params;
    params.fixed_boundaries  = {"base"};
    params.pressure_boundary = "endocardium";
    params.robin_boundaries  = {"epicardium"};
    params.robin_stiffness   = 0.5;
    params.linear_solver     = "direct";
    Mechanics::Problem problem(
      {params, tria, names, 2, 2, law, volumetric, fibres, logger});
    problem.set_displacement(Wobble(0.8));
    CHECK(observed_order(problem, 3.0, 20.0, 1e-3) == Approx(2.0).margin(0.2));
  }

  SECTION("Land ventricle, Q2 (penalty) and Q2-P1disc (nearly incompressible, "
          "incompressible), follower pressure, active tension: the products "
          "of the matrix-free back ends")
  {
    Geometry::Parameters geometry; // the Land ventricle
    dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
    const auto names = Geometry::create_mesh(geometry, tria);
    for (const auto incompressibility : all_formulations)
      {
        Mechanics::Parameters params;
        params.incompressibility = incompressibility;
        params.fixed_boundaries  = {"base"};
        params.pressure_boundary = "endocardium";
        params.linear_solver     = "matrix-free";
        Mechanics::Problem problem(
          {params, tria, names, 2, 2, law, volumetric, fibres, logger});
        problem.set_displacement(Wobble(0.8));
        if (params.mixed())
          systole::Mechanics::ProblemChecks::set_pressure_field(problem, 2.0);
        INFO(problem.discretization_name()
             << ", " << problem.linear_solver_name());
        CHECK_THAT(problem.linear_solver_name(),
                   Catch::Contains("matrix-free"));
        CHECK(observed_order(problem, 3.0, 20.0, 1e-3) ==
              Approx(2.0).margin(0.2));
      }
  }

  SECTION("Land ventricle split into tetrahedra, P2 (penalty) and P2-P1 "
          "(Taylor-Hood, incompressible), follower pressure, active tension, "
          "Robin springs")
  {
    Geometry::Parameters geometry; // the Land ventricle, 8 x 3 hexahedra
    geometry.lv_cells.circumferential = 8;
    geometry.lv_cells.longitudinal    = 3;
    geometry.tetrahedra               = true;
    const auto mesh =
      Geometry::create_distributed_mesh(geometry, MPI_COMM_WORLD);
    for (const auto incompressibility :
         {Mechanics::Incompressibility::penalty,
          Mechanics::Incompressibility::incompressible})
      {
        Mechanics::Parameters params;
        params.incompressibility = incompressibility;
        params.pressure_element  = Mechanics::PressureElement::continuous;
        params.fixed_boundaries  = {"base"};
        params.pressure_boundary = "endocardium";
        params.robin_boundaries  = {"epicardium"};
        params.robin_stiffness   = 0.5;
        params.linear_solver     = "direct";
        Mechanics::Problem problem({params,
                                    *mesh.tria,
                                    mesh.names,
                                    2,
                                    1,
                                    law,
                                    volumetric,
                                    fibres,
                                    logger});
        REQUIRE(problem.cell_kind().simplex());
        // Smaller than on hexahedra: the split cells near the apex are small.
        problem.set_displacement(Wobble(0.2));
        if (params.mixed())
          systole::Mechanics::ProblemChecks::set_pressure_field(problem, 2.0);
        INFO(problem.discretization_name());
        CHECK(observed_order(problem, 3.0, 20.0, 1e-4) ==
              Approx(2.0).margin(0.2));
      }
  }

  SECTION("Beam, Q1 (penalty) and Q1-P0 (mixed, incompressible), follower "
          "pressure on a free face, sliding face, Robin springs")
  {
    Geometry::Parameters geometry;
    geometry.type      = Geometry::Parameters::Type::box;
    geometry.box_upper = dealii::Point<3>(10, 1, 1);
    geometry.box_cells = {{5, 2, 2}};
    dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
    const auto names = Geometry::create_mesh(geometry, tria);
    for (const auto incompressibility :
         {Mechanics::Incompressibility::penalty,
          Mechanics::Incompressibility::incompressible})
      {
        Mechanics::Parameters params;
        params.incompressibility  = incompressibility;
        params.fixed_boundaries   = {"x_min"};
        params.sliding_boundaries = {"y_min"};
        params.pressure_boundary  = "z_min";
        params.robin_boundaries   = {"x_max"};
        params.robin_stiffness    = 0.2;
        params.robin_normal_only  = false;
        params.linear_solver      = "direct";
        Mechanics::Problem problem(
          {params, tria, names, 1, 1, law, volumetric, fibres, logger});
        problem.set_displacement(Wobble(0.5));
        if (params.mixed())
          systole::Mechanics::ProblemChecks::set_pressure_field(problem, 2.0);
        INFO(problem.discretization_name());
        CHECK(observed_order(problem, 0.5, 5.0, 1e-3) ==
              Approx(2.0).margin(0.2));
      }
  }

  SECTION("Land ventricle, mixed Q2-P1disc and Q2-Q1, nearly incompressible "
          "and incompressible, with a pressure field, follower pressure, "
          "active tension and Robin springs; Q2-P1disc also with the "
          "iterative solver, whose augmented Lagrangian assembles T K (the "
          "check undoes T with the assembled G)")
  {
    Geometry::Parameters geometry; // the Land ventricle
    dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
    const auto names = Geometry::create_mesh(geometry, tria);
    struct Configuration
    {
      Mechanics::PressureElement element;
      const char                *linear_solver;
      double                     augmented_lagrangian;
    };
    for (const Configuration &c :
         {Configuration{Mechanics::PressureElement::discontinuous, "direct", 0},
          Configuration{Mechanics::PressureElement::continuous, "direct", 0},
          Configuration{Mechanics::PressureElement::discontinuous,
                        "iterative",
                        3.0}})
      for (const auto incompressibility :
           {Mechanics::Incompressibility::nearly_incompressible,
            Mechanics::Incompressibility::incompressible})
        {
          Mechanics::Parameters params;
          params.incompressibility    = incompressibility;
          params.pressure_element     = c.element;
          params.fixed_boundaries     = {"base"};
          params.pressure_boundary    = "endocardium";
          params.robin_boundaries     = {"epicardium"};
          params.robin_stiffness      = 0.5;
          params.linear_solver        = c.linear_solver;
          params.augmented_lagrangian = c.augmented_lagrangian;
          Mechanics::Problem problem(
            {params, tria, names, 2, 2, law, volumetric, fibres, logger});
          problem.set_displacement(Wobble(0.8));
          systole::Mechanics::ProblemChecks::set_pressure_field(problem, 4.0);
          INFO(problem.discretization_name() << ", " << c.linear_solver);
          CHECK(observed_order(problem, 3.0, 20.0, 1e-3) ==
                Approx(2.0).margin(0.2));
        }
  }
}


TEST_CASE("The mechanics tangent is the derivative of the residual with "
          "every passive law in every formulation",
          "[mechanics][fd]")
{
  // The laws of the factory table (test_support::passive_law_cases()) on
  // the beam with Q1 displacements: penalty, and Q1-P0 nearly
  // incompressible and incompressible (the mixed ones evaluate the
  // isochoric part of the law), with a pressure field, follower pressure,
  // active tension, a sliding face and Robin springs.
  std::ostringstream             sink;
  Logger                         logger(MPI_COMM_WORLD, sink);
  const Materials::VolumetricLaw volumetric(
    Materials::VolumetricLaw::Form::simo_taylor,
    100.0);
  const Fibres::FibreField fibres = test_support::rotating_fibres();
  Geometry::Parameters     geometry;
  geometry.type      = Geometry::Parameters::Type::box;
  geometry.box_upper = dealii::Point<3>(10, 1, 1);
  geometry.box_cells = {{5, 2, 2}};
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto names = Geometry::create_mesh(geometry, tria);

  for (const test_support::LawCase &c : test_support::passive_law_cases())
    DYNAMIC_SECTION(c.label)
    {
      // A tension switch blends over I4 - 1 in [0, 0.01]: its higher
      // derivatives (~ width^-3) make the truncation error large unless the
      // step is small (the observed order is 2 either way). The logistic
      // switch is smooth everywhere but as steep (k^3).
      const bool steep = !c.tension_switches.empty() ||
                         c.label.find("logistic") != std::string::npos;
      const double h = steep ? 1e-4 : 1e-3;
      for (const auto incompressibility : all_formulations)
        {
          Mechanics::Parameters params;
          params.incompressibility  = incompressibility;
          params.fixed_boundaries   = {"x_min"};
          params.sliding_boundaries = {"y_min"};
          params.pressure_boundary  = "z_min";
          params.robin_boundaries   = {"x_max"};
          params.robin_stiffness    = 0.2;
          params.robin_normal_only  = false;
          params.linear_solver      = "direct";
          Mechanics::Problem problem(
            {params, tria, names, 1, 1, *c.law, volumetric, fibres, logger});
          problem.set_displacement(Wobble(0.3));
          if (params.mixed())
            systole::Mechanics::ProblemChecks::set_pressure_field(problem, 2.0);
          INFO(problem.discretization_name());
          CHECK(observed_order(problem, 0.5, 5.0, h) ==
                Approx(2.0).margin(0.2));
        }
    }
}
