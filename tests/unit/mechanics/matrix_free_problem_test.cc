// The mechanics' own matrix-free tangent (Problem::matrix_free_tangent(),
// issue 40) against the Problem's assembled tangent.
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/problem.h"
#include "mechanics/problem_checks.h"
#include "support/matrix_free_problem.h"
#include "support/mechanics_fixture.h"

#include <catch2/catch.hpp>

TEST_CASE("The mechanics' matrix-free tangent is its assembled tangent: Land "
          "ventricle, Q2, Guccione with rule-based fibres, Simo-Taylor "
          "penalty, uniform and per-point active tension",
          "[mechanics][matrix-free]")
{
  const auto d = test_support::matrix_free_problem_differences(MPI_COMM_WORLD);
  INFO("cached " << d.cached << ", single " << d.single << ", other tension "
                 << d.other_tension << ", stale " << d.stale << ", updated "
                 << d.updated << ", pressure " << d.pressure
                 << ", pressure left out " << d.pressure_left_out);
  CHECK(d.cached < 1e-10);
  CHECK(d.updated < 1e-10);
  // The follower pressure's face term (FEFaceEvaluation) is the assembly's.
  CHECK(d.pressure < 1e-10);
  CHECK(d.pressure_left_out > 1e-4);
  // Single precision: about 1e-7 relative.
  CHECK(d.single < 1e-5);
  CHECK(d.single > 1e-10);
  // What the check tells apart: the active stress (10 kPa of the uniform
  // tension left out) and a tangent of another displacement.
  CHECK(d.other_tension > 1e-3);
  CHECK(d.stale > 1e-3);
}

TEST_CASE("The mechanics' matrix-free tangent refuses mixed, reduced, Q1",
          "[mechanics][matrix-free]")
{
  using systole::Mechanics::Incompressibility;
  using systole::Mechanics::ProblemChecks;
  {
    test_support::VentricleMechanics v;
    v.params.incompressibility = Incompressibility::nearly_incompressible;
    CHECK_THROWS_WITH(ProblemChecks::matrix_free_tangent(*v.problem(2), 10.0),
                      Catch::Contains("needs the penalty formulation"));
  }
  {
    test_support::VentricleMechanics v;
    v.params.reduced_volumetric_integration = true;
    CHECK_THROWS_WITH(ProblemChecks::matrix_free_tangent(*v.problem(2), 10.0),
                      Catch::Contains("full volumetric rule"));
  }
  {
    test_support::VentricleMechanics v;
    const auto                       problem = v.problem(2);
    CHECK_NOTHROW(ProblemChecks::matrix_free_tangent(*problem, 10.0));
    CHECK_THROWS_WITH(ProblemChecks::matrix_free_tangent(*v.problem(1), 10.0),
                      Catch::Contains("needs the penalty formulation on Q2"));
  }
}
