// The volume-constrained (bordered) mechanics: the Jacobian of the bordered
// system against finite differences, and the pressure-volume relation of a
// pressure-driven solve recovered by a volume-driven one.
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

  /// The bordered Jacobian of @p s's problem (Q2) at the wobbled state,
  /// 2 kPa, 10 kPa of active tension, against central differences at h and
  /// h/2: the first row falls like h^2 to below 1e-6, the volume row (V is
  /// a cubic in u along a line) matches to 1e-7.
  void
  check_bordered_jacobian(Setup &s)
  {
    const auto problem = s.problem();
    problem->set_displacement(Wobble());
    const auto e1 =
      systole::Mechanics::ProblemChecks::bordered_jacobian_error(*problem,
                                                                 2.0,
                                                                 10.0,
                                                                 1e-3);
    const auto e2 =
      systole::Mechanics::ProblemChecks::bordered_jacobian_error(*problem,
                                                                 2.0,
                                                                 10.0,
                                                                 5e-4);
    INFO("row errors at h: " << e1[0] << ", " << e1[1] << "; at h/2: " << e2[0]
                             << ", " << e2[1]);
    CHECK(e2[0] < 1e-6);
    CHECK(std::log2(e1[0] / e2[0]) == Approx(2.0).margin(0.2));
    CHECK(e2[1] < 1e-7);
  }
} // namespace

TEST_CASE("The bordered Jacobian is the derivative of (R, V)",
          "[mechanics][fd]")
{
  Setup s;
  check_bordered_jacobian(s);
}

TEST_CASE("With a base on springs the volume row is the derivative of the "
          "moving-lid volume",
          "[mechanics][fd]")
{
  // The base held by springs and a tapered pericardium: the rim moves, the
  // cavity is closed by the fan over it, and dV/du has the lid's flux (the
  // endocardial flux alone misses it: the volume row would be off by the
  // lid area times the rim's motion).
  Setup s;
  s.params.fixed_boundaries = {};
  s.params.robin_supports   = Mechanics::Parameters::parse_robin_supports(
    "base: full, 0.5, 0; epicardium: normal, 0.2, 0, taper 0.4 0");
  check_bordered_jacobian(s);
  CHECK(s.sink.str().find("closed by the fan") != std::string::npos);
}

TEST_CASE("With the pressure on the moving lid the bordered Jacobian is the "
          "derivative of (R, V)",
          "[mechanics][fd]")
{
  // The load p dV/du of the closed cavity: its tangent is the fan's face
  // Hessian plus the rank-6 coupling of the rim to the wall (low_rank_u/v,
  // applied by tangent_vmult and by Woodbury in the solves).
  Setup s;
  s.params.fixed_boundaries = {};
  s.params.lid_pressure     = true;
  s.params.robin_supports   = Mechanics::Parameters::parse_robin_supports(
    "base: full, 0.5, 0; epicardium: normal, 0.2, 0, taper 0.4 0");
  check_bordered_jacobian(s);
}

TEST_CASE("With the pressure on the moving lid the cavity exerts no net "
          "force",
          "[mechanics]")
{
  // A base on springs: on the endocardium alone the pressure pushes the
  // ventricle toward its apex by about p times the lid's area; with the lid
  // loaded (its force on the rim) the closed cavity's load is p dV/du, whose
  // sum over the nodes is p dV/du along a translation: zero.
  Setup s;
  s.params.fixed_boundaries = {};
  s.params.robin_supports   = Mechanics::Parameters::parse_robin_supports(
    "base: tangential, 1, 0; epicardium: normal, 5, 0");
  dealii::Vector<double> pressures(1);
  pressures[0] = 2.0; // kPa
  double open  = 0.0;
  for (const bool lid : {false, true})
    {
      s.params.lid_pressure = lid;
      const auto problem    = s.problem();
      problem->set_displacement(Wobble());
      const dealii::Tensor<1, 3> force = problem->net_pressure_force(pressures);
      INFO("lid pressure " << lid << ": net force " << force << " mN");
      if (!lid)
        {
          // The Land ventricle's lid: radius 7 mm at z = 5, deformed a
          // little: -p pi 7^2 along z, within 20 %.
          open = force.norm();
          CHECK(force[2] == Approx(-2.0 * M_PI * 49.0).epsilon(0.2));
        }
      else
        CHECK(force.norm() < 1e-10 * open);
    }
}

