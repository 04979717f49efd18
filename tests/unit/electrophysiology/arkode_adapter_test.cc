// ImexIntegrator (the ARKode adapter) on a small stiff system with a known
// solution: convergence order, adaptive steps, error propagation.
#include <deal.II/base/index_set.h>

#include "electrophysiology/arkode_adapter.h"

#include <catch2/catch.hpp>
#include <petscvec.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

using namespace systole;
using namespace systole::Electrophysiology;

namespace
{
  constexpr double lambda = 50.0; // stiff implicit decay rate [1/ms]

  /// y = (a, b): a' = -lambda a + cos t (implicit: -lambda a), b' = -b
  /// (explicit). Exact: b = e^-t, a = (lambda cos t + sin t)/(lambda^2 + 1)
  /// + (1 - lambda/(lambda^2 + 1)) e^(-lambda t) from a(0) = b(0) = 1.
  ImexIntegrator::Callbacks
  test_system(unsigned int *solves = nullptr)
  {
    ImexIntegrator::Callbacks c;
    c.explicit_rhs =
      [](const double t, const LA::MPI::Vector &y, LA::MPI::Vector &f) {
        f(0) = std::cos(t);
        f(1) = -y(1);
        f.compress(dealii::VectorOperation::insert);
      };
    c.implicit_rhs = [](const LA::MPI::Vector &y, LA::MPI::Vector &f) {
      f(0) = -lambda * y(0);
      f(1) = 0;
      f.compress(dealii::VectorOperation::insert);
    };
    c.solve = [solves](const double           gamma,
                       const LA::MPI::Vector &b,
                       LA::MPI::Vector       &x) {
      x(0) = b(0) / (1 + gamma * lambda);
      x(1) = b(1);
      x.compress(dealii::VectorOperation::insert);
      if (solves)
        ++*solves;
    };
    return c;
  }

  double
  exact_a(const double t)
  {
    const double l2 = lambda * lambda + 1;
    return (lambda * std::cos(t) + std::sin(t)) / l2 +
           (1 - lambda / l2) * std::exp(-lambda * t);
  }

  /// Error in a at t = 1 after fixed steps of dt (advanced step by step).
  double
  error_with_step(const double dt, const unsigned int order)
  {
    ImexIntegrator::Settings s;
    s.order = order;
    ImexIntegrator  ode(s, test_system(), 0.0, MPI_COMM_SELF);
    LA::MPI::Vector y(dealii::complete_index_set(2), MPI_COMM_SELF);
    y                    = 1.0;
    const unsigned int n = std::lround(1.0 / dt);
    for (unsigned int k = 1; k <= n; ++k)
      ode.evolve(y, k * dt);
    CHECK(ode.n_steps() == n);
    CHECK(y(1) == Approx(std::exp(-1.0)).epsilon(1e-3));
    return std::abs(y(0) - exact_a(1.0));
  }
} // namespace

TEST_CASE("ARKode IMEX steps converge at the order of the method",
          "[ep][arkode]")
{
  const unsigned int order = GENERATE(3u, 4u);
  const double       e1    = error_with_step(0.02, order);
  const double       e2    = error_with_step(0.01, order);
  INFO("order " << order << ": errors " << e1 << ", " << e2);
  CHECK(e2 < 1e-5);
  // The stiff transient e^-50t is long gone by t = 1; the observed order
  // is that of the method (ARK-4(2)3 and ARK-6(3)4 of Kennedy-Carpenter).
  CHECK(std::log2(e1 / e2) == Approx(order).margin(0.4));
}

TEST_CASE("Adaptive ARKode steps meet the tolerance, stop at the end time",
          "[ep][arkode]")
{
  ImexIntegrator::Settings s;
  s.adaptive             = true;
  s.relative_tolerance   = 1e-6;
  s.absolute_tolerance   = 1e-8;
  s.max_step             = 0.5;
  unsigned int    solves = 0;
  ImexIntegrator  ode(s, test_system(&solves), 0.0, MPI_COMM_SELF);
  LA::MPI::Vector y(dealii::complete_index_set(2), MPI_COMM_SELF);
  y = 1.0;
  ode.evolve(y, 0.3);
  CHECK(ode.time() == 0.3);
  CHECK(y(0) == Approx(exact_a(0.3)).epsilon(1e-3));
  ode.evolve(y, 2.0);
  CHECK(y(0) == Approx(exact_a(2.0)).epsilon(1e-3));
  CHECK(ode.n_steps() > 4); // the transient needs small steps
  CHECK(solves > 0);

  // Restart from a given state: the same result as going on.
  LA::MPI::Vector z(y);
  ode.evolve(y, 3.0);
  ode.reset(2.0);
  ode.evolve(z, 3.0);
  CHECK(z(0) == Approx(y(0)).epsilon(1e-6));
}

