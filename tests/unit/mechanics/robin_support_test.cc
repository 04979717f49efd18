// The spring-dashpot supports' entry: the apex-to-base taper of a
// pericardium, parsed and evaluated against the hand-computed profile; the
// option end-diastole, parsed, and its springs' reference checked through
// the translation invariance of a block held by them.
#include <deal.II/base/function.h>

#include "base/errors.h"
#include "mechanics/parameters.h"
#include "support/mechanics_fixture.h"

#include <catch2/catch.hpp>

using namespace systole;

namespace
{
  /// The one-line message of parsing @p item as Robin supports (empty if it
  /// parses).
  std::string
  parse_error(const std::string &item)
  {
    try
      {
        Mechanics::Parameters::parse_robin_supports(item);
      }
    catch (const std::exception &e)
      {
        return one_line_message(e);
      }
    return "";
  }

  /// The parameters of a 2 x 1 x 1 mm block held only by the Robin
  /// @p supports on x = 0 and pulled on x = 2 (a follower pressure).
  Mechanics::Parameters
  block_on_springs(const std::string &supports)
  {
    Mechanics::Parameters params;
    params.fixed_boundaries  = {};
    params.pressure_boundary = "x_max";
    params.linear_solver     = "direct";
    params.robin_supports =
      Mechanics::Parameters::parse_robin_supports(supports);
    return params;
  }

  /// That block, 2 x 1 x 1 cells of the Guccione law, with @p params.
  test_support::GuccioneBox
  block(const Mechanics::Parameters &params)
  {
    return test_support::GuccioneBox(dealii::Point<3>(2, 1, 1),
                                     {{2, 1, 1}},
                                     params,
                                     20.0);
  }

  /// Moves @p problem to the uniform displacement @p c [mm].
  void
  displace(Mechanics::Problem &problem, const dealii::Tensor<1, 3> &c)
  {
    problem.set_displacement(dealii::Functions::ConstantFunction<3>(
      std::vector<double>{c[0], c[1], c[2]}));
  }
} // namespace

TEST_CASE("A tapered support scales its springs from the apex to the base",
          "[mechanics]")
{
  const auto supports = Mechanics::Parameters::parse_robin_supports(
    "epicardium: normal, 0.1, 0.005, taper 0.5 0.2; base: full, 1, 0");
  REQUIRE(supports.size() == 2);
  auto epicardium = supports[0];
  CHECK(epicardium.normal_only);
  CHECK(epicardium.stiffness == 0.1);
  CHECK(epicardium.damping == 0.005);
  CHECK(epicardium.tapered());
  CHECK_FALSE(supports[1].tapered());
  CHECK(supports[1].scale(dealii::Point<3>(0, 0, -20)) == 1.0);

  // Base plane z = 5, apex at z = -20: h = (z + 20) / 25.
  epicardium.base_point   = dealii::Point<3>(3, -2, 5);
  epicardium.apex_to_base = dealii::Tensor<1, 3>({0, 0, 1});
  epicardium.height       = 25;
  CHECK(epicardium.scale(dealii::Point<3>(0, 0, -20)) == Approx(1.0));
  CHECK(epicardium.scale(dealii::Point<3>(7, 1, -7.5)) == Approx(1.0));
  // h = 0.75: halfway from h0 = 0.5 to the base, 1 - 0.8 / 2.
  CHECK(epicardium.scale(dealii::Point<3>(0, 9, -1.25)) == Approx(0.6));
  CHECK(epicardium.scale(dealii::Point<3>(0, 0, 5)) == Approx(0.2));
  // Beyond the base and the apex: clamped.
  CHECK(epicardium.scale(dealii::Point<3>(0, 0, 8)) == Approx(0.2));
  CHECK(epicardium.scale(dealii::Point<3>(0, 0, -30)) == Approx(1.0));
}

