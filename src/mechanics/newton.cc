#include "mechanics/newton.h"

#include "base/errors.h"
#include "mechanics/problem_impl.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole::Mechanics
{
  namespace
  {
    /// Solve the small dense system A x = b by Gaussian elimination with
    /// partial pivoting (@p A and @p b are overwritten; x = b / A for one
    /// unknown). False if A is singular or a result is not finite.
    bool
    solve_small_system(dealii::FullMatrix<double> &A,
                       dealii::Vector<double>     &b,
                       dealii::Vector<double>     &x)
    {
      const unsigned int k = b.size();
      for (unsigned int c = 0; c < k; ++c)
        {
          unsigned int pivot = c;
          for (unsigned int r = c + 1; r < k; ++r)
            if (std::abs(A(r, c)) > std::abs(A(pivot, c)))
              pivot = r;
          if (!(std::isfinite(A(pivot, c)) && A(pivot, c) != 0.0))
            return false;
          if (pivot != c)
            {
              for (unsigned int j = 0; j < k; ++j)
                std::swap(A(c, j), A(pivot, j));
              std::swap(b[c], b[pivot]);
            }
          for (unsigned int r = c + 1; r < k; ++r)
            {
              const double factor = A(r, c) / A(c, c);
              for (unsigned int j = c; j < k; ++j)
                A(r, j) -= factor * A(c, j);
              b[r] -= factor * b[c];
            }
        }
      x.reinit(k);
      for (unsigned int c = k; c-- > 0;)
        {
          double sum = b[c];
          for (unsigned int j = c + 1; j < k; ++j)
            sum -= A(c, j) * x[j];
          x[c] = sum / A(c, c);
          if (!std::isfinite(x[c]))
            return false;
        }
      return true;
    }

    /// The update of the bordered system [K -B; D^T -W'] [du; dp] = -[R; g]
    /// (B the loads per unit pressure, D = dV/du the volume rows: D = B
    /// unless a lid moves) from the back substitutions with one
    /// factorization of K: @p du = w_R (K w_R = -R) on entry, @p w[j] =
    /// K^-1 b_j. Solves the k x k system (D^T w - W') dp = -(g + D^T w_R)
    /// and adds w dp to @p du. The dot products d_i . w use the constrained
    /// entries of the distributed w: d is condensed (zero there), so they
    /// are d^T K^-1 b. False (and @p du unchanged) if the Schur complement
    /// is singular.
    bool
    bordered_update(const std::vector<LA::MPI::Vector> &D,
                    const std::vector<LA::MPI::Vector> &w,
                    const dealii::Vector<double>       &g,
                    const dealii::FullMatrix<double>   &dW_dp,
                    LA::MPI::Vector                    &du,
                    dealii::Vector<double>             &dp)
    {
      const unsigned int         k = D.size();
      dealii::FullMatrix<double> schur(k, k);
      dealii::Vector<double>     rhs(k);
      for (unsigned int i = 0; i < k; ++i)
        {
          rhs[i] = -(g[i] + D[i] * du);
          for (unsigned int j = 0; j < k; ++j)
            schur(i, j) = D[i] * w[j] - dW_dp(i, j);
        }
      if (!solve_small_system(schur, rhs, dp))
        return false;
      for (unsigned int j = 0; j < k; ++j)
        du.add(dp[j], w[j]);
      return true;
    }

    /// "<what>; |R_u| = ..., |R_p|/|V_body| = ..., |dV|/V = ...": the
    /// residual of every block, for the message of a failed solve.
    std::string
    with_block_residuals(const std::string           &what,
                         const std::array<double, 2> &residual,
                         const bool                   mixed,
                         const double                 body_volume,
                         const bool                   bordered,
                         const double                 volume_error)
    {
      std::ostringstream o;
      o << what << std::scientific << std::setprecision(3)
        << "; |R_u| = " << residual[0];
      if (mixed)
        o << ", |R_p|/|V_body| = " << residual[1] / body_volume;
      if (bordered)
        o << ", |dV|/V = " << volume_error;
      return o.str();
    }

    /// The depth of the Anderson acceleration of a solve's chord
    /// iterations: the entry's, but in a volume-constrained solve (where only
    /// the chords that start it on an earlier factorization are accelerated)
    /// only an explicit one: auto leaves them plain (the BiV heartbeat took
    /// 5 % more iterations accelerated, the LV ones 2-3 % fewer,
    /// docs/verification.md).
    unsigned int
    chord_acceleration_depth(const Parameters &p, const bool bordered)
    {
      return bordered && p.chord_acceleration_auto ? 0
                                                   : p.chord_acceleration_depth;
    }
  } // namespace

  // (The one place that sees both: the solver works on the NewtonSystem.)
  NewtonReport
  Problem::Impl::newton(dealii::Vector<double>      &pressures,
                        const double                 active_tension,
                        const Problem::VolumeTarget *target)
  {
    return NewtonSolver(*this, pressures, active_tension, target).solve();
  }

  NewtonSolver::NewtonSolver(NewtonSystem                &problem,
                             dealii::Vector<double>      &pressures,
                             const double                 active_tension,
                             const Problem::VolumeTarget *target)
    : m(problem)
    , pressures(pressures)
    , active_tension(active_tension)
    , target(target)
    , bordered(target != nullptr)
    , mixed(problem.layout().mixed())
    , k(bordered ? problem.n_cavities() : 0)
    , out(problem.log())
    , w_volume(k)
    , target_volume(k)
    , volume_error(k)
    , target_derivative(k, k)
    , assembly_start(problem.seconds_in("Mechanics / assembly"))
    , solver_start(problem.seconds_in("Mechanics / linear solver"))
    // One assembly pass per iteration: outside the bordered solves (whose
    // chord iterations reuse the last factorization, which assembling a
    // tangent discards), the tangent is assembled with the residual at the
    // start and at every trial point, unless the quadratic rate says the
    // trial point will be converged.
    , tangent_ready(!bordered)
    , anderson(
        chord_acceleration_depth(problem.parameters(), target != nullptr))
  {
    problem.reinit_vector(du);
    for (auto &w : w_volume)
      problem.reinit_vector(w);
  }

  std::string
  NewtonSolver::failure(const std::string &what) const
  {
    return with_block_residuals(what,
                                residual,
                                mixed,
                                m.body_volume(),
                                bordered,
                                largest_volume_error());
  }

  double
  NewtonSolver::largest_volume_error() const
  {
    return k == 0 ? 0.0 : volume_error.linfty_norm();
  }

  dealii::Vector<double>
  NewtonSolver::volume_residual() const
  {
    dealii::Vector<double> g(k);
    for (unsigned int i = 0; i < k; ++i)
      g[i] = volume_error[i] * target_volume[i];
    return g;
  }

  void
  NewtonSolver::print_pressures() const
  {
    // "p" for one, "p_1, p_2, ..." else.
    for (unsigned int i = 0; i < pressures.size(); ++i)
      out << (i > 0 ? ", " : "") << pressures[i];
  }

  double
  NewtonSolver::pressure_load(const std::vector<LA::MPI::Vector> &B) const
  {
    // A solve that starts close to equilibrium is not held to a fraction of
    // its tiny first residual.
    double square = 0;
    for (unsigned int i = 0; i < k; ++i)
      {
        const double load = std::abs(pressures[i]) * B[i].l2_norm();
        square += load * load;
      }
    return std::sqrt(square);
  }

  bool
  NewtonSolver::pressure_converged() const
  {
    // The pressure rows are volumes: held to the relative tolerance times
    // the volume of the body.
    return !mixed || residual[1] <= m.parameters().newton_relative_tolerance *
                                      m.body_volume();
  }

  bool
  NewtonSolver::converged(const double reference) const
  {
    const bool u_ok =
      residual[0] <= m.parameters().newton_absolute_tolerance ||
      residual[0] <= m.parameters().newton_relative_tolerance * reference;
    return u_ok && pressure_converged();
  }

  NewtonReport &
  NewtonSolver::converged_now()
  {
    m.factorization().last_solve_converged = true;
    return report;
  }

  bool
  NewtonSolver::assemble(std::array<double, 2> &norms, const bool with_matrix)
  {
    try
      {
        m.assemble(pressures,
                   active_tension,
                   with_matrix,
                   with_matrix && bordered);
        norms = block_norms(m.layout(), m.residual());
        if (bordered)
          {
            dealii::Vector<double> volumes;
            {
              dealii::TimerOutput::Scope scope(m.timers(),
                                               "Mechanics / cavity volume");
              volumes = m.cavity_volumes_now();
            }
            target_volume     = 0;
            target_derivative = 0;
            (*target)(pressures, target_volume, target_derivative);
            AssertThrow(target_volume.size() == k &&
                          target_derivative.m() == k &&
                          target_derivative.n() == k,
                        dealii::ExcMessage(
                          "Mechanics: the volume target must return " +
                          std::to_string(k) + " volumes and their " +
                          std::to_string(k) + " x " + std::to_string(k) +
                          " derivatives."));
            for (unsigned int i = 0; i < k; ++i)
              {
                AssertThrow(target_volume[i] != 0.0,
                            dealii::ExcMessage(
                              "Mechanics: the volume target of the cavity '" +
                              m.pressure_names()[i] +
                              "' is 0 mm^3 (the volume tolerance is "
                              "relative to it)."));
                volume_error[i] =
                  (volumes[i] - target_volume[i]) / target_volume[i];
              }
          }
      }
    catch (const ExcInvertedElement &)
      {
        return false;
      }
    bool finite = std::isfinite(norms[0]) && std::isfinite(norms[1]);
    for (unsigned int i = 0; i < k; ++i)
      {
        finite = finite && std::isfinite(volume_error[i]);
        for (unsigned int j = 0; j < k; ++j)
          finite = finite && std::isfinite(target_derivative(i, j));
      }
    return finite;
  }

  bool
  NewtonSolver::chord_solve(const double tolerance)
  {
    try
      {
        dealii::TimerOutput::Scope scope(m.timers(),
                                         "Mechanics / linear solver");
        m.residual() *= -1.0;
        report.linear_iterations +=
          m.linear_solve(du, m.residual(), 0, 0.0, tolerance);
        return true;
      }
    catch (const dealii::ExceptionBase &)
      {
        return false;
      }
  }

  void
  NewtonSolver::bordered_correction(const std::vector<LA::MPI::Vector> &B,
                                    const std::vector<LA::MPI::Vector> &W,
                                    dealii::Vector<double>             &dp,
                                    const unsigned int                  it,
                                    const double relative)
  {
    AssertThrow(
      bordered_update(B, W, volume_residual(), target_derivative, du, dp),
      ExcNewtonDidNotConverge(
        "the bordered system is singular (B^T K^-1 B - dW/dp)",
        it,
        relative));
  }

  NewtonReport
  NewtonSolver::solve()
  {
    dealii::TimerOutput::Scope scope(m.timers(), "Mechanics / Newton");
    // The factorization of the last solve is worth reusing only if that
    // solve converged (its tangent is that of an iterate near its solution).
    const bool reuse = m.parameters().reuse_factorization &&
                       m.factorization().held &&
                       m.factorization().last_solve_converged;
    m.factorization().last_solve_converged = false;
    ChordStart chords;
    if (bordered && reuse && m.factorization().volume_derivatives.size() == k &&
        bordered_chords(chords))
      return converged_now();

    const bool start_assembled = !bordered && reuse && euler_predictor();
    if (!start_assembled)
      {
        AssertThrow(assemble(residual, tangent_ready),
                    ExcNewtonDidNotConverge("an element is inverted at the "
                                            "start of the load step",
                                            0,
                                            1.0));
        report.initial_residual = residual[0];
      }
    if (!chords.newton_from_there)
      return iterate(start_assembled);
    try
      {
        return iterate(start_assembled);
      }
    catch (const ExcNewtonDidNotConverge &e)
      {
        return retry_from_chord_start(chords, e);
      }
  }

  bool
  NewtonSolver::inexact() const
  {
    return m.parameters().inexact_newton && !bordered &&
           !m.linear_solver().direct();
  }

  double
  NewtonSolver::target_residual() const
  {
    return std::max(m.parameters().newton_absolute_tolerance,
                    m.parameters().newton_relative_tolerance * reference);
  }

  bool
  NewtonSolver::chords_worth_going_on(const double rate) const
  {
    // At a rate of 0.3 or worse, or where more than three more chords would
    // be needed at this rate: Newton from here needs about three iterations
    // (a new tangent, a chord, another tangent: the default heartbeat's
    // solves after chords took 3.2 on average), and some chord solves took
    // nine iterations at rates of 0.2-0.3.
    if (!(rate < 0.3))
      return false;
    const double target = target_residual();
    return residual[0] <= target ||
           std::log(target / residual[0]) / std::log(rate) <= 3.0;
  }

  NewtonReport
  NewtonSolver::retry_from_chord_start(const ChordStart            &start,
                                       const dealii::ExceptionBase &failure)
  {
    // The chords' iterate can lie along a mode the old tangent holds too
    // softly (in the late filling of a variant of the refined default
    // heartbeat, docs/verification.md, Newton from it raised |R_u| 1e22-fold
    // at once, along the torsion): the predicted state is the better start
    // then.
    out << "      (Newton from the chords' iterate failed: "
        << one_line_message(failure) << "; Newton again from their start)"
        << std::endl;
    const unsigned int first_attempt = report.iterations;
    m.set_iterate(start.u);
    pressures           = start.pressures;
    reference           = 0;
    tangent_ready       = false;
    first_factorization = true;
    AssertThrow(assemble(residual, false),
                ExcNewtonDidNotConverge("an element is inverted at the "
                                        "start of the load step",
                                        0,
                                        1.0));
    NewtonReport second = iterate(false);
    second.iterations += first_attempt;
    return second;
  }

  bool
  NewtonSolver::bordered_chords(ChordStart &start)
  {
    // Chord iterations on the factorization of an earlier solve: residual
    // only, one back substitution per iteration, the bordered system of that
    // tangent (its B0 and W0 = K^-1 B0; W and W' of the current pressures);
    // Anderson-accelerated (the pressure updates combined with the
    // displacement's coefficients); left as soon as they stop converging
    // fast.
    const LA::MPI::Vector        u_begin        = m.iterate();
    const dealii::Vector<double> pressure_begin = pressures;
    bool                         ok             = assemble(residual, false);
    const double                 start_residual = residual[0];
    constexpr unsigned int       max_chord_iterations = 12;
    bool                         rose                 = false;
    anderson.reset();
    for (unsigned int it = 0; ok; ++it)
      {
        // The residual where the chords start, not that of a chord that
        // raised it: see iterate().
        reference =
          std::max({reference,
                    start_residual,
                    pressure_load(m.factorization().volume_derivatives)});
        if (largest_volume_error() <= m.parameters().cavity_volume_tolerance &&
            converged(reference))
          {
            report.final_residual   = residual[0];
            report.initial_residual = start_residual;
            return true;
          }
        if (it == max_chord_iterations)
          break;
        if (!chord_solve())
          {
            ok = false;
            break;
          }
        dealii::Vector<double> dp;
        if (!bordered_update(m.factorization().volume_rows,
                             m.factorization().w,
                             volume_residual(),
                             target_derivative,
                             du,
                             dp))
          {
            ok = false;
            break;
          }
        anderson.accelerate(du, &dp);
        m.add_to_iterate(1.0, du);
        pressures += dp;
        anderson.record_step(du, &dp);
        ++report.reused_iterations;
        const double previous = residual[0];
        ok                    = assemble(residual, false);
        out << "      chord " << report.reused_iterations
            << ": |R_u| = " << std::scientific << std::setprecision(3)
            << residual[0];
        if (mixed)
          out << "  |R_p| = " << residual[1];
        out << "  |dV|/V = " << largest_volume_error() << "  p = ";
        print_pressures();
        out << std::defaultfloat << std::endl;
        // (The first iteration mostly corrects the volume, which |R| does
        // not measure: judge the rate from the second on.)
        rose = residual[0] > previous;
        if (ok && it > 0 && !chords_worth_going_on(residual[0] / previous))
          break; // slow: continue with full Newton from here
      }
    // Failed, no better, or the last chord raised |R_u| (the old
    // factorization no longer fits: in the BiV heartbeat's first filling
    // Newton from such an iterate diverged, 1.1e3 -> 2.7e110).
    const bool wasted = !ok || rose || !(residual[0] < start_residual);
    if (wasted)
      {
        // Failed or no better: full Newton from the start.
        m.set_iterate(u_begin);
        pressures = pressure_begin;
      }
    else
      start = {u_begin, pressure_begin, true};
    reference = 0;
    out << "      (" << report.reused_iterations
        << " chord iterations on the old factorization; Newton from "
        << (wasted ? "the start" : "there") << ")" << std::endl;
    return false;
  }

  bool
  NewtonSolver::euler_predictor()
  {
    // Without volume constraints, a solve starts with one chord iteration on
    // the factorization of the last solve: the Euler predictor of the new
    // load (the tangent is that of an iterate near the last solution), for a
    // residual and a back substitution instead of a tangent and a
    // factorization. Newton continues from it unless it inverts an element
    // or the residual is not finite.
    const LA::MPI::Vector u_begin = m.iterate();
    bool                  ok      = assemble(residual, false);
    report.initial_residual       = residual[0];
    ok = ok && chord_solve(inexact() ? ForcingTerm::eta_max : 0.0);
    if (ok)
      {
        // (The first update of the accelerated chord iterations that may
        // continue it; no-ops at depth 0.)
        anderson.reset();
        anderson.accelerate(du);
        anderson.record_step(du);
        if (m.parameters().chord_acceleration_depth > 0)
          last_update_length = du.l2_norm();
        m.add_to_iterate(1.0, du);
        const double start_residual = residual[0];
        // (With the direct solver the residual only: the next update is a
        // chord iteration too if this one cut |R| fast, see iterate().)
        const bool with_tangent = !m.linear_solver().direct();
        ok                      = assemble(residual, with_tangent);
        if (ok)
          {
            reference = start_residual;
            du_norm   = block_norms(m.layout(), du);
            ++report.reused_iterations;
            tangent_ready = with_tangent;
            out << "      chord 1: |R_u| = " << std::scientific
                << std::setprecision(3) << residual[0];
            if (mixed)
              out << "  |R_p|/|V_body| = " << residual[1] / m.body_volume();
            out << std::defaultfloat
                << "  (Euler predictor on the last factorization)" << std::endl;
            return true;
          }
      }
    m.set_iterate(u_begin);
    return false;
  }

  void
  NewtonSolver::log_iteration(const unsigned int           it,
                              const unsigned int           n_chord,
                              const bool                   last_was_chord,
                              const double                 relative,
                              const std::array<double, 2> &u_norm)
  {
    if (last_was_chord)
      out << "      chord  " << std::setw(2) << n_chord;
    else
      out << "      Newton " << std::setw(2) << it - n_chord;
    out << ": |R_u| = " << std::scientific << std::setprecision(3)
        << residual[0] << "  |R_u|/ref = " << relative;
    if (mixed)
      out << "  |R_p|/|V_body| = " << residual[1] / m.body_volume();
    out << "  |du|/|u| = " << du_norm[0] / std::max(u_norm[0], 1e-300);
    if (mixed)
      out << "  |dp|/|p| = " << du_norm[1] / std::max(u_norm[1], 1e-300);
    if (bordered)
      {
        out << "  |dV|/V = " << largest_volume_error() << "  p_cavity = ";
        print_pressures();
      }
    out << std::defaultfloat << std::setprecision(2) << "  (assembly "
        << m.seconds_in("Mechanics / assembly") - assembly_start
        << " s, solver "
        << m.seconds_in("Mechanics / linear solver") - solver_start << " s, "
        << report.linear_iterations << " linear its";
    const long negative = m.linear_solver().negative_pivots();
    if (negative >= 0)
      out << ", " << negative << " negative pivots";
    out << ")" << std::endl;
  }

  NewtonSolver::ChordRules
  NewtonSolver::chord_rules(const bool start_assembled) const
  {
    ChordRules s;
    s.direct            = m.linear_solver().direct();
    s.last_was_chord    = start_assembled;
    s.previous_residual = start_assembled ? report.initial_residual : 0.0;
    s.accelerated =
      s.direct && !bordered && m.parameters().chord_acceleration_depth > 0;
    s.chord_ratio      = s.accelerated ? 0.5 : 0.25;
    s.newton_cut       = s.accelerated ? 0.4 : 0.1;
    s.predictor_chords = start_assembled && s.accelerated;
    s.inexact          = inexact();
    s.forcing          = ForcingTerm(m.parameters().linear_tolerance);
    return s;
  }

  bool
  NewtonSolver::next_is_chord(ChordRules        &s,
                              const unsigned int it,
                              const double       relative)
  {
    // A chord update that raised |R| (accelerated: that cut it less than
    // twofold; further out, where chords stall, an iterate they moved a
    // little can be one Newton diverges from) is undone: Newton from the
    // iterate before it.
    const bool rejected =
      s.undo_chord &&
      residual[0] > (s.accelerated ? s.chord_ratio : 1.0) * s.previous_residual;
    if (rejected)
      {
        m.set_iterate(u_start);
        pressures     = pressure_start;
        tangent_ready = false;
        out << "      (chord iteration undone: |R_u| "
            << (s.accelerated ? "fell less than twofold" : "rose") << ")"
            << std::endl;
      }
    if (rejected || (it > 0 && !s.last_was_chord))
      s.predictor_chords = false;
    s.undo_chord = false;
    return !rejected && m.parameters().reuse_factorization &&
           m.factorization().held && s.previous_residual > 0.0 &&
           (s.direct
              ? s.n_chord < ChordRules::max_chord_iterations &&
                  (s.last_was_chord
                     ? (s.predictor_chords && it == 0) ||
                         residual[0] <= s.chord_ratio * s.previous_residual
                     : relative <= s.newton_cut &&
                         residual[0] <= s.newton_cut * s.previous_residual)
              : it > 0 && s.n_chord < 3 && relative <= 1e-3 &&
                  residual[0] <= 0.1 * s.previous_residual);
  }

  bool
  NewtonSolver::accelerate(const bool              chord,
                           const unsigned int      it,
                           const double            relative,
                           dealii::Vector<double> &dp,
                           const double            chord_ratio)
  {
    // Deuflhard's natural monotonicity test: a chord update at least half as
    // long as the last update says the held tangent no longer contracts
    // here, however much |R_u| fell. (At large rotations |R_u| is no merit
    // function: on the beam of Land problem 1 a chord continuing the
    // predictor cut |R_u| 24-fold with an update of 1.45 |u|, to an iterate
    // Newton then needed 12 iterations from.) It is not taken: Newton from
    // the iterate.
    bool         taken_chord = chord;
    const double length      = du.l2_norm();
    if (chord && !(length <= chord_ratio * last_update_length))
      {
        out << "      (chord update not taken: " << std::setprecision(3)
            << length / last_update_length
            << " times the length of the last update)" << std::endl;
        taken_chord = false;
        assemble(residual, true);
        update(false, it, relative, dp);
      }
    last_update_length = taken_chord ? length : du.l2_norm();
    // The history holds the updates of one factorization: a Newton update
    // starts a new one.
    if (!taken_chord)
      anderson.reset();
    anderson.accelerate(du);
    return taken_chord;
  }

  void
  NewtonSolver::take_step(ChordRules                   &s,
                          const bool                    chord,
                          const unsigned int            it,
                          const double                  relative,
                          const dealii::Vector<double> &dp)
  {
    // Quadratic convergence, |R_k+1| ~ |R_k|^2 (relative): the trial point
    // is expected to be converged, or close enough for a chord iteration, so
    // the tangent there is not needed (nor after a chord iteration, whose
    // factorization the next one reuses). With chord iterations, the tangent
    // waits for the trial point's residual, which says whether the next
    // update needs it.
    const bool trial_tangent =
      !bordered && !chord &&
      !(m.parameters().reuse_factorization && s.direct) &&
      !(relative * relative <=
        std::max(m.parameters().newton_relative_tolerance, 1e-3));
    const double alpha =
      step(dp, trial_tangent, it, relative, !s.newton_done && !chord);
    if (alpha < 1.0)
      ++report.damped_updates;
    s.newton_done = s.newton_done || !chord;
    tangent_ready = trial_tangent;
    if (s.accelerated)
      {
        LA::MPI::Vector taken = du;
        taken *= alpha;
        anderson.record_step(taken);
      }
    du_norm = block_norms(m.layout(), du);
    du_norm[0] *= alpha;
    du_norm[1] *= alpha;
    if (chord)
      ++s.n_chord;
    s.last_was_chord = chord;
  }

  NewtonReport
  NewtonSolver::iterate(const bool start_assembled)
  {
    // Modified Newton with chord iterations on the held factorization
    // (ChordRules: when, next_is_chord()). Neither counts against the
    // Newton iteration limit.
    ChordRules s       = chord_rules(start_assembled);
    report.accelerated = s.accelerated;
    for (unsigned int it = 0;; ++it)
      {
        // The relative tolerance refers to the residual where Newton starts
        // (and to the pressure load), never to an iterate's: an update that
        // overshot (|R_u| 1.1e3 -> 3.0e10 in the isovolumetric contraction
        // of a variant of the refined heartbeat, before a back-off) would
        // make a residual 1e5-fold above the tolerance look converged.
        if (it == 0)
          reference = std::max(reference, residual[0]);
        else
          reference =
            std::max(reference, pressure_load(m.volume_derivatives()));
        const double relative = residual[0] / std::max(reference, 1e-300);
        const auto   u_norm   = block_norms(m.layout(), m.iterate());
        if (it > 0)
          log_iteration(it, s.n_chord, s.last_was_chord, relative, u_norm);
        // (So far: a failure's retry counts them, retry_from_chord_start().)
        report.iterations = it - s.n_chord;
        // Converged: the residual fell by the relative tolerance, or is at
        // the absolute floor, or the last update was at round-off level; and
        // every cavity volume is on its target.
        const bool volume_ok =
          largest_volume_error() <= m.parameters().cavity_volume_tolerance;
        if (volume_ok &&
            ((residual[0] <= m.parameters().newton_absolute_tolerance &&
              pressure_converged()) ||
             (it > 0 &&
              (converged(reference) || du_norm[0] <= 1e-12 * u_norm[0]))))
          {
            report.iterations = it - s.n_chord;
            report.reused_iterations += s.n_chord;
            report.final_residual = residual[0];
            return converged_now();
          }
        // The final message names the residual of every block.
        AssertThrow(
          it - s.n_chord < m.parameters().max_newton_iterations,
          ExcNewtonDidNotConverge(failure(bordered ? "volume-constrained step"
                                                   : "load step"),
                                  it,
                                  relative));

        bool chord = next_is_chord(s, it, relative);
        // The tangent (and dV/du) at this iterate, unless the last pass made
        // it; the residual again.
        if (!tangent_ready && !chord)
          assemble(residual, true);
        s.previous_residual = residual[0];
        tangent_ready       = false;
        dealii::Vector<double> dp(pressures.size());
        update(chord,
               it,
               relative,
               dp,
               s.inexact ? s.forcing.next(residual[0], target_residual(), chord)
                         : 0.0);
        if (s.accelerated)
          chord = accelerate(chord, it, relative, dp, s.chord_ratio);
        s.undo_chord = chord && s.direct;
        take_step(s, chord, it, relative, dp);
      }
  }

  void
  NewtonSolver::update(const bool              chord,
                       const unsigned int      it,
                       const double            relative,
                       dealii::Vector<double> &dp,
                       const double            tolerance)
  {
    // K du = -R; bordered by the volume constraints g = V(u) - W(p):
    // [K -B; B^T -W'] [du; dp] = -[R; g] with B = [dV_i/du]. k + 1 solves
    // with one factorization: K w_R = -R, K w_j = b_j; then the k x k Schur
    // complement (bordered_update).
    dealii::TimerOutput::Scope scope(m.timers(), "Mechanics / linear solver");
    m.residual() *= -1.0;
    if (chord)
      {
        report.linear_iterations +=
          m.linear_solve(du, m.residual(), it, relative, tolerance);
        if (bordered)
          bordered_correction(m.factorization().volume_rows,
                              m.factorization().w,
                              dp,
                              it,
                              relative);
        return;
      }
    try
      {
        {
          dealii::TimerOutput::Scope setup(m.timers(),
                                           "Mechanics / linear solver set-up");
          m.setup_linear_solver();
        }
        if (first_factorization)
          restart_if_indefinite();
        else
          back_off_if_indefinite();
        first_factorization = false;
        m.factorize_low_rank();
        // (Of K alone until the bordered update below stores B0, W0.)
        m.factorization().held = true;
        m.factorization().volume_derivatives.clear();
        m.factorization().volume_rows.clear();
        m.factorization().w.clear();
        m.factorization().u              = m.iterate();
        m.factorization().pressures      = pressures;
        m.factorization().active_tension = active_tension;
        m.remember_factorized_tension();
      }
    catch (const dealii::ExceptionBase &e)
      {
        throw_linear_solver_failure(e, it, relative);
      }
    report.linear_iterations +=
      m.linear_solve(du, m.residual(), it, relative, tolerance);
    if (bordered)
      {
        for (unsigned int j = 0; j < k; ++j)
          report.linear_iterations += m.linear_solve(w_volume[j],
                                                     m.volume_derivatives()[j],
                                                     it,
                                                     relative,
                                                     0.0);
        bordered_correction(m.volume_rows(), w_volume, dp, it, relative);
        m.factorization().volume_derivatives = m.volume_derivatives();
        m.factorization().volume_rows        = m.volume_rows();
        m.factorization().w                  = w_volume;
        m.factorization().held               = true;
      }
  }

  void
  NewtonSolver::restart_if_indefinite()
  {
    // A volume-constrained step (the heartbeat) starts from the predicted
    // displacement. Where the tangent there is indefinite (negative pivots
    // of K, displacement-only formulations), Newton's first update follows
    // the unstable direction: in diastasis a 20 ms step's first update was
    // 0.46 |u| long and the iteration failed (docs/verification.md). Start
    // from the last accepted state instead, whose tangent is that of an
    // equilibrium.
    const long negative = m.linear_solver().negative_pivots();
    if (!bordered || mixed || negative <= 0 || m.solution_history().n_saves < 2)
      return;
    out << "      (the predicted start's tangent has " << negative
        << " negative pivot(s): Newton from the last accepted state)"
        << std::endl;
    m.set_iterate(m.solution_history().u_saved);
    assemble(residual, true);
    reference = std::max(reference, residual[0]);
    m.residual() *= -1.0;
    m.setup_linear_solver();
  }

  void
  NewtonSolver::back_off_if_indefinite()
  {
    // An iterate of a volume-constrained solve whose tangent is indefinite
    // (negative pivots of K, displacement-only formulations) lies past a
    // stability limit that the solution, an equilibrium the heartbeat passes
    // through, does not: Newton from there follows the unstable direction.
    // Measured: of 15 coupled solves with such an iterate in five heartbeat
    // runs, 7 failed, and 7 of their 10 failures had one (docs/
    // verification.md). Back along the last update, halving it, while the
    // tangent stays indefinite (at most three times; if none is definite, on
    // from the full update). As restart_if_indefinite(): within a sequence
    // of solves (two accepted states).
    const long before = m.linear_solver().negative_pivots();
    if (!bordered || mixed || before <= 0 || m.solution_history().n_saves < 2)
      return;
    const LA::MPI::Vector        u_end = m.iterate();
    const dealii::Vector<double> p_end = pressures;
    LA::MPI::Vector              last  = u_end;
    last.add(-1.0, u_start);
    if (pressure_start.size() != pressures.size() || last.linfty_norm() == 0.0)
      return;
    // The iterate at theta along the last update, its residual (negated,
    // as update() expects) and its tangent factorized; false where an
    // element inverts.
    const auto move_to = [&](const double theta) {
      pressures = pressure_start;
      pressures.add(theta, p_end);
      pressures.add(-theta, pressure_start);
      if (theta == 1.0)
        {
          m.set_iterate(u_end);
          pressures = p_end;
        }
      else
        {
          m.set_iterate(u_start);
          m.add_to_iterate(theta, last);
        }
      if (!assemble(residual, true))
        return false;
      m.residual() *= -1.0;
      m.setup_linear_solver();
      return true;
    };
    long   negative = before;
    double theta    = 1.0;
    while (negative > 0 && theta > 0.125)
      {
        theta *= 0.5;
        if (!move_to(theta))
          break;
        negative = m.linear_solver().negative_pivots();
      }
    if (negative > 0)
      {
        theta = 1.0;
        move_to(theta);
        negative = before;
      }
    out << "      (the tangent at the iterate has " << before
        << " negative pivot(s): back to " << theta
        << " of the last update, |R_u| = " << std::scientific
        << std::setprecision(3) << residual[0] << ", " << negative
        << " negative pivot(s) there)" << std::defaultfloat << std::endl;
  }

  double
  NewtonSolver::step(const dealii::Vector<double> &dp,
                     const bool                    with_tangent,
                     const unsigned int            it,
                     const double                  relative,
                     const bool                    guarded)
  {
    // Safeguarded update: halve the step while it inverts an element. (A
    // residual-norm merit test is no use in general: the first iterations
    // of a load step that rotates the body raise |R| by orders of magnitude
    // on their way to the solution.)
    // Guarded (the first Newton update of a solve, from the converged state
    // of a nearby load): a step that raises |R_u| more than tenfold has
    // overshot what the tangent predicts. Land problem 2's second load step
    // went from |R_u| 36 to 788 there, to an iterate whose tangent is
    // indefinite (more negative LDL^T pivots than pressure DoFs): two more
    // Newton iterations, and the iterative solver's hardest solve, whose
    // Krylov count grew with the mesh (28, 53, 78 from 2.7k to 129k DOFs).
    // Halved, it stays in the stable region. Up to three halvings; if none
    // keeps the bound, the full step after all.
    constexpr double       growth_limit   = 10.0;
    constexpr unsigned int max_backtracks = 3;
    const double           start          = residual[0];
    u_start                               = m.iterate();
    pressure_start                        = pressures;
    double       alpha                    = 1.0;
    unsigned int backtracks               = 0;
    bool         full_after_all           = false;
    double       growth                   = 0.0;
    for (unsigned int cut = 0;;)
      {
        m.set_iterate(u_start);
        m.add_to_iterate(alpha, du);
        pressures = pressure_start;
        pressures.add(alpha, dp);
        std::array<double, 2> trial;
        if (assemble(trial, with_tangent))
          {
            if (guarded && !full_after_all && start > 0.0 &&
                trial[0] > growth_limit * start)
              {
                if (backtracks == 0)
                  growth = trial[0] / start;
                if (backtracks < max_backtracks)
                  {
                    ++backtracks;
                    alpha *= 0.5;
                    continue;
                  }
                full_after_all = true;
                alpha          = 1.0;
                continue;
              }
            residual = trial;
            break;
          }
        AssertThrow(cut < 6,
                    ExcNewtonDidNotConverge(failure(
                                              "no acceptable step length"),
                                            it,
                                            relative));
        ++cut;
        alpha *= 0.5;
      }
    if (backtracks > 0)
      {
        out << "      (the full step raised |R_u| " << std::setprecision(3)
            << growth << "-fold: ";
        if (full_after_all)
          out << "no shorter one keeps it within " << growth_limit
              << "-fold, full step)";
        else
          out << "step length " << alpha << ")";
        out << std::endl;
      }
    else if (alpha < 1.0)
      out << "      (step length " << alpha << ")" << std::endl;
    return alpha;
  }
} // namespace systole::Mechanics