TEST_CASE("A volume-driven solve recovers the pressure of a pressure-driven "
          "one",
          "[mechanics]")
{
  Setup              s;
  Mechanics::Problem problem(
    {s.params, s.tria, s.names, 2, 2, s.law, s.volumetric, s.fibres, s.logger});
  const double V0 = problem.cavity_volume();

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

namespace
{
  /// u = (0, 0, -a z): the ventricle (base at z = 0, apex below) shortened
  /// along its axis by the fraction a, the base in place.
  class AxialShortening : public dealii::Function<3>
  {
  public:
    explicit AxialShortening(const double a)
      : dealii::Function<3>(3)
      , a(a)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return c == 2 ? -a * p[2] : 0.0;
    }

  private:
    const double a;
  };

  /// @p s's problem after two accepted states, at 0.5 and 1 kPa (the
  /// history a solve of the heartbeat starts from).
  auto
  two_accepted_states(Setup &s)
  {
    auto problem = s.problem();
    problem->solve(0.5, 0.0);
    problem->save();
    problem->solve(1.0, 0.0);
    problem->save();
    return problem;
  }
} // namespace

TEST_CASE("A volume-constrained solve that starts where the tangent is "
          "indefinite restarts from the last accepted state",
          "[mechanics][newton]")
{
  // Two accepted states (0.5 and 1 kPa), then a start far from equilibrium
  // (the wall shortened along the axis by 30 %: compressed, its tangent has
  // negative pivots) and a volume target near the last state. The solve
  // must say that it restarts, and end at the equilibrium that the solve
  // from the accepted state reaches.
  const double a          = 0.3;
  double       p_accepted = 1.0, p_restarted = 1.0;
  double       V_target = 0;
  std::string  log;
  for (const bool from_bad_start : {false, true})
    {
      Setup      s;
      const auto problem = two_accepted_states(s);
      V_target           = 1.01 * problem->cavity_volume();
      if (from_bad_start)
        problem->set_displacement(AxialShortening(a));
      double    &p      = from_bad_start ? p_restarted : p_accepted;
      const auto report = problem->solve_volume(V_target, 0.0, p);
      INFO((from_bad_start ? "from the shortened wall" : "from the accepted")
           << ": " << report.iterations << " Newton iterations, p = " << p);
      CHECK(problem->cavity_volume() == Approx(V_target).epsilon(1e-8));
      if (from_bad_start)
        log = s.sink.str();
    }
  INFO(log.substr(log.size() > 4000 ? log.size() - 4000 : 0));
  CHECK(log.find("negative pivot(s): Newton from the last accepted state") !=
        std::string::npos);
  CHECK(p_restarted == Approx(p_accepted).epsilon(1e-8));
}

TEST_CASE("A volume-constrained solve backs off from an iterate whose "
          "tangent is indefinite",
          "[mechanics][newton]")
{
  // Two accepted states (0.5 and 1 kPa), then a volume 60 % larger in one
  // solve: the first Newton update overshoots to an iterate whose tangent
  // has negative pivots. The solve must back off along that update to a
  // point whose tangent is positive definite, and end at the equilibrium
  // that four solves of 15 % each reach.
  double      p_one = 1.0, p_steps = 1.0;
  double      V_one = 0, V_steps = 0;
  std::string log;
  for (const bool in_one : {true, false})
    {
      Setup        s;
      const auto   problem = two_accepted_states(s);
      const double V0      = problem->cavity_volume();
      double      &p       = in_one ? p_one : p_steps;
      for (unsigned int i = 1; i <= (in_one ? 1 : 4); ++i)
        {
          problem->solve_volume(V0 * (1.0 + 0.6 * i / (in_one ? 1 : 4)),
                                0.0,
                                p);
          problem->save();
        }
      (in_one ? V_one : V_steps) = problem->cavity_volume();
      if (in_one)
        log = s.sink.str();
    }
  INFO(log.substr(log.size() > 4000 ? log.size() - 4000 : 0));
  const auto at = log.find("negative pivot(s): back to");
  REQUIRE(at != std::string::npos);
  CHECK(log.find(", 0 negative pivot(s) there)", at) != std::string::npos);
  CHECK(V_one == Approx(V_steps).epsilon(1e-8));
  CHECK(p_one == Approx(p_steps).epsilon(1e-6));
}