TEST_CASE("A support acts on the normal, the tangential or all components",
          "[mechanics]")
{
  const auto supports = Mechanics::Parameters::parse_robin_supports(
    "a: normal, 1, 0; b: tangential, 1, 0; c: full, 1, 0; d: full 0.25, 1, "
    "0, taper 0.5 0.2");
  const dealii::Tensor<1, 3> N({0.6, 0, 0.8});
  const dealii::Tensor<1, 3> u({1, 2, 3});
  // (u.N) N = 3 N; u - 3 N; u.
  const double               un = 0.6 * 1 + 0.8 * 3;
  const dealii::Tensor<1, 3> normal({0.6 * un, 0, 0.8 * un});
  CHECK((supports[0].projection(N) * u - normal).norm() < 1e-15);
  CHECK((supports[1].projection(N) * u - (u - normal)).norm() < 1e-15);
  CHECK((supports[2].projection(N) * u - u).norm() < 1e-15);
  // 'full 0.25': a quarter of the stiffness along the normal.
  REQUIRE(supports.size() == 4);
  CHECK(supports[3].normal_fraction == 0.25);
  CHECK(supports[3].base_scale == 0.2);
  CHECK((supports[3].projection(N) * u - (u - 0.75 * normal)).norm() < 1e-15);
}

TEST_CASE("A malformed taper names the item and the form", "[mechanics]")
{
  for (const std::string item : {"epicardium: normal, 1, 0, taper 1.2 0",
                                 "epicardium: normal, 1, 0, taper 0.5",
                                 "epicardium: normal, 1, 0, slope 0.5 0",
                                 "base: full -1, 1, 0, taper 0.5 0",
                                 "base: tangential 0.5, 1, 0, taper 0.5 0",
                                 "base: full x, 1, 0, taper 0.5 0"})
    {
      INFO(item);
      CHECK_THAT(parse_error(item),
                 Catch::Contains("Mechanics / Robin supports: '" + item +
                                 "' is not of the form") &&
                   Catch::Contains("taper h0 s_base"));
    }
}

TEST_CASE("The end-diastole option is parsed with or without a taper and a "
          "release time, once",
          "[mechanics]")
{
  const auto supports = Mechanics::Parameters::parse_robin_supports(
    "epicardium: normal, 20, 0, taper 0.5 0.05, end-diastole; base: full "
    "0.2, 1, 0, end-diastole; apex: normal, 1, 0");
  REQUIRE(supports.size() == 3);
  CHECK(supports[0].from_end_diastole);
  CHECK(supports[0].base_scale == 0.05);
  CHECK(supports[1].from_end_diastole);
  CHECK(supports[1].normal_fraction == 0.2);
  CHECK_FALSE(supports[2].from_end_diastole);
  for (const std::string item :
       {"base: full, 1, 0, end-diastole, end-diastole",
        "base: full, 1, 0, end diastole",
        "base: full, 1, 0, taper 0.5 0.1, taper 0.5 0.1",
        "base: full, 1, 0, taper 0.5 0.1, end-diastole, x",
        "base: full, 1, 0, end-diastole -1",
        "base: full, 1, 0, end-diastole x",
        "base: full, 1, 0, end-diastole 1 2"})
    {
      INFO(item);
      CHECK_THAT(parse_error(item),
                 Catch::Contains("Mechanics / Robin supports: '" + item +
                                 "' is not of the form") &&
                   Catch::Contains("', end-diastole [release time, ms]'"));
    }
}

TEST_CASE("The end-diastole option takes a release time, the same for all",
          "[mechanics]")
{
  const auto supports = Mechanics::Parameters::parse_robin_supports(
    "epicardium: normal, 20, 0, end-diastole 30; base: full, 1, 0, "
    "end-diastole 30");
  REQUIRE(supports.size() == 2);
  CHECK(supports[0].release_time == 30.0);
  CHECK(supports[1].release_time == 30.0);
  CHECK(Mechanics::Parameters::parse_robin_supports(
          "base: full, 1, 0, end-diastole")[0]
          .release_time == 0.0);
  CHECK_THAT(parse_error("epicardium: normal, 20, 0, end-diastole 30; base: "
                         "full, 1, 0, end-diastole 20"),
             Catch::Contains("different release times") &&
               Catch::Contains("give them the same T"));
}

