// The eikonal solver: the local solver on one simplex, exactness for plane
// fronts, and the ellipsoidal arrival times of a point source in a
// homogeneous anisotropic block with their order of convergence.
#include "electrophysiology/eikonal.h"
#include "support/eikonal_fixture.h"
#include "support/ep_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <sstream>

using namespace systole::Electrophysiology;
using test_support::EikonalBlock;
using test_support::run_eikonal_block;

TEST_CASE("The local eikonal update minimizes over the simplex",
          "[ep][eikonal]")
{
  const dealii::SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
  const dealii::Point<3>              x(0, 0, 1);
  const dealii::Point<3>              a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const dealii::Point<3>             *y[3] = {&a, &b, &c};
  // Equal times on the face: the foot of the perpendicular.
  double T[3] = {1, 1, 1};
  CHECK(eikonal_simplex_update(I, x, y, T, 3) == Approx(2).epsilon(1e-14));
  // A plane front through the face at unit speed, T = nu . x, whose
  // characteristic from (0.4, 0.4, 1) crosses the face inside.
  const dealii::Tensor<1, 3> nu({0.2, 0.3, std::sqrt(1 - 0.13)});
  const dealii::Point<3>     x2(0.4, 0.4, 1);
  const double               Tp[3] = {0, nu * b, nu * c};
  CHECK(eikonal_simplex_update(I, x2, y, Tp, 3) ==
        Approx(nu * x2).epsilon(1e-14));
  // One known vertex: the distance; an anisotropic metric A = V^-1.
  dealii::SymmetricTensor<2, 3> A;
  A[0][0] = 1 / 4.0, A[1][1] = 1, A[2][2] = 1 / 9.0;
  const dealii::Point<3>  far(2, 0, 3);
  const dealii::Point<3> *one[1] = {&a};
  CHECK(eikonal_simplex_update(A, far, one, T, 1) ==
        Approx(1 + std::sqrt(2.0)).epsilon(1e-14));
}

TEST_CASE("Plane fronts are exact on hexahedra and tetrahedra", "[ep][eikonal]")
{
  for (const bool tets : {false, true})
    {
      EikonalBlock block;
      block.tetrahedra      = tets;
      block.plane_normal[0] = 0.8;
      block.plane_normal[1] = -0.36;
      block.plane_normal[2] = 0.48;
      block.start           = 20;
      const auto r          = run_eikonal_block(block, MPI_COMM_SELF);
      INFO((tets ? "P1" : "Q1") << ": max error " << r.max_error << " ms");
      CHECK(r.max_error < 1e-11);
    }
}

namespace
{
  /// A 4 x 3 x 2 mm block, fibre frame rotated against the axes, v = 0.6,
  /// 0.25, 0.15 mm/ms; the nodes within one cell, or within a fixed 0.5 mm,
  /// of the source start from the exact times. Max and mean errors over all
  /// nodes at h = 0.5 ... 0.5 / finest mm (Q1; P1 to 0.125 mm), each level
  /// checked against the one before (docs/verification.md has the table of
  /// finest = 8).
  void
  check_point_source_convergence(const unsigned int finest)
  {
    std::ostringstream out;
    out << std::setprecision(4);
    for (const double radius : {0.0, 0.5})
      for (const bool tets : {false, true})
        {
          out << "exact times within " << (radius > 0 ? "0.5 mm" : "one cell")
              << " of the source:\n";
          std::vector<double> max_error, mean_error;
          for (unsigned int k = 1; k <= finest; k *= 2)
            {
              EikonalBlock block;
              block.tetrahedra   = tets;
              block.exact_radius = radius;
              block.cells        = {{8 * k, 6 * k, 4 * k}};
              if (tets && k == 8)
                break;
              const auto r = run_eikonal_block(block, MPI_COMM_SELF);
              max_error.push_back(r.max_error);
              mean_error.push_back(r.mean_error);
              out << (tets ? "P1" : "Q1") << " h = " << 0.5 / k
                  << " mm: " << r.n_nodes << " nodes, max error " << r.max_error
                  << " ms, mean " << r.mean_error << " ms";
              if (max_error.size() > 1)
                out << ", orders "
                    << std::log2(max_error[max_error.size() - 2] /
                                 max_error.back())
                    << " (max), "
                    << std::log2(mean_error[mean_error.size() - 2] /
                                 mean_error.back())
                    << " (mean)";
              out << "\n";
            }
          // Measured (mean error orders): one cell, 0.80, 0.49, 0.84 (Q1) and
          // 0.52, 0.54 (P1): the point source's singularity, resolved by ever
          // fewer nodes; a fixed 0.5 mm, 1.55, 1.05, 1.04 (Q1) and 1.15, 1.00
          // (P1): first order, the scheme's.
          for (unsigned int k = 1; k < max_error.size(); ++k)
            {
              CHECK(max_error[k] < 0.8 * max_error[k - 1]);
              CHECK(mean_error[k] < 0.8 * mean_error[k - 1]);
            }
          if (radius > 0)
            CHECK(std::log2(mean_error[max_error.size() - 2] /
                            mean_error.back()) > 0.95);
        }
    WARN(out.str());
  }
} // namespace

TEST_CASE("A point source gives ellipsoidal fronts, converging under "
          "refinement",
          "[ep][eikonal]")
{
  check_point_source_convergence(4);
}

// The table's finest level too (h = 0.0625 mm, 105 105 nodes: the whole
// study took 104 s, the levels above 17 s); hidden, run by name:
// systole-unit "[eikonal-study]".
TEST_CASE("The point-source study of docs/verification.md, to h = 0.0625 mm",
          "[.eikonal-study]")
{
  check_point_source_convergence(8);
}

