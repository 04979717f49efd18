// The TAO least-squares wrapper on problems with known answers: a straight
// line (closed-form estimate and covariance), an exponential with exact data
// (recovered to round-off), and an active bound.
#include "inverse/least_squares.h"
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace systole;

namespace
{
  const std::vector<double> t    = {0, 1, 2, 3, 4, 5};
  const std::vector<double> line = {1.1, 2.9, 5.2, 6.8, 9.1, 11.0};
} // namespace

TEST_CASE("Least squares fits a line with the textbook covariance",
          "[inverse][least_squares]")
{
  // r_i = c0 + c1 t_i - y_i: linear, so Gauss-Newton's first step solves it.
  Inverse::LeastSquaresProblem problem;
  problem.n_residuals = t.size();
  problem.initial     = {0.5, 0.5};
  problem.lower       = {-100, -100};
  problem.upper       = {100, 100};
  problem.evaluate    = [](const std::vector<double> &x,
                        std::vector<double>       &r,
                        std::vector<double>       *J) {
    for (unsigned int i = 0; i < t.size(); ++i)
      {
        r[i] = x[0] + x[1] * t[i] - line[i];
        if (J)
          {
            (*J)[2 * i]     = 1;
            (*J)[2 * i + 1] = t[i];
          }
      }
  };
  const auto fit = Inverse::solve_least_squares(problem, {});

  // Closed form: c1 = Sxy / Sxx, c0 = ybar - c1 tbar; var(c1) = s^2 / Sxx,
  // var(c0) = s^2 (1/n + tbar^2 / Sxx), s^2 = RSS / (n - 2).
  const double n    = t.size();
  double       tbar = 0, ybar = 0;
  for (unsigned int i = 0; i < t.size(); ++i)
    tbar += t[i] / n, ybar += line[i] / n;
  double Sxx = 0, Sxy = 0;
  for (unsigned int i = 0; i < t.size(); ++i)
    Sxx += (t[i] - tbar) * (t[i] - tbar),
      Sxy += (t[i] - tbar) * (line[i] - ybar);
  const double c1 = Sxy / Sxx, c0 = ybar - c1 * tbar;
  double       rss = 0;
  for (unsigned int i = 0; i < t.size(); ++i)
    rss += std::pow(c0 + c1 * t[i] - line[i], 2);
  const double s2 = rss / (n - 2);

  REQUIRE(fit.converged);
  CHECK(fit.x[0] == Approx(c0).epsilon(1e-6));
  CHECK(fit.x[1] == Approx(c1).epsilon(1e-6));
  CHECK(fit.sigma2 == Approx(s2).epsilon(1e-5));
  CHECK(fit.standard_deviation[1] == Approx(std::sqrt(s2 / Sxx)).epsilon(1e-5));
  CHECK(fit.standard_deviation[0] ==
        Approx(std::sqrt(s2 * (1 / n + tbar * tbar / Sxx))).epsilon(1e-5));
  // Covariance of c0 and c1: -tbar s^2 / Sxx.
  CHECK(fit.covariance[1] == Approx(-tbar * s2 / Sxx).epsilon(1e-5));
  // Student's t_{0.975} with 4 degrees of freedom: 2.776445 (tables).
  CHECK(fit.t_quantile == Approx(2.776445).epsilon(1e-6));
  CHECK(fit.upper_95[1] - fit.x[1] ==
        Approx(2.776445 * fit.standard_deviation[1]).epsilon(1e-6));
}

TEST_CASE("Least squares recovers an exponential from exact data",
          "[inverse][least_squares]")
{
  // y = 2 exp(0.3 t), started at (1, 0.1).
  Inverse::LeastSquaresProblem problem;
  problem.n_residuals = t.size();
  problem.initial     = {1, 0.1};
  problem.lower       = {0.01, 0.01};
  problem.upper       = {10, 1};
  unsigned int calls  = 0;
  problem.evaluate    = [&](const std::vector<double> &x,
                         std::vector<double>       &r,
                         std::vector<double>       *J) {
    ++calls;
    for (unsigned int i = 0; i < t.size(); ++i)
      {
        const double e = std::exp(x[1] * t[i]);
        r[i]           = x[0] * e - 2 * std::exp(0.3 * t[i]);
        if (J)
          {
            (*J)[2 * i]     = e;
            (*J)[2 * i + 1] = x[0] * t[i] * e;
          }
      }
  };
  const auto fit = Inverse::solve_least_squares(problem, {});
  CHECK(fit.x[0] == Approx(2).epsilon(1e-7));
  CHECK(fit.x[1] == Approx(0.3).epsilon(1e-7));
  CHECK(fit.residual_norm < 1e-6);
  CHECK(fit.evaluations == calls);
  CHECK_FALSE(fit.at_bound[0]);
}

TEST_CASE("Least squares stops at an active bound", "[inverse][least_squares]")
{
  // min (x0 - 3)^2 + (x1 - 1)^2 + (x0 + x1 - 4)^2 with x0 <= 2: at x0 = 2
  // the best x1 solves (x1 - 1) + (x1 - 2) = 0, x1 = 1.5.
  Inverse::LeastSquaresProblem problem;
  problem.n_residuals = 3;
  problem.initial     = {1, 1};
  problem.lower       = {0, 0};
  problem.upper       = {2, 5};
  problem.evaluate    = [](const std::vector<double> &x,
                        std::vector<double>       &r,
                        std::vector<double>       *J) {
    r = {x[0] - 3, x[1] - 1, x[0] + x[1] - 4};
    if (J)
      *J = {1, 0, 0, 1, 1, 1};
  };
  const auto fit = Inverse::solve_least_squares(problem, {});
  CHECK(fit.x[0] == Approx(2).epsilon(1e-8));
  CHECK(fit.x[1] == Approx(1.5).epsilon(1e-6));
  CHECK(fit.at_bound[0]);
  CHECK_FALSE(fit.at_bound[1]);
}

TEST_CASE("Least squares stops once the residual is within its tolerance",
          "[inverse][least_squares]")
{
  // The exponential of the exact-data case: with a residual tolerance the fit
  // stops (TAO_CONVERGED_USER) at the first iterate with |r| below it, in
  // fewer evaluations than without, and |r| is then at most the tolerance.
  const auto run = [](const double tolerance) {
    Inverse::LeastSquaresProblem problem;
    problem.n_residuals = t.size();
    problem.initial     = {1, 0.1};
    problem.lower       = {0.01, 0.01};
    problem.upper       = {10, 1};
    problem.evaluate    = [](const std::vector<double> &x,
                          std::vector<double>       &r,
                          std::vector<double>       *J) {
      for (unsigned int i = 0; i < t.size(); ++i)
        {
          const double e = std::exp(x[1] * t[i]);
          r[i]           = x[0] * e - 2 * std::exp(0.3 * t[i]);
          if (J)
            {
              (*J)[2 * i]     = e;
              (*J)[2 * i + 1] = x[0] * t[i] * e;
            }
        }
    };
    Inverse::LeastSquaresSettings settings;
    settings.residual_tolerance = tolerance;
    return Inverse::solve_least_squares(problem, settings);
  };
  const auto loose = run(1e-2);
  const auto tight = run(0);
  CHECK(loose.converged);
  CHECK(loose.reason == "CONVERGED_USER");
  CHECK(loose.residual_norm <= 1e-2);
  CHECK(loose.evaluations < tight.evaluations);
  CHECK(tight.residual_norm < 1e-6);
}