TEST_CASE("A support referred to end-diastole pulls toward the displacement "
          "it was referred at",
          "[mechanics]")
{
  // A 2 x 1 x 1 mm block held only by a full support on x = 0 and pulled on
  // x = 2. The problem is invariant under translations (follower pressure,
  // no clamp) except through the springs: referred to a uniform
  // displacement c, the equilibrium under the same pull is the one
  // referred to zero, moved by c.
  Mechanics::Parameters params =
    block_on_springs("x_min: full, 0.5, 0, end-diastole");
  test_support::GuccioneBox           box     = block(params);
  auto                               &problem = *box.problem;
  const std::vector<dealii::Point<3>> points  = {dealii::Point<3>(0, 0, 0),
                                                 dealii::Point<3>(2, 1, 1),
                                                 dealii::Point<3>(1, 0.5, 0)};
  problem.solve(-0.2, 0.0);
  const auto   unshifted = problem.deformed_positions(points);
  const double energy    = problem.support_energy();
  // The spring stretch is about pull / alpha = 0.4 mm.
  CHECK(unshifted[0][0] > 0.3);

  const dealii::Tensor<1, 3> c({0.7, -0.3, 0.2});
  displace(problem, c);
  problem.refer_supports_to_end_diastole(0.0);
  CHECK(problem.support_energy() == 0.0);
  problem.solve(-0.2, 0.0);
  const auto shifted = problem.deformed_positions(points);
  for (unsigned int i = 0; i < points.size(); ++i)
    {
      INFO("point " << i);
      CHECK((shifted[i] - unshifted[i] - c).norm() < 1e-8);
    }
  // The same stretch of the springs, so the same energy in them.
  CHECK(problem.support_energy() == Approx(energy).epsilon(1e-7));

  // Without the option, the springs pull toward the unloaded state: the
  // shift is undone.
  params.robin_supports[0].from_end_diastole = false;
  test_support::GuccioneBox plain            = block(params);
  displace(*plain.problem, c);
  plain.problem->refer_supports_to_end_diastole(0.0);
  plain.problem->solve(-0.2, 0.0);
  const auto back = plain.problem->deformed_positions(points);
  for (unsigned int i = 0; i < points.size(); ++i)
    CHECK((back[i] - unshifted[i]).norm() < 1e-8);
}

TEST_CASE("A released support moves its rest position by a smooth step",
          "[mechanics]")
{
  // The block of the test above, its support released over 10 ms: referred
  // at t = 5 ms to the uniform displacement c, the rest position is
  // c s((t - 5) / 10), s(x) = 3 x^2 - 2 x^3; the equilibrium under the same
  // pull is the one referred to zero moved by it.
  const Mechanics::Parameters params =
    block_on_springs("x_min: full, 0.5, 0, end-diastole 10");
  test_support::GuccioneBox           box     = block(params);
  auto                               &problem = *box.problem;
  const std::vector<dealii::Point<3>> points  = {dealii::Point<3>(0, 0, 0),
                                                 dealii::Point<3>(2, 1, 1)};
  problem.solve(-0.2, 0.0);
  const auto unshifted = problem.deformed_positions(points);

  const dealii::Tensor<1, 3> c({0.7, -0.3, 0.2});
  displace(problem, c);
  problem.refer_supports_to_end_diastole(5.0);
  // t, the fraction of c the rest position has moved: before the start,
  // 0.3 and 0.5 of the way, at the end and after it.
  for (const auto &[t, s] : std::vector<std::pair<double, double>>{{4, 0},
                                                                   {8, 0.216},
                                                                   {10, 0.5},
                                                                   {15, 1},
                                                                   {40, 1}})
    {
      INFO("t = " << t);
      problem.set_support_time(t);
      problem.solve(-0.2, 0.0);
      const auto shifted = problem.deformed_positions(points);
      for (unsigned int i = 0; i < points.size(); ++i)
        CHECK((shifted[i] - unshifted[i] - s * c).norm() < 1e-8);
    }

  // Referred again halfway (t = 50 + 5) to 2 c: from c on toward 2 c.
  problem.set_support_time(50);
  displace(problem, 2 * c);
  problem.refer_supports_to_end_diastole(50.0);
  problem.set_support_time(55);
  problem.solve(-0.2, 0.0);
  const auto again = problem.deformed_positions(points);
  for (unsigned int i = 0; i < points.size(); ++i)
    CHECK((again[i] - unshifted[i] - 1.5 * c).norm() < 1e-8);
}
