#pragma once

// Internal to src/mechanics: the relative tolerance of each linear solve of
// an inexact Newton method with an iterative linear solver.

#include <algorithm>
#include <cmath>

namespace systole::Mechanics
{
  /// Eisenstat-Walker forcing terms (Eisenstat and Walker 1996, SIAM J. Sci.
  /// Comput. 17:16, choice 2), bounded as Kelley (1995, Iterative Methods
  /// for Linear and Nonlinear Equations, 6.3) bounds them: the Newton update
  /// of residual r_k is solved to a relative linear residual eta_k, with
  ///   eta_k = gamma (r_k / r_{k-1})^alpha  (the first: eta_max),
  ///   eta_k <= eta_max = 0.01 (Eisenstat and Walker allow 0.9; at 0.1 the
  ///   first updates cut |R_u| only 1.4-fold on the incompressible ventricle
  ///   and 1.6-fold on the Q1 beam of GMRES + GAMG, and the beam's adaptive
  ///   load steps, which count Newton iterations, took 14 steps instead of
  ///   6; below 0.1 their safeguard gamma eta_{k-1}^alpha > 0.1 never
  ///   applies),
  ///   eta_k >= 0.5 target / r_k (no more accuracy than the nonlinear
  ///   tolerance @p target needs),
  ///   eta_k >= floor (the solver's own tolerance).
  /// Far from the solution a few Krylov iterations then suffice; near it the
  /// solves tighten as fast as Newton converges, which keeps its rate.
  class ForcingTerm
  {
  public:
    static constexpr double gamma   = 0.9;
    static constexpr double alpha   = 2.0;
    static constexpr double eta_max = 0.01;

    /// @p floor: the tightest tolerance ever asked (Linear solver tolerance).
    explicit ForcingTerm(const double floor)
      : floor(floor)
    {}

    /// The tolerance of the solve for the update at residual norm @p
    /// residual, where Newton stops at @p target.
    double
    next(const double residual, const double target)
    {
      double eta = eta_max;
      if (previous_residual > 0.0 && residual > 0.0)
        eta = gamma * std::pow(residual / previous_residual, alpha);
      if (residual > 0.0)
        eta = std::max(eta, 0.5 * target / residual);
      eta               = std::max(std::min(eta, eta_max), floor);
      previous_residual = residual;
      return eta;
    }

  private:
    double floor;
    double previous_residual = 0.0;
  };
} // namespace systole::Mechanics
