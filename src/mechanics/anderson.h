#pragma once

// Internal to src/mechanics: Anderson acceleration of a fixed-point
// iteration, used on the chord iterations of the Newton solver (newton.cc).

#include <deal.II/lac/vector.h>

#include "base/linear_algebra.h"

#include <deque>

namespace systole::Mechanics
{
  /// Anderson acceleration (Walker and Ni 2011, "type II") of the
  /// fixed-point iteration x_{k+1} = x_k + f(x_k): with the differences of
  /// the last @p depth updates, dF = [f_i - f_{i-1}], and of the iterates,
  /// dX = [x_i - x_{i-1}], the accelerated update is
  ///   f_k - (dX + dF) gamma,  gamma = argmin |f_k - dF gamma|_2.
  /// On a linear iteration with n unknowns and depth >= n it reaches the
  /// fixed point in at most n + 1 updates (it is then GMRES on the
  /// preconditioned system). For the chord iterations f = -K0^-1 R(x) with a
  /// held factorization K0: the error modes that K0 misses contract slowly
  /// (a ratio near 0.4 per iteration on a factorization from the last load
  /// step), and the least-squares step damps them (on Land problem 2 half
  /// the chord iterations to the tolerance).
  class AndersonAcceleration
  {
  public:
    /// @p max_growth: an accelerated update longer than this multiple of
    /// the plain one is not taken (the plain one is, and the history
    /// restarts).
    explicit AndersonAcceleration(const unsigned int depth,
                                  const double       max_growth = 3.0);

    /// (Depth 0: every call is a no-op.)
    /// Forget the history (a new map: new factorization or load).
    void
    reset();

    /// @p f: the plain update at the current iterate; replaced by the
    /// accelerated one. The first update after reset() stays as it is.
    /// @p g, if given: further unknowns' update (the cavity pressures of a
    /// bordered chord iteration), combined with the same coefficients but
    /// not in the least squares (a few unknowns that f's determine).
    void
    accelerate(LA::MPI::Vector &f, dealii::Vector<double> *g = nullptr);

    /// The step x_{k+1} - x_k actually taken (a multiple of the update that
    /// accelerate() returned, if the step was shortened); @p g_step that of
    /// the further unknowns.
    void
    record_step(const LA::MPI::Vector        &step,
                const dealii::Vector<double> *g_step = nullptr);

  private:
    /// Drop every difference.
    void
    clear_history();
    /// Drop the oldest difference of every history.
    void
    pop_oldest();
    /// Append the differences to the last update (and step).
    void
    push_history(const LA::MPI::Vector &f, const dealii::Vector<double> *g);

    const unsigned int          depth;
    const double                max_growth;
    std::deque<LA::MPI::Vector> dF, dX;
    LA::MPI::Vector             last_f, last_step;
    /// The further unknowns' differences and last update and step.
    std::deque<dealii::Vector<double>> dG, dY;
    dealii::Vector<double>             last_g, last_g_step;
    bool                               have_f    = false;
    bool                               have_step = false;
  };
} // namespace systole::Mechanics
