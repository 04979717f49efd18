// Elastodynamics, part 2: Kelvin-Voigt viscosity and spring-dashpot (Robin)
// supports inside the generalized-alpha step. Independent checks:
// - the consistent tangent of a dynamic step with viscosity, normal and full
//   dashpots against central differences of its residual (order 2);
// - a stiff block on a spring-dashpot support (full, on one face) moves like
//   one damped degree of freedom, m u'' + beta A u' + alpha A u = 0: its
//   trajectory, period and decay rate against the analytic solution;
// - the energy balance of a bar pulled by a pulse with viscosity and
//   dashpots: kinetic + strain + support + dissipated energy = work of the
//   loads, to the scheme's second order (the defect falls about fourfold
//   when the step halves), with a dissipation that is not small.
#include <deal.II/base/function.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/lac/vector.h>

#include "base/logger.h"
#include "geometry/mesh.h"
#include "materials/guccione.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem.h"
#include "mechanics/problem_checks.h"
#include "support/mechanics_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

using namespace systole;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  /// The bar of dynamics_test.cc (4 x 1 x 1 mm, clamped at x = 0, pulled on
  /// x = 4 by a smooth pulse), with viscosity and two dashpot supports.
  Mechanics::Parameters
  damped_bar_parameters(const double spectral_radius)
  {
    Mechanics::Parameters params;
    params.fixed_boundaries  = {"x_min"};
    params.pressure_boundary = "x_max";
    params.linear_solver     = "direct";
    params.density           = 1.0;
    params.spectral_radius   = spectral_radius;
    params.viscosity         = 0.5; // kPa ms
    // Normal springs and dashpots on y = 1, full ones on z = 1.
    params.robin_supports = {{"y_max", 0.2, 0.5, true},
                             {"z_max", 0.1, 0.3, false}};
    return params;
  }

  double
  pull(const double t)
  {
    const double s = std::sin(pi * t / 4.0);
    return t < 4.0 ? -0.5 * s * s : 0.0;
  }
} // namespace

TEST_CASE("dynamic step with viscosity and dashpots: consistent tangent",
          "[mechanics][dynamics][fd]")
{
  test_support::GuccioneBox bar(dealii::Point<3>(4, 1, 1),
                                {{4, 1, 1}},
                                damped_bar_parameters(0.8),
                                20.0);
  auto                     &problem = *bar.problem;
  problem.start_dynamics(0.0, 0.0);
  problem.set_time_step(0.5);
  for (const double t : {0.5, 1.0, 1.5, 2.0})
    {
      problem.solve(pull(t), 3.0);
      problem.accept_time_step(pull(t), 3.0);
    }
  // Moving, away from the solution of the next step, with an active stress.
  REQUIRE(problem.kinetic_energy() > 0.0);
  const double e1 = systole::Mechanics::ProblemChecks::tangent_error(problem,
                                                                     pull(2.5),
                                                                     3.0,
                                                                     1e-3);
  const double e2 = systole::Mechanics::ProblemChecks::tangent_error(problem,
                                                                     pull(2.5),
                                                                     3.0,
                                                                     1e-4);
  INFO("tangent errors " << e1 << ", " << e2);
  CHECK(e2 < 1e-6);
  CHECK(std::log10(e1 / e2) == Approx(2.0).margin(0.2));
}

