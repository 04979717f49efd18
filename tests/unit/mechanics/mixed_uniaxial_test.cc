// The mixed u-p formulations against an analytic solution: a unit cube of
// isotropic Guccione material on three symmetry planes, pulled by a negative
// follower pressure on x = 1, stretches homogeneously.
//
// Derivation (by hand, independent of the FE code). With all Guccione
// weights 1, Q = E:E and W = C/2 (exp(Q) - 1) is isotropic, so
// S_passive = C exp(Q) E whatever the fibre frame. Try F = diag(l, t, t):
//   E = diag(E11, E22, E22), E11 = (l^2 - 1)/2, E22 = (t^2 - 1)/2,
//   Q = E11^2 + 2 E22^2, J = l t^2, C^{-1} = diag(1/l^2, 1/t^2, 1/t^2).
// The mixed energy W(E_bar) - p (J - 1) - p^2/(2 kappa), with the isochoric
// part of the law (E_bar of C_bar = J^{-2/3} C, materials/isochoric_part.h),
// gives
//   S = J^{-2/3} (S_bar - (C : S_bar)/3 C^{-1}) - p J C^{-1},
//   S_bar = C exp(Q_bar) E_bar,   p = -kappa (J - 1);
// for J = 1 the first term differs from C exp(Q) E only by a multiple of
// C^{-1}, which p absorbs, so the incompressible solution below uses
// S = C exp(Q) E - p J C^{-1}
// (p the pressure unknown, positive in compression; 1/kappa = 0, J = 1 for
// the incompressible formulation). The stress is uniform, so equilibrium
// holds in the body; on the symmetry planes x, y, z = 0 the shear tractions
// vanish (S diagonal) and the normal displacement is zero. The faces y = 1
// and z = 1 are traction free:
//   S22 = C exp(Q) E22 - p J / t^2 = 0.                                 (1)
// On x = 1 the follower pressure -P (P > 0) acts on the deformed area along
// the deformed normal n = e1: the traction is -(-P) n = P e1, and with the
// Cauchy stress sigma = F S F^T / J,
//   sigma11 = l^2 S11 / J = (l^2 C exp(Q) E11 - p J) / J = P.           (2)
// (with S_bar, E_bar in place of C exp(Q) E, E when J != 1).
// Incompressible: t = 1/sqrt(l), J = 1; (1) gives p = C exp(Q) E22 t^2 and
// (2) becomes the scalar equation
//   P(l) = C exp(Q) (l^2 E11 - t^2 E22) = P,
// increasing in l > 1; solved here by bisection. Nearly incompressible: p =
// -kappa (l t^2 - 1) in (1) and (2), a 2x2 system in (l, t), solved here by
// Newton with a central-difference Jacobian.
//
// The displacement (linear) and the pressure (constant) lie in the Q2-P1disc
// space on the undistorted box, so the FE solution is exact up to the Newton
// and round-off errors.
//
// The same cube checks the iterative solvers against the direct one, with
// either displacement preconditioner, and the p-multigrid's fall-back to GAMG
// for Q1 displacements.
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria.h>

#include "base/logger.h"
#include "geometry/mesh.h"
#include "materials/guccione.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace systole;

namespace
{
  constexpr double stiffness = 2.0; // Guccione C [kPa]

  /// Residuals of (1) and (2) above for F = diag(l, t, t) of the nearly
  /// incompressible formulation, p = -kappa (J - 1): {S22, sigma11 - P}
  /// [kPa].
  std::array<double, 2>
  homogeneous_residual(const double l,
                       const double t,
                       const double P,
                       const double kappa)
  {
    // The isochoric part of the law (what the mixed formulations use):
    // S_bar = C exp(Q_bar) E_bar at C_bar = J^(-2/3) C, and
    // S_iso = J^(-2/3) (S_bar - (C : S_bar)/3 C^-1).
    const double J       = l * t * t;
    const double Jm23    = std::pow(J, -2.0 / 3.0);
    const double E11     = 0.5 * (Jm23 * l * l - 1.0);
    const double E22     = 0.5 * (Jm23 * t * t - 1.0);
    const double Q       = E11 * E11 + 2.0 * E22 * E22;
    const double Ce      = stiffness * std::exp(Q);
    const double S11_bar = Ce * E11, S22_bar = Ce * E22;
    const double C_S = l * l * S11_bar + 2.0 * t * t * S22_bar;
    const double S11 = Jm23 * (S11_bar - C_S / (3.0 * l * l));
    const double S22 = Jm23 * (S22_bar - C_S / (3.0 * t * t));
    const double p   = -kappa * (J - 1.0);
    return {{S22 - p * J / (t * t), (l * l * S11 - p * J) / J - P}};
  }

