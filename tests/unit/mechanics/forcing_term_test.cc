// Eisenstat-Walker forcing terms (src/mechanics/forcing_term.h) on an
// inexact Newton iteration whose linear solves err by exactly the tolerance
// asked: it must still reach the nonlinear tolerance in about as many
// iterations as exact Newton, with far fewer digits of linear accuracy.
#include "mechanics/forcing_term.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

namespace
{
  using systole::Mechanics::ForcingTerm;

  /// F_i(x) = x_i + x_i^3 / 2 - b_i: n uncoupled cubic equations.
  struct Cubic
  {
    std::vector<double> b;

    std::vector<double>
    residual(const std::vector<double> &x) const
    {
      std::vector<double> r(x.size());
      for (unsigned int i = 0; i < x.size(); ++i)
        r[i] = x[i] + 0.5 * x[i] * x[i] * x[i] - b[i];
      return r;
    }
  };

  double
  norm(const std::vector<double> &v)
  {
    double s = 0.0;
    for (const double x : v)
      s += x * x;
    return std::sqrt(s);
  }

  struct Outcome
  {
    unsigned int iterations = 0;
    /// Sum of log10(1 / eta): the digits the linear solves gained, which a
    /// Krylov solver with a fixed contraction pays for in proportion.
    double digits    = 0.0;
    bool   converged = false;
  };

  /// How iterate() runs.
  struct Run
  {
    /// The start x = start * x* (x* the solution).
    double start = 0.0;
    /// Converged at |F| <= tolerance |F_0|.
    double tolerance = 1e-10;
    /// If > 0, every update to this eta instead of the forcing term's.
    double fixed_eta = 0.0;
    /// Chord iterations on the Jacobian at the start (else Newton).
    bool chords = false;
    /// Whether the forcing term is told the updates are chords.
    bool told = false;
  };

  /// Inexact Newton (or chord) iterations on the cubic: each update solves
  /// J du = -F only to |J du + F| = eta |F| (the error along the worst
  /// direction: the first component's, the slowest to converge).
  Outcome
  iterate(const Run &run)
  {
    Cubic               problem{{3.0, -2.0, 0.5, 8.0, -6.0}};
    std::vector<double> x(problem.b.size()), start_jacobian(x.size());
    for (unsigned int i = 0; i < x.size(); ++i)
      {
        double y = 0.0; // x* by Newton on the scalar equation
        for (unsigned int k = 0; k < 60; ++k)
          y -= (y + 0.5 * y * y * y - problem.b[i]) / (1.0 + 1.5 * y * y);
        x[i]              = run.start * y;
        start_jacobian[i] = 1.0 + 1.5 * x[i] * x[i];
      }
    auto         r      = problem.residual(x);
    const double target = run.tolerance * norm(r);
    ForcingTerm  forcing(1e-12);
    Outcome      outcome;
    for (; outcome.iterations < 60; ++outcome.iterations)
      {
        const double r_norm = norm(r);
        if (r_norm <= target)
          {
            outcome.converged = true;
            break;
          }
        const double eta = run.fixed_eta > 0.0
                             ? run.fixed_eta
                             : forcing.next(r_norm, target, run.told);
        outcome.digits += std::log10(1.0 / eta);
        for (unsigned int i = 0; i < x.size(); ++i)
          {
            const double jacobian =
              run.chords ? start_jacobian[i] : 1.0 + 1.5 * x[i] * x[i];
            // The linear residual J du + F = e, |e| = eta |F|, along x_0.
            const double error = i == 0 ? eta * r_norm : 0.0;
            x[i] += (-r[i] + error) / jacobian;
          }
        r = problem.residual(x);
      }
    return outcome;
  }

  /// Newton from x = 0 to 1e-10, each update to @p fixed_eta if > 0, else
  /// to the forcing term's.
  Outcome
  solve(const double fixed_eta)
  {
    return iterate({0.0, 1e-10, fixed_eta, false, false});
  }

  /// Chord iterations on the Jacobian at x = 0.99 x* to 1e-12; @p told:
  /// the forcing term knows the updates are chords.
  Outcome
  chords(const bool told)
  {
    return iterate({0.99, 1e-12, 0.0, true, told});
  }
} // namespace

TEST_CASE("Forcing terms: the safeguards", "[forcing_term]")
{
  ForcingTerm forcing(1e-8);
  // The first solve: eta_max.
  CHECK(forcing.next(100.0, 1e-6) == ForcingTerm::eta_max);
  // A residual cut 100-fold: 0.9 * 1e-4 (0.9 * 0.1^2 = 9e-3 < 0.1, so the
  // previous eta does not hold it up).
  CHECK(forcing.next(1.0, 1e-6) == Approx(0.9e-4).epsilon(1e-12));
  // Quadratic convergence would ask 0.9 * (1e-4)^2 = 9e-9; the nonlinear
  // tolerance 1e-8 needs only 0.5 * 1e-8 / 1e-4 = 5e-5.
  CHECK(forcing.next(1e-4, 1e-8) == Approx(5e-5).epsilon(1e-12));
  // A slow step (residual cut twofold) relaxes it to eta_max: 0.9 * 0.25
  // is above it.
  CHECK(forcing.next(5e-5, 1e-16) == ForcingTerm::eta_max);
  // After eta_max, a 1000-fold cut asks 0.9 * 1e-6 at once.
  CHECK(forcing.next(5e-8, 1e-16) == Approx(0.9e-6).epsilon(1e-12));

  // A chord update (on the last tangent) converges linearly: a tenth of the
  // last contraction, 0.1 * 1e-3, where choice 2 asks 0.9 * 1e-6.
  ForcingTerm chord(1e-12);
  chord.next(1.0, 1e-12);
  CHECK(chord.next(1e-3, 1e-12, true) == Approx(1e-4).epsilon(1e-12));
  // A slow chord (a contraction of 0.5) at eta_max.
  CHECK(chord.next(5e-4, 1e-12, true) == ForcingTerm::eta_max);

  // The floor: never below the solver's own tolerance.
  ForcingTerm floored(1e-3);
  floored.next(1.0, 1e-12);
  CHECK(floored.next(1e-6, 1e-12) == 1e-3);
  // A floor above eta_max wins.
  ForcingTerm loose(0.5);
  CHECK(loose.next(1.0, 1e-12) == 0.5);
}

TEST_CASE("Forcing terms: inexact Newton converges with fewer linear digits",
          "[forcing_term]")
{
  const Outcome exact   = solve(1e-12);
  const Outcome inexact = solve(0.0);
  REQUIRE(exact.converged);
  REQUIRE(inexact.converged);
  // At most two more Newton iterations than (nearly) exact solves ...
  CHECK(inexact.iterations <= exact.iterations + 2);
  // ... for less than half the linear accuracy in all.
  CHECK(inexact.digits < 0.5 * exact.digits);
  // A fixed loose tolerance converges only linearly: more iterations.
  const Outcome loose = solve(0.1);
  CHECK(loose.iterations > inexact.iterations);
}

TEST_CASE("Forcing terms: chords need no solve tighter than their rate",
          "[forcing_term]")
{
  const Outcome aware = chords(true), blind = chords(false);
  REQUIRE(aware.converged);
  REQUIRE(blind.converged);
  // The linear rate of the chords, not the solves, sets their number ...
  CHECK(aware.iterations <= blind.iterations + 1);
  // ... and Eisenstat-Walker's choice 2 alone solves them too accurately
  // (7 chords each; 18.0 linear digits against 21.9).
  CHECK(aware.digits < 0.85 * blind.digits);
}
