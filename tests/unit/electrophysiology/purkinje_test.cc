// The Purkinje tree: reproducible from its seed, on the surface, activated
// at path length / velocity, and activating the muscle at its junctions.
#include <deal.II/base/parameter_handler.h>

#include "electrophysiology/monodomain.h"
#include "electrophysiology/purkinje.h"
#include "support/ep_fixture.h"
#include "support/purkinje_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

using namespace systole::Electrophysiology;
using test_support::run_purkinje_lv;
using test_support::small_purkinje_parameters;

namespace
{
  bool
  same_tree(const PurkinjeNetwork &a, const PurkinjeNetwork &b)
  {
    if (a.nodes.size() != b.nodes.size() || a.edges != b.edges ||
        a.junctions != b.junctions)
      return false;
    for (unsigned int i = 0; i < a.nodes.size(); ++i)
      if (a.nodes[i] != b.nodes[i] || a.times[i] != b.times[i])
        return false;
    return true;
  }
} // namespace

TEST_CASE("The same seed grows the same Purkinje tree, another seed another",
          "[ep][purkinje]")
{
  const auto params       = small_purkinje_parameters();
  const auto first        = run_purkinje_lv(params, 2, false, MPI_COMM_SELF);
  const auto again        = run_purkinje_lv(params, 2, false, MPI_COMM_SELF);
  auto       other_params = params;
  other_params.seed       = params.seed + 1;
  const auto other = run_purkinje_lv(other_params, 2, false, MPI_COMM_SELF);
  INFO(first.network.nodes.size()
       << " nodes, " << first.network.junctions.size() << " junctions");
  CHECK(first.network.nodes.size() > 100);
  CHECK(first.network.junctions.size() > 10);
  CHECK(same_tree(first.network, again.network));
  CHECK(!same_tree(first.network, other.network));
}

TEST_CASE("Every Purkinje node lies on the endocardial surface",
          "[ep][purkinje]")
{
  const auto run =
    run_purkinje_lv(small_purkinje_parameters(), 2, false, MPI_COMM_SELF);
  // Distances by brute force over all triangles, with a point-triangle
  // distance of its own (test_support::distance_to_triangle).
  double largest = 0;
  for (const auto &x : run.network.nodes)
    {
      double d = std::numeric_limits<double>::infinity();
      for (const auto &t : run.triangles)
        d = std::min(d, test_support::distance_to_triangle(x, t));
      largest = std::max(largest, d);
    }
  INFO(run.network.nodes.size()
       << " nodes, " << run.triangles.size() << " triangles");
  CHECK(largest < 1e-8);
  // And the tree spreads: its nodes span much of the cavity's height.
  double z_min = 0;
  for (const auto &x : run.network.nodes)
    z_min = std::min(z_min, x[2]);
  CHECK(z_min < -8);
}

TEST_CASE("Closest points on the surface equal the brute-force ones",
          "[ep][purkinje]")
{
  const auto run =
    run_purkinje_lv(small_purkinje_parameters(), 1, false, MPI_COMM_SELF);
  const TriangleSurface surface(run.triangles);
  std::mt19937          rng(42);
  const auto            uniform = [&](const double a, const double b) {
    return a + (b - a) * (rng() / 4294967296.0);
  };
  for (unsigned int k = 0; k < 200; ++k)
    {
      const dealii::Point<3> p(uniform(-12, 12),
                               uniform(-12, 12),
                               uniform(-22, 8));
      double                 d = std::numeric_limits<double>::infinity();
      for (const auto &t : run.triangles)
        d = std::min(d, test_support::distance_to_triangle(p, t));
      const auto projection = surface.project(p);
      CHECK(projection.distance == Approx(d).margin(1e-10));
      CHECK(p.distance(projection.point) == Approx(d).margin(1e-10));
    }
}

TEST_CASE("Purkinje activation equals path length over velocity",
          "[ep][purkinje]")
{
  auto params     = small_purkinje_parameters();
  params.velocity = 2.5;
  const auto  run = run_purkinje_lv(params, 2, false, MPI_COMM_SELF);
  const auto &net = run.network;
  // Edges go from parent to child: walk each node back to the His entry.
  std::vector<int> parent(net.nodes.size(), -1);
  for (const auto &[a, b] : net.edges)
    {
      REQUIRE(a < b);
      REQUIRE(parent[b] == -1);
      parent[b] = a;
    }
  double largest = 0;
  for (unsigned int i = 1; i < net.nodes.size(); ++i)
    {
      double length = 0;
      for (int j = i; parent[j] >= 0; j = parent[j])
        length += net.nodes[j].distance(net.nodes[parent[j]]);
      largest =
        std::max(largest, std::abs(net.times[i] - length / params.velocity));
    }
  CHECK(net.times[0] == 0);
  CHECK(largest < 1e-12);
}