  /// The incompressible uniaxial stretch l under the traction P > 0:
  /// bisection on P(l) = C exp(Q) (l^2 E11 - t^2 E22), t^2 = 1/l.
  double
  incompressible_stretch(const double P)
  {
    const auto traction = [](const double l) {
      const double t2  = 1.0 / l;
      const double E11 = 0.5 * (l * l - 1.0);
      const double E22 = 0.5 * (t2 - 1.0);
      const double Q   = E11 * E11 + 2.0 * E22 * E22;
      return stiffness * std::exp(Q) * (l * l * E11 - t2 * E22);
    };
    double lo = 1.0, hi = 3.0;
    REQUIRE(traction(hi) > P);
    for (unsigned int i = 0; i < 200 && hi - lo > 1e-15; ++i)
      {
        const double mid              = 0.5 * (lo + hi);
        (traction(mid) < P ? lo : hi) = mid;
      }
    return 0.5 * (lo + hi);
  }

  /// The nearly incompressible homogeneous solution {l, t} under the traction
  /// P: Newton on (1), (2) with a central-difference Jacobian, from the
  /// incompressible solution.
  std::array<double, 2>
  nearly_incompressible_stretches(const double P, const double kappa)
  {
    const double l0   = incompressible_stretch(P);
    double       x[2] = {l0, 1.0 / std::sqrt(l0)};
    for (unsigned int it = 0;; ++it)
      {
        REQUIRE(it < 30);
        const auto   r = homogeneous_residual(x[0], x[1], P, kappa);
        const double h = 1e-6;
        double       jac[2][2];
        for (unsigned int j = 0; j < 2; ++j)
          {
            double xp[2] = {x[0], x[1]}, xm[2] = {x[0], x[1]};
            xp[j] += h;
            xm[j] -= h;
            const auto rp = homogeneous_residual(xp[0], xp[1], P, kappa);
            const auto rm = homogeneous_residual(xm[0], xm[1], P, kappa);
            for (unsigned int i = 0; i < 2; ++i)
              jac[i][j] = (rp[i] - rm[i]) / (2 * h);
          }
        const double det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        const double dl  = -(jac[1][1] * r[0] - jac[0][1] * r[1]) / det;
        const double dt  = -(-jac[1][0] * r[0] + jac[0][0] * r[1]) / det;
        x[0] += dl;
        x[1] += dt;
        if (std::abs(dl) + std::abs(dt) < 1e-14)
          break;
      }
    const auto r = homogeneous_residual(x[0], x[1], P, kappa);
    REQUIRE(std::abs(r[0]) + std::abs(r[1]) < 1e-11);
    return {{x[0], x[1]}};
  }

  const std::vector<double> loads = {0.5, 1.0, 2.0}; // P [kPa]