TEST_CASE("Exceptions in the callbacks leave ARKode as themselves",
          "[ep][arkode]")
{
  auto       callbacks = test_system();
  const auto original  = callbacks.explicit_rhs;
  callbacks.explicit_rhs =
    [original](const double t, const LA::MPI::Vector &y, LA::MPI::Vector &f) {
      if (t > 0.25)
        throw std::runtime_error("bad ionic state");
      original(t, y, f);
    };
  ImexIntegrator::Settings s;
  ImexIntegrator           ode(s, callbacks, 0.0, MPI_COMM_SELF);
  LA::MPI::Vector          y(dealii::complete_index_set(2), MPI_COMM_SELF);
  y = 1.0;
  ode.evolve(y, 0.1);
  CHECK_THROWS_WITH(ode.evolve(y, 0.3), "bad ionic state");

  // A recoverable failure with fixed steps cannot be cured: it comes back
  // as itself.
  auto failing  = test_system();
  failing.solve = [](const double, const LA::MPI::Vector &, LA::MPI::Vector &) {
    AssertThrow(false, ExcRecoverableStepFailure("CG did not converge"));
  };
  ImexIntegrator other(s, failing, 0.0, MPI_COMM_SELF);
  y = 1.0;
  CHECK_THROWS_AS(other.evolve(y, 0.1), ExcRecoverableStepFailure);
}

namespace
{
  /// N decoupled explicit components y_i' = -lambda_i (y_i - g) + g' that
  /// follow the slow g(t) = cos(t/100) exactly from y_i(0) = 1 (as the
  /// plateau potential, smooth enough for steps of 2 ms): rate 1/ms,
  /// except component 0 at 3/ms (as the one node of a monodomain plateau
  /// that activated last). The implicit part is 0.
  struct StiffComponent
  {
    static constexpr unsigned int n            = 20000;
    static constexpr double       lambda_rest  = 1.0;
    static constexpr double       lambda_stiff = 3.0;

    static double
    g(const double t)
    {
      return std::cos(t / 100);
    }

    static double
    rate(const unsigned int i)
    {
      return i == 0 ? lambda_stiff : lambda_rest;
    }

    ImexIntegrator::Callbacks
    callbacks(const bool with_stiffness) const
    {
      ImexIntegrator::Callbacks c;
      c.explicit_rhs = [](const double           t,
                          const LA::MPI::Vector &y_vector,
                          LA::MPI::Vector       &f) {
        const Vec     y = static_cast<const Vec &>(y_vector);
        const double *values;
        double       *out;
        VecGetArrayRead(y, &values);
        VecGetArray(static_cast<const Vec &>(f), &out);
        for (unsigned int i = 0; i < n; ++i)
          out[i] = -rate(i) * (values[i] - g(t)) - std::sin(t / 100) / 100;
        VecRestoreArray(static_cast<const Vec &>(f), &out);
        VecRestoreArrayRead(y, &values);
      };
      c.implicit_rhs = [](const LA::MPI::Vector &, LA::MPI::Vector &f) {
        f = 0;
      };
      c.solve = [](const double, const LA::MPI::Vector &b, LA::MPI::Vector &x) {
        x = b;
      };
      if (with_stiffness)
        c.explicit_stiffness = [](const LA::MPI::Vector &) {
          return lambda_stiff;
        };
      return c;
    }
  };

  /// Largest |y_i - g| over the components at the ends of 2 ms intervals
  /// up to 100 ms, adaptive steps of at most 2 ms at the default
  /// tolerances.
  double
  largest_error(const bool     with_stiffness,
                unsigned long &steps,
                unsigned long &limited,
                double        &beta)
  {
    ImexIntegrator::Settings s;
    s.adaptive = true;
    s.max_step = 2.0;
    StiffComponent system;
    ImexIntegrator ode(s, system.callbacks(with_stiffness), 0.0, MPI_COMM_SELF);
    LA::MPI::Vector y(dealii::complete_index_set(StiffComponent::n),
                      MPI_COMM_SELF);
    y            = 1.0;
    double error = 0;
    for (unsigned int k = 1; k <= 50; ++k)
      {
        const double t = 2.0 * k;
        ode.evolve(y, t);
        const double *values;
        VecGetArrayRead(static_cast<const Vec &>(y), &values);
        for (unsigned int i = 0; i < StiffComponent::n; ++i)
          error = std::max(error, std::abs(values[i] - StiffComponent::g(t)));
        VecRestoreArrayRead(static_cast<const Vec &>(y), &values);
      }
    steps   = ode.n_steps();
    limited = ode.n_stability_limited_steps();
    beta    = ode.explicit_stability_interval();
    return error;
  }
} // namespace

