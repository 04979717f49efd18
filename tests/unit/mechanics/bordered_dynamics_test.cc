// The volume-constrained (bordered) solves inside a generalized-alpha step
// (inertia, Rayleigh damping, Kelvin-Voigt viscosity, a spring-dashpot
// epicardium): the bordered Jacobian of a dynamic step against central
// differences (order 2), and a volume-driven dynamic step against the
// pressure-driven dynamic step at the pressure it found (an independent code
// path: the unbordered Newton), from an accepted state that moves.
#include <deal.II/base/function.h>

#include "mechanics/problem_checks.h"
#include "support/mechanics_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole;

namespace
{
  using Setup = test_support::VentricleMechanics;
  using test_support::Wobble;

  /// The ventricle of the bordered tests with inertia and damping.
  void
  make_dynamic(Setup &s)
  {
    s.params.density               = 1.0;  // mg/mm^3 (1000 kg/m^3)
    s.params.spectral_radius       = 0.8;  // -
    s.params.rayleigh_mass_damping = 0.01; // 1/ms
    s.params.viscosity             = 0.5;  // kPa ms
    s.params.robin_supports        = {{"epicardium", 0.5, 0.5, true}};
  }
} // namespace

TEST_CASE("The bordered Jacobian of a dynamic step is the derivative of "
          "(R, V)",
          "[mechanics][dynamics][fd]")
{
  Setup s;
  make_dynamic(s);
  auto         problem = s.problem();
  const double V0      = problem->cavity_volume();
  problem->start_dynamics(0.0, 0.0);
  problem->set_time_step(2.0);
  double p = 0;
  for (const unsigned int i : {1u, 2u})
    {
      problem->solve_volume(V0 * (1.0 + 0.05 * i), 4.0 * i, p);
      problem->accept_time_step(p, 4.0 * i);
    }
  // Moving, at an iterate away from the next step's solution.
  REQUIRE(problem->kinetic_energy() > 0.0);
  problem->set_displacement(Wobble());
  const auto e1 =
    systole::Mechanics::ProblemChecks::bordered_jacobian_error(*problem,
                                                               p,
                                                               10.0,
                                                               1e-3);
  const auto e2 =
    systole::Mechanics::ProblemChecks::bordered_jacobian_error(*problem,
                                                               p,
                                                               10.0,
                                                               5e-4);
  INFO("row errors at h: " << e1[0] << ", " << e1[1] << "; at h/2: " << e2[0]
                           << ", " << e2[1]);
  CHECK(e2[0] < 1e-6);
  CHECK(std::log2(e1[0] / e2[0]) == Approx(2.0).margin(0.2));
  CHECK(e2[1] < 1e-7);
}

TEST_CASE("A volume-driven dynamic step equals the pressure-driven dynamic "
          "step at its pressure",
          "[mechanics][dynamics]")
{
  Setup s;
  make_dynamic(s);
  auto         problem = s.problem();
  const double V0      = problem->cavity_volume();
  const double dt      = 2.0; // ms

  // The quasi-static pressure of the first target (for comparison).
  double p_static = 0;
  problem->solve_volume(1.05 * V0, 4.0, p_static);
  problem->set_displacement(dealii::Functions::ZeroFunction<3>(3));

  problem->start_dynamics(0.0, 0.0);
  problem->set_time_step(dt);
  double     p  = 0;
  const auto r1 = problem->solve_volume(1.05 * V0, 4.0, p);
  INFO("step 1: " << r1.iterations << " Newton + " << r1.reused_iterations
                  << " chord iterations, p = " << p << " kPa (quasi-static "
                  << p_static << " kPa)");
  // (Factorizations and chord iterations apart: the modified Newton trades
  // tangents for chords while they contract; measured 2 + 9.)
  CHECK(r1.iterations <= 4);
  CHECK(r1.reused_iterations <= 12);
  // The inertia of a 1.05 V0 filling in 2 ms is not small.
  CHECK(std::abs(p - p_static) > 1e-2 * std::abs(p_static));
  problem->accept_time_step(p, 4.0);
  problem->save();

  // Step 2 from a moving state: volume-driven, then pressure-driven at the
  // pressure found from the same accepted state (and the same start).
  const double V2 = 1.08 * V0;
  const auto   r2 = problem->solve_volume(V2, 6.0, p);
  INFO("step 2: " << r2.iterations << " Newton + " << r2.reused_iterations
                  << " chord iterations, p = " << p << " kPa");
  CHECK(r2.iterations <= 4);
  CHECK(r2.reused_iterations <= 12);
  CHECK(std::abs(problem->cavity_volume() - V2) <= 2e-9 * V2);
  problem->restore();
  problem->solve(p, 6.0);
  CHECK(problem->cavity_volume() == Approx(V2).epsilon(1e-7));
}