  /// The unit cube of isotropic Guccione material (2 x 2 x 2 cells) on the
  /// three symmetry planes, pulled by a follower pressure on x = 1.
  struct PulledCube
  {
    PulledCube(const Mechanics::Incompressibility          incompressibility,
               const std::string                          &linear_solver,
               const double                                kappa,
               const Mechanics::DisplacementPreconditioner preconditioner =
                 Mechanics::DisplacementPreconditioner::amg,
               const unsigned int degree = 2)
      : logger(MPI_COMM_WORLD, sink)
      , law(guccione())
      , volumetric(Materials::VolumetricLaw::Form::quadratic, kappa)
      , tria(MPI_COMM_WORLD)
    {
      Geometry::Parameters geometry;
      geometry.type               = Geometry::Parameters::Type::box;
      geometry.box_upper          = dealii::Point<3>(1, 1, 1);
      geometry.box_cells          = {{2, 2, 2}};
      const auto            names = Geometry::create_mesh(geometry, tria);
      Mechanics::Parameters params;
      params.incompressibility           = incompressibility;
      params.sliding_boundaries          = {"x_min", "y_min", "z_min"};
      params.fixed_boundaries            = {};
      params.pressure_boundary           = "x_max";
      params.linear_solver               = linear_solver;
      params.displacement_preconditioner = preconditioner;
      // A constant frame not aligned with the box (the law is isotropic).
      const Fibres::FibreField fibres =
        [](const auto &, const auto &points, auto &bases) {
          bases.resize(points.size());
          for (auto &b : bases)
            {
              b.f = dealii::Tensor<1, 3>({1, 1, 1}) / std::sqrt(3.0);
              b.s = dealii::Tensor<1, 3>({1, -1, 0}) / std::sqrt(2.0);
              b.n = dealii::Tensor<1, 3>({1, 1, -2}) / std::sqrt(6.0);
            }
        };
      problem = std::make_unique<Mechanics::Problem>(
        Mechanics::Problem::Inputs{params,
                                   tria,
                                   names,
                                   degree,
                                   1,
                                   law,
                                   volumetric,
                                   fibres,
                                   logger});
      CHECK_FALSE(problem->has_cavity());
    }

    static Materials::Guccione::Parameters
    guccione()
    {
      Materials::Guccione::Parameters p;
      p.C    = stiffness;
      p.b_f  = 1;
      p.b_t  = 1;
      p.b_fs = 1;
      return p;
    }

    /// Deformed position of the corner (1, 1, 1) after each load of loads,
    /// each solve starting from the previous one.
    std::vector<dealii::Point<3>>
    corners()
    {
      INFO(problem->discretization_name()
           << ", " << problem->linear_solver_name());
      std::vector<dealii::Point<3>> result;
      for (const double P : loads)
        {
          // A negative follower pressure pulls the face outwards.
          const auto report = problem->solve(-P, 0.0);
          problem->save();
          INFO("P = " << P << " kPa: " << report.iterations
                      << " Newton iterations, |R| = " << report.final_residual);
          CHECK(report.iterations > 0);
          result.push_back(
            problem->deformed_positions({dealii::Point<3>(1, 1, 1)})[0]);
        }
      return result;
    }

    std::ostringstream                              sink;
    Logger                                          logger;
    const Materials::Guccione                       law;
    const Materials::VolumetricLaw                  volumetric;
    dealii::parallel::distributed::Triangulation<3> tria;
    std::unique_ptr<Mechanics::Problem>             problem;
  };

  /// PulledCube(...).corners().
  std::vector<dealii::Point<3>>
  pulled_corner(const Mechanics::Incompressibility          incompressibility,
                const std::string                          &linear_solver,
                const double                                kappa,
                const Mechanics::DisplacementPreconditioner preconditioner =
                  Mechanics::DisplacementPreconditioner::amg)
  {
    return PulledCube(incompressibility, linear_solver, kappa, preconditioner)
      .corners();
  }

  double
  relative_error(const double value, const double exact)
  {
    return std::abs(value - exact) / std::abs(exact);
  }
} // namespace