TEST_CASE("Every Purkinje junction activates the muscle", "[ep][purkinje]")
{
  const auto run =
    run_purkinje_lv(small_purkinje_parameters(), 2, true, MPI_COMM_SELF);
  const auto &net = run.network;
  REQUIRE(!net.junctions.empty());
  double worst = -std::numeric_limits<double>::infinity();
  for (unsigned int j = 0; j < net.junctions.size(); ++j)
    worst = std::max(worst,
                     run.junction_node_time[j] -
                       (net.times[net.junctions[j]] + net.junction_delay +
                        run.h / run.velocity));
  INFO("h = " << run.h << " mm");
  CHECK(worst <= 0);
  CHECK(run.n_unreached == 0);
  // Nothing activates before the earliest junction plus the delay.
  double earliest = std::numeric_limits<double>::infinity();
  for (const unsigned int j : net.junctions)
    earliest = std::min(earliest, net.times[j] + net.junction_delay);
  for (const double t : run.junction_node_time)
    CHECK(t >= earliest);
}

TEST_CASE("A Junction height limit keeps the junctions and branches apical",
          "[ep][purkinje]")
{
  // The small ventricle: endocardial apex at z = -17, base plane z = 5.
  auto params    = small_purkinje_parameters();
  params.apex    = dealii::Point<3>(0, 0, -17);
  params.base    = dealii::Point<3>(0, 0, 5);
  const auto all = run_purkinje_lv(params, 2, false, MPI_COMM_SELF);
  params.junction_height_limit = 0.75; // z <= -0.5
  const auto  apical = run_purkinje_lv(params, 2, false, MPI_COMM_SELF);
  const auto &net    = apical.network;
  // The height by hand: z relative to the axis from -17 to 5.
  const auto height = [](const dealii::Point<3> &x) {
    return (x[2] + 17) / 22;
  };
  unsigned int above_all = 0;
  for (const unsigned int j : all.network.junctions)
    above_all += height(all.network.nodes[j]) > 0.75;
  INFO(all.network.junctions.size()
       << " junctions without a limit, " << above_all << " of them above 0.75; "
       << net.junctions.size() << " with it");
  REQUIRE(above_all > 0); // the limit has something to remove
  REQUIRE(net.junctions.size() > 5);
  for (const unsigned int j : net.junctions)
    CHECK(height(net.nodes[j]) <= 0.75 + 1e-12);
  // The branches after the fascicles stay below: only the bundle and the
  // fascicles (their nodes are the first ones grown, up to 3 + 4 + 4 mm of
  // 0.5 mm segments: at most 23 nodes after the His entry) may lie above.
  for (unsigned int i = 24; i < net.nodes.size(); ++i)
    CHECK(height(net.nodes[i]) <= 0.75 + 1e-12);
  // The bundle and fascicles are the same with and without the limit.
  for (unsigned int i = 0; i < 24 && i < net.nodes.size(); ++i)
    CHECK(net.nodes[i] == all.network.nodes[i]);
}

TEST_CASE("A His point away from the endocardium is an error", "[ep][purkinje]")
{
  auto params      = small_purkinje_parameters();
  params.his_point = dealii::Point<3>(0, 0, -5); // in the cavity
  CHECK_THROWS_WITH(run_purkinje_lv(params, 1, false, MPI_COMM_SELF),
                    Catch::Contains("His point"));
}

TEST_CASE("Purkinje parameters parse to their declared defaults and name "
          "bad entries",
          "[ep][purkinje]")
{
  const auto parsed = [](const std::string &extra) {
    dealii::ParameterHandler prm;
    prm.enter_subsection("Electrophysiology");
    PurkinjeParameters::declare(prm);
    prm.leave_subsection();
    prm.parse_input_from_string("subsection Electrophysiology\n"
                                "  subsection Purkinje\n"
                                "    set Enable = true\n" +
                                extra + "  end\nend\n");
    return PurkinjeParameters::parse(prm);
  };
  const PurkinjeParameters defaults;
  const auto               p = parsed("");
  CHECK(p.enabled);
  CHECK(p.his_point == defaults.his_point);
  CHECK(p.initial_direction == defaults.initial_direction);
  CHECK(p.fascicle_angles == defaults.fascicle_angles);
  CHECK(p.fascicle_lengths == defaults.fascicle_lengths);
  CHECK(p.his_length == defaults.his_length);
  CHECK(p.branch_length == defaults.branch_length);
  CHECK(p.branch_angle == defaults.branch_angle);
  CHECK(p.generations == defaults.generations);
  CHECK(p.velocity == defaults.velocity);
  CHECK(p.junction_delay == defaults.junction_delay);
  CHECK(p.apex == defaults.apex);
  CHECK(p.base == defaults.base);
  CHECK(p.junction_height_limit == defaults.junction_height_limit);
  CHECK_THROWS_WITH(parsed("    set Base = 0, 0, -84\n"),
                    Catch::Contains("Base"));
  CHECK_THROWS_WITH(parsed("    set Minimum node distance = 1.5\n"),
                    Catch::Contains("Minimum node distance"));
  CHECK_THROWS_WITH(parsed("    set Fascicle lengths = 10, 10\n"),
                    Catch::Contains("Fascicle lengths"));
  CHECK_THROWS_WITH(parsed("    set His point = 1, 2\n"),
                    Catch::Contains("His point"));
}