TEST_CASE("The reaction-eikonal models activate the nodes at their eikonal "
          "times",
          "[ep][eikonal][monodomain]")
{
  // A 4 x 2 x 1 mm slab, fibres along x, corner stimulus: the eikonal model
  // alone, RE- (the ionic model at the nodes, stimulated from its latency
  // before the eikonal time) and RE+ (with the diffusion). RE- upstrokes
  // at the eikonal times up to the time sampling; RE+ earlier or equal
  // (the diffusion adds to the stimulus).
  test_support::EPBox box;
  box.upper    = dealii::Point<3>(4, 2, 1);
  box.cells    = {{16, 8, 4}};
  box.fibre    = test_support::unit_vector(0);
  Parameters p = Parameters::defaults("Mitchell-Schaeffer");
  p.stimuli = parse_stimuli("corner: box 0 0 0 0.5 0.5 0.5 from 1 for 2 at 50");
  p.time_step                                = 0.05;
  p.eikonal.velocity_fibre                   = 0.5;
  p.eikonal.velocity_sheet                   = 0.2;
  p.eikonal.velocity_normal                  = 0.2;
  const std::vector<dealii::Point<3>> probes = {dealii::Point<3>(4, 2, 1),
                                                dealii::Point<3>(2, 1, 0.5),
                                                dealii::Point<3>(4, 0, 0)};
  const auto run = [&](const Parameters::Model model, const bool diffusion) {
    p.model                      = model;
    p.reaction_eikonal_diffusion = diffusion;
    return test_support::run_ep_box(p, box, 30, 5, probes, MPI_COMM_SELF);
  };
  const auto eikonal = run(Parameters::Model::eikonal, false);
  const auto minus   = run(Parameters::Model::reaction_eikonal, false);
  const auto plus    = run(Parameters::Model::reaction_eikonal, true);
  // Far corner: sqrt((3.5/0.5)^2 + (1.5/0.2)^2 + (0.5/0.2)^2) = 10.56 ms
  // after the stimulated cube's activation.
  CHECK(eikonal.probes.activation_time[0] > 11.5);
  CHECK(eikonal.probes.activation_time[0] < 13.5);
  for (unsigned int i = 0; i < probes.size(); ++i)
    {
      INFO("probe " << i << ": eikonal " << eikonal.probes.activation_time[i]
                    << ", RE- " << minus.probes.activation_time[i] << ", RE+ "
                    << plus.probes.activation_time[i] << " ms");
      CHECK(std::abs(minus.probes.activation_time[i] -
                     eikonal.probes.activation_time[i]) < 0.05);
      CHECK(plus.probes.activation_time[i] <
            eikonal.probes.activation_time[i] + 0.05);
      CHECK(plus.probes.activation_time[i] >
            eikonal.probes.activation_time[i] - 1.5);
    }
  CHECK(minus.statistics.linear_solves == 0);
  CHECK(eikonal.statistics.steps == 0);
}

namespace
{
  /// Checks that no node of @p faster (a run with more fast layer) is later
  /// than in @p slower; returns the largest gain [ms].
  template <class Times>
  double
  largest_gain(const Times &slower, const Times &faster)
  {
    REQUIRE(faster.size() == slower.size());
    double gain = 0;
    for (unsigned int i = 0; i < faster.size(); ++i)
      {
        CHECK(faster[i] <= slower[i] + 1e-12);
        gain = std::max(gain, slower[i] - faster[i]);
      }
    return gain;
  }
} // namespace

TEST_CASE("A fast endocardial layer conducts isotropically at its velocity",
          "[ep][eikonal]")
{
  // The point source's block with a layer of 0.3 mm (the first row of
  // cells, h = 0.25 mm) along y = 0 at 3 mm/ms. Along the layer the front
  // runs at its speed: the node (4, 0, 0) activates after about
  // |(4, 0, 0) - source| reached through the layer, far sooner than without.
  EikonalBlock block;
  block.cells                = {{16, 12, 8}};
  block.source               = dealii::Point<3>(0.5, 0.25, 0.5);
  const auto without         = run_eikonal_block(block, MPI_COMM_SELF);
  block.layer_part           = "y_min";
  block.layer_thickness      = 0.3;
  block.layer_velocity       = 3;
  const auto   with          = run_eikonal_block(block, MPI_COMM_SELF);
  const double earliest_gain = largest_gain(without.times, with.times);
  // (4, 0, 0) lies 3.5 mm along x from the source's foot in the layer:
  // about 1.2 ms through the layer against 3.5/0.6 = 5.8 ms (and more,
  // the fibres are oblique) without.
  INFO("largest gain " << earliest_gain << " ms");
  CHECK(earliest_gain > 4);
}

TEST_CASE(
  "A fast endocardial layer along two boundary parts conducts along both",
  "[ep][eikonal]")
{
  // The block of the test above with the layer along y = 0 alone, then
  // along y = 0 and y = 3 (the entry's comma-separated list, as for the
  // two endocardia of a biventricular mesh): the second layer can only
  // make nodes earlier, and along it, far from where the front first
  // reaches it, much earlier.
  EikonalBlock block;
  block.cells           = {{16, 12, 8}};
  block.source          = dealii::Point<3>(0.5, 0.25, 0.5);
  block.layer_part      = "y_min";
  block.layer_thickness = 0.3;
  block.layer_velocity  = 3;
  const auto one        = run_eikonal_block(block, MPI_COMM_SELF);
  block.layer_part      = "y_min, y_max";
  const auto   two      = run_eikonal_block(block, MPI_COMM_SELF);
  const double gain     = largest_gain(one.times, two.times);
  INFO("largest gain " << gain << " ms");
  CHECK(gain > 1);
  block.layer_part = "y_min, no_such_part";
  CHECK_THROWS(run_eikonal_block(block, MPI_COMM_SELF));
}