TEST_CASE("a stiff block on a spring-dashpot support is a damped oscillator",
          "[mechanics][dynamics]")
{
  // 1 mm cube, density 1 mg/mm^3 (m = 1 mg), support on x = 0 with alpha A
  // = 0.01 mN/mm and beta A = 0.01 mN ms/mm: omega_0 = sqrt(alpha A / m) =
  // 0.1 /ms, zeta = beta A / (2 sqrt(alpha A m)) = 0.05. The block (P-wave
  // modulus about 21 kPa) is 2000 times stiffer than the spring, so it
  // moves as a rigid body to about 1e-4.
  const double alpha = 0.01, beta = 0.01, mass = 1.0, area = 1.0;
  const double omega_0 = std::sqrt(alpha * area / mass);
  const double zeta    = beta * area / (2 * std::sqrt(alpha * area * mass));
  const double omega_d = omega_0 * std::sqrt(1 - zeta * zeta);
  const double u0      = 0.05; // initial translation [mm]

  Mechanics::Parameters params;
  params.fixed_boundaries  = {};
  params.pressure_boundary = "";
  params.linear_solver     = "direct";
  params.density           = mass;
  params.spectral_radius   = 0.8;
  params.viscosity         = 0.1; // damps the block's own modes
  params.robin_supports    = {{"x_min", alpha, beta, false}};
  test_support::GuccioneBox block(dealii::Point<3>(1, 1, 1),
                                  {{1, 1, 1}},
                                  params,
                                  20.0);
  auto                     &problem = *block.problem;
  problem.set_displacement(
    dealii::Functions::ConstantFunction<3>(std::vector<double>{u0, 0, 0}));
  problem.start_dynamics(0.0, 0.0);

  const double           period = 2 * pi / omega_d;
  const double           dt     = period / 100;
  const dealii::Point<3> centre(0.5, 0.5, 0.5);
  std::vector<double>    t_values{0.0}, u_values{u0};
  problem.set_time_step(dt);
  double largest_error = 0;
  for (unsigned int i = 1; i <= 250; ++i)
    {
      const double t = i * dt;
      problem.solve(0.0, 0.0);
      problem.accept_time_step(0.0, 0.0);
      const double u = problem.deformed_positions({centre})[0][0] - centre[0];
      const double exact = u0 * std::exp(-zeta * omega_0 * t) *
                           (std::cos(omega_d * t) +
                            zeta * omega_0 / omega_d * std::sin(omega_d * t));
      largest_error = std::max(largest_error, std::abs(u - exact));
      t_values.push_back(t);
      u_values.push_back(u);
    }
  // Upward zero crossings (linear interpolation) give the damped period,
  // the maxima between them the decay rate.
  std::vector<double> crossings, peaks;
  for (unsigned int i = 1; i < u_values.size(); ++i)
    if (u_values[i - 1] < 0 && u_values[i] >= 0)
      crossings.push_back(t_values[i - 1] + (t_values[i] - t_values[i - 1]) *
                                              (-u_values[i - 1]) /
                                              (u_values[i] - u_values[i - 1]));
  for (unsigned int i = 1; i + 1 < u_values.size(); ++i)
    if (u_values[i] > u_values[i - 1] && u_values[i] >= u_values[i + 1] &&
        u_values[i] > 0)
      peaks.push_back(u_values[i]);
  REQUIRE(crossings.size() >= 2);
  REQUIRE(peaks.size() >= 2);
  const double measured_period =
    (crossings.back() - crossings.front()) / (crossings.size() - 1);
  const double decay_rate =
    std::log(peaks.front() / peaks.back()) / ((peaks.size() - 1) * period);
  INFO("largest |u - exact| " << largest_error << " mm of " << u0 << "; period "
                              << measured_period << " ms (exact " << period
                              << "), decay rate " << decay_rate
                              << " /ms (exact " << zeta * omega_0 << ")");
  // The scheme's period error, about (omega dt)^2 / 12 = 3e-4, shifts the
  // phase by 0.6 % of the amplitude over the 2.5 periods.
  CHECK(largest_error < 0.015 * u0);
  CHECK(measured_period == Approx(period).epsilon(2e-3));
  CHECK(decay_rate == Approx(zeta * omega_0).epsilon(0.02));
}

TEST_CASE("viscous energy balance: kinetic + strain + dissipated = work",
          "[mechanics][dynamics]")
{
  // The largest |E_kin + E_strain + E_support + D - W| over 10 ms, relative
  // to the largest work, for two steps.
  const auto defect = [](const double dt, double &dissipated_fraction) {
    test_support::GuccioneBox bar(dealii::Point<3>(4, 1, 1),
                                  {{4, 1, 1}},
                                  damped_bar_parameters(1.0),
                                  20.0);
    auto                     &problem = *bar.problem;
    problem.start_dynamics(0.0, 0.0);
    problem.set_time_step(dt);
    const auto pressures = [](const double t) {
      return dealii::Vector<double>(1) = pull(t);
    };
    auto       powers = problem.accepted_powers(pressures(0.0), 0.0);
    double     work = 0, dissipated = 0, largest = 0, largest_work = 0;
    const auto n = static_cast<unsigned int>(std::lround(10.0 / dt));
    for (unsigned int i = 1; i <= n; ++i)
      {
        const double t = i * dt;
        problem.solve(pull(t), 0.0);
        problem.accept_time_step(pull(t), 0.0);
        const auto next = problem.accepted_powers(pressures(t), 0.0);
        work += 0.5 * dt * (powers.loads + next.loads);
        dissipated += 0.5 * dt * (powers.dissipation + next.dissipation);
        powers              = next;
        const double stored = problem.kinetic_energy() +
                              problem.strain_energy() +
                              problem.support_energy();
        largest      = std::max(largest, std::abs(stored + dissipated - work));
        largest_work = std::max(largest_work, std::abs(work));
      }
    dissipated_fraction = dissipated / work;
    return largest / largest_work;
  };
  double       fraction_coarse, fraction_fine;
  const double coarse = defect(0.125, fraction_coarse);
  const double fine   = defect(0.0625, fraction_fine);
  INFO("relative energy defect " << coarse << " (dt = 0.125 ms), " << fine
                                 << " (dt = 0.0625 ms); dissipated fraction of "
                                    "the work "
                                 << fraction_fine);
  CHECK(fraction_fine > 0.2);
  CHECK(coarse < 2e-2);
  CHECK(fine < 0.35 * coarse);
}