TEST_CASE("A right bundle grows its own tree on its own surface",
          "[ep][purkinje]")
{
  // The small ventricle has one cavity: its epicardium stands in for the
  // right ventricle's endocardium.
  auto       params       = small_purkinje_parameters();
  const auto left         = run_purkinje_lv(params, 2, false, MPI_COMM_SELF);
  params.right.surface    = "epicardium";
  params.right.his_point  = dealii::Point<3>(-10, 0, 1);
  params.right.his_length = 3;
  params.right.fascicle_angles  = {0};
  params.right.fascicle_lengths = {4};
  const auto  both = run_purkinje_lv(params, 2, false, MPI_COMM_SELF);
  const auto &net  = both.network;
  // The left tree is unchanged and numbered first.
  REQUIRE(both.n_left == left.network.nodes.size());
  REQUIRE(net.nodes.size() > both.n_left + 20);
  for (unsigned int i = 0; i < both.n_left; ++i)
    CHECK(net.nodes[i] == left.network.nodes[i]);
  // The right tree starts at its own His entry at the same time, on the
  // epicardium (r_s = 10 mm at the equator), its edges inside it.
  CHECK(net.times[both.n_left] == 0);
  CHECK(std::abs(net.nodes[both.n_left].distance(dealii::Point<3>(0, 0, 1)) -
                 10) < 0.1);
  for (const auto &[a, b] : net.edges)
    CHECK((a < both.n_left) == (b < both.n_left));
  unsigned int right_junctions = 0;
  for (const unsigned int j : net.junctions)
    right_junctions += j >= both.n_left ? 1 : 0;
  CHECK(right_junctions > 5);
}

TEST_CASE("With the monodomain model the junctions stimulate the muscle at "
          "their times",
          "[ep][purkinje]")
{
  auto params = Parameters::defaults("Mitchell-Schaeffer");
  // The stimulus's region is not used: the junctions' stimuli replace it,
  // with its duration and amplitude.
  params.stimuli = parse_stimuli("his: box 0 0 0 1 1 1 from 1 for 2 at 50");
  auto &tree     = params.purkinje;
  tree           = small_purkinje_parameters();
  tree.surface   = "z_min";
  tree.his_point = dealii::Point<3>(1, 1, 0);
  tree.initial_direction = dealii::Tensor<1, 3>({1, 1, 0});
  tree.his_length        = 2;
  tree.fascicle_angles   = {-45, 45};
  tree.fascicle_lengths  = {3, 3};
  tree.branch_length     = 2;
  tree.generations       = 2;
  tree.junction_radius   = 1;
  test_support::EPBox box;
  box.upper = dealii::Point<3>(10, 10, 1);
  box.cells = {{20, 20, 2}};
  box.fibre = test_support::unit_vector(0);
  PurkinjeNetwork network;
  PointValues     at_junctions;
  test_support::run_ep_box(params,
                           box,
                           20,
                           10,
                           {},
                           MPI_COMM_SELF,
                           [&](const Monodomain &ep) {
                             network = ep.purkinje();
                             std::vector<dealii::Point<3>> points;
                             for (const unsigned int j : network.junctions)
                               points.push_back(network.nodes[j]);
                             at_junctions = ep.values_at_points(points);
                           });
  REQUIRE(network.junctions.size() > 3);
  CHECK(network.times[0] == 1); // the His entry at the stimulus's start
  double earliest = std::numeric_limits<double>::infinity();
  for (const unsigned int j : network.junctions)
    earliest = std::min(earliest, network.times[j] + network.junction_delay);
  double worst = -std::numeric_limits<double>::infinity();
  double first = std::numeric_limits<double>::infinity();
  for (unsigned int k = 0; k < network.junctions.size(); ++k)
    {
      const double t = at_junctions.activation_time[k];
      REQUIRE(std::isfinite(t));
      // Activated within 3 ms of its stimulus (the cell's latency, about 1
      // ms, and the wave from the stimulated half ball).
      worst = std::max(worst,
                       t - (network.times[network.junctions[k]] +
                            network.junction_delay + 3));
      first = std::min(first, t);
    }
  INFO(network.junctions.size()
       << " junctions, first junction stimulus at " << earliest << " ms");
  CHECK(worst <= 0);
  // Nothing activates before the first junction's stimulus.
  CHECK(first >= earliest);
}
