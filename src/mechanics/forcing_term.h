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
  ///   eta_k >= floor (the solver's own tolerance),
  ///   eta_k >= chord_fraction r_k / r_{k-1} for a chord update (on the last
  ///   tangent): a chord contracts |R| linearly, r_{k+1} <= (rho + eta_k)
  ///   r_k with rho the lag of its tangent (Kelley 1995, chapters 5 and 6),
  ///   so a solve tighter than a tenth of rho does not make it converge
  ///   faster; rho is taken as the last contraction r_k / r_{k-1}, which
  ///   after a Newton update predicts the chord's (both are about L |du|:
  ///   Land problem 2 at 511k DOFs, 2.6e-3 and 2.5e-3). Choice 2 alone
  ///   asked gamma rho^2, 6e-6, for the first chord of its last load step
  ///   (24 Krylov iterations); a tenth of rho took 16.
  /// Far from the solution a few Krylov iterations then suffice; near it the
  /// solves tighten as fast as Newton converges, which keeps its rate.
  class ForcingTerm
  {
  public:
    static constexpr double gamma          = 0.9;
    static constexpr double alpha          = 2.0;
    static constexpr double eta_max        = 0.01;
    static constexpr double chord_fraction = 0.1;

    /// @p floor: the tightest tolerance ever asked (Linear solver tolerance).
    explicit ForcingTerm(const double floor)
      : floor(floor)
    {}

    /// The tolerance of the solve for the update at residual norm @p
    /// residual, where Newton stops at @p target; @p chord: the update is
    /// solved on the last tangent.
    double
    next(const double residual, const double target, const bool chord = false)
    {
      double eta = eta_max;
      if (previous_residual > 0.0 && residual > 0.0)
        {
          const double rate = residual / previous_residual;
          eta               = gamma * std::pow(rate, alpha);
          if (chord)
            eta = std::max(eta, chord_fraction * rate);
        }
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