TEST_CASE("A mixed u-p cube pulled by a follower pressure stretches like the "
          "analytic uniaxial solution",
          "[mechanics][analytic]")
{
  SECTION("Incompressible Q2-P1disc, direct solver")
  {
    const auto corners =
      pulled_corner(Mechanics::Incompressibility::incompressible,
                    "direct",
                    50.0);
    for (unsigned int i = 0; i < loads.size(); ++i)
      {
        const double l = incompressible_stretch(loads[i]);
        const double t = 1.0 / std::sqrt(l);
        INFO("P = " << loads[i] << " kPa: analytic l = " << l << ", FE corner "
                    << corners[i]);
        const double e_l = relative_error(corners[i][0], l);
        const double e_y = relative_error(corners[i][1], t);
        const double e_z = relative_error(corners[i][2], t);
        INFO("relative errors: x " << e_l << ", y " << e_y << ", z " << e_z);
        CHECK(e_l < 1e-8);
        CHECK(e_y < 1e-8);
        CHECK(e_z < 1e-8);
      }
  }

  SECTION("Nearly incompressible Q2-P1disc, kappa = 50 kPa, direct solver")
  {
    const double kappa = 50.0;
    const auto   corners =
      pulled_corner(Mechanics::Incompressibility::nearly_incompressible,
                    "direct",
                    kappa);
    for (unsigned int i = 0; i < loads.size(); ++i)
      {
        const auto [l, t] = nearly_incompressible_stretches(loads[i], kappa);
        INFO("P = " << loads[i] << " kPa: analytic l = " << l << ", t = " << t
                    << ", J - 1 = " << l * t * t - 1.0 << ", FE corner "
                    << corners[i]);
        // The compressibility is visible: J - 1 well above the tolerance.
        CHECK(l * t * t - 1.0 > 1e-3);
        const double e_l = relative_error(corners[i][0], l);
        const double e_y = relative_error(corners[i][1], t);
        const double e_z = relative_error(corners[i][2], t);
        INFO("relative errors: x " << e_l << ", y " << e_y << ", z " << e_z);
        CHECK(e_l < 1e-8);
        CHECK(e_y < 1e-8);
        CHECK(e_z < 1e-8);
      }
  }

  SECTION("Incompressible Q2-P1disc, the iterative solver reproduces the "
          "direct one, with either displacement preconditioner (the "
          "p-multigrid on sliding boundaries: constrained components)")
  {
    const auto direct =
      pulled_corner(Mechanics::Incompressibility::incompressible,
                    "direct",
                    50.0);
    for (const auto preconditioner :
         {Mechanics::DisplacementPreconditioner::amg,
          Mechanics::DisplacementPreconditioner::p_multigrid})
      {
        PulledCube        cube(Mechanics::Incompressibility::incompressible,
                        "iterative",
                        50.0,
                        preconditioner);
        const std::string name = cube.problem->linear_solver_name();
        INFO(name);
        CHECK((name.find("p-multigrid Q2 -> Q1") != std::string::npos) ==
              (preconditioner ==
               Mechanics::DisplacementPreconditioner::p_multigrid));
        const auto iterative = cube.corners();
        for (unsigned int i = 0; i < loads.size(); ++i)
          {
            const double l = incompressible_stretch(loads[i]);
            INFO("P = " << loads[i] << " kPa: direct " << direct[i]
                        << ", iterative " << iterative[i]);
            for (unsigned int d = 0; d < 3; ++d)
              {
                const double e = relative_error(iterative[i][d], direct[i][d]);
                INFO("component " << d << ": relative difference " << e
                                  << ", x against analytic "
                                  << relative_error(iterative[i][0], l));
                CHECK(e < 1e-7);
              }
          }
      }
  }
}

TEST_CASE("With the penalty formulation, FGMRES with the p-multigrid "
          "reproduces the direct solver",
          "[mechanics][linear_solver]")
{
  const auto direct =
    pulled_corner(Mechanics::Incompressibility::penalty, "direct", 50.0);
  PulledCube cube(Mechanics::Incompressibility::penalty,
                  "iterative",
                  50.0,
                  Mechanics::DisplacementPreconditioner::p_multigrid);
  INFO(cube.problem->linear_solver_name());
  CHECK(cube.problem->linear_solver_name().find(
          "FGMRES + p-multigrid Q2 -> Q1") != std::string::npos);
  const auto iterative = cube.corners();
  for (unsigned int i = 0; i < loads.size(); ++i)
    for (unsigned int d = 0; d < 3; ++d)
      {
        INFO("P = " << loads[i] << " kPa, component " << d << ": direct "
                    << direct[i][d] << ", iterative " << iterative[i][d]);
        CHECK(relative_error(iterative[i][d], direct[i][d]) < 1e-7);
      }
}

TEST_CASE("The p-multigrid falls back to GAMG for Q1 displacements, and the "
          "solver name says so",
          "[mechanics][linear_solver]")
{
  for (const auto incompressibility :
       {Mechanics::Incompressibility::penalty,
        Mechanics::Incompressibility::incompressible})
    {
      const PulledCube  cube(incompressibility,
                            "iterative",
                            50.0,
                            Mechanics::DisplacementPreconditioner::p_multigrid,
                            1);
      const std::string name = cube.problem->linear_solver_name();
      INFO(name);
      CHECK(name.find("GAMG") != std::string::npos);
      CHECK(name.find("p-multigrid Q") == std::string::npos);
      CHECK(name.find("no coarser degree") != std::string::npos);
    }
}