TEST_CASE("Adaptive steps stay within the explicit stability interval of "
          "the stiffest component",
          "[ep][arkode]")
{
  // The error estimate is an RMS norm over the 20 000 components: one
  // component that goes unstable (3/ms at steps of 2 ms, z = -6, outside
  // ARK-4(2)3's explicit interval [-3.66, 0]) weighs 1/141 of its error, so
  // it grows far past the tolerance while the steps stay long (measured:
  // 0.21, 101 steps). The explicit stiffness keeps every step, the first
  // included, within 0.9 * beta / rho = 1.1 ms, where every component is
  // stable (measured: 2.5e-5; two steps per 2 ms interval, 125 in all).
  unsigned long steps_bounded = 0, steps_free = 0, limited = 0,
                limited_free = 0;
  double       beta = 0, beta_free = 0;
  const double bounded = largest_error(true, steps_bounded, limited, beta);
  const double free = largest_error(false, steps_free, limited_free, beta_free);
  INFO("largest error " << bounded << " with the stability bound ("
                        << steps_bounded << " steps, " << limited
                        << " set by the bound), " << free << " without ("
                        << steps_free << " steps); beta = " << beta);
  CHECK(beta == Approx(3.664).margin(0.01));
  CHECK(beta_free == 0);
  CHECK(bounded < 1e-4);
  CHECK(free > 1e-2);
  CHECK(limited > steps_bounded / 2);
  CHECK(limited_free == 0);
  CHECK(steps_bounded >= 100);
  CHECK(steps_bounded <= 130);
}

TEST_CASE("ARKode DIRK steps with Newton's method locate a root of the "
          "solution of a nonlinear ODE",
          "[ep][arkode]")
{
  // y' = -y^2 from y(0) = 1: y = 1 / (1 + t), implicit only (a DIRK method,
  // Newton with the exact Jacobian -2 y). The root function g = y - 1/2 has
  // its one root at t = 1, falling.
  ImexIntegrator::Settings s;
  s.order                            = GENERATE(2u, 5u);
  s.adaptive                         = true;
  s.relative_tolerance               = 1e-9;
  s.absolute_tolerances              = {1e-12};
  s.max_step                         = 0.25;
  s.initial_step                     = 0.01;
  unsigned int              n_solves = 0;
  ImexIntegrator::Callbacks c;
  c.nonlinear_implicit_rhs =
    [](const double, const LA::MPI::Vector &y, LA::MPI::Vector &f) {
      f(0) = -y(0) * y(0);
      f.compress(dealii::VectorOperation::insert);
    };
  c.newton_solve = [&n_solves](const double,
                               const LA::MPI::Vector &y,
                               const double           gamma,
                               const LA::MPI::Vector &b,
                               LA::MPI::Vector       &x) {
    x(0) = b(0) / (1 + gamma * 2 * y(0));
    x.compress(dealii::VectorOperation::insert);
    ++n_solves;
  };
  std::vector<double> root_times, root_values;
  std::vector<int>    root_directions;
  c.n_roots = 1;
  c.roots = [](const double, const LA::MPI::Vector &y, std::vector<double> &g) {
    g[0] = y(0) - 0.5;
  };
  c.at_root = [&](const double            t,
                  const LA::MPI::Vector  &y,
                  const std::vector<int> &found) {
    root_times.push_back(t);
    root_values.push_back(y(0));
    root_directions.push_back(found[0]);
  };
  ImexIntegrator  ode(s, c, 0.0, MPI_COMM_SELF);
  LA::MPI::Vector y(dealii::complete_index_set(1), MPI_COMM_SELF);
  y = 1.0;
  ode.evolve(y, 0.6);
  CHECK(root_times.empty());
  ode.evolve(y, 3.0);
  CHECK(y(0) == Approx(0.25).epsilon(1e-6));
  REQUIRE(root_times.size() == 1);
  CHECK(root_times[0] == Approx(1.0).epsilon(1e-6));
  CHECK(root_values[0] == Approx(0.5).epsilon(1e-6));
  CHECK(root_directions[0] == -1);
  CHECK(n_solves > 0);
  CHECK(ode.n_implicit_evaluations() > 0);
  CHECK(ode.n_explicit_evaluations() == 0);
}
