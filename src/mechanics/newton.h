#pragma once

// Internal to src/mechanics: Newton's method for the mechanics problem, the
// nonlinear solver of Problem::Impl::newton(), on the problem's
// NewtonSystem interface (newton_system.h): separate from the assembly
// (assembly.cc) and the linear solvers (linear_solver.cc) it drives. Not
// included outside src/mechanics.

#include "mechanics/anderson.h"
#include "mechanics/forcing_term.h"
#include "mechanics/newton_system.h"
#include "mechanics/problem.h"

#include <array>
#include <vector>

namespace systole::Mechanics
{
  /// Newton's method for R(u; p) = 0 at fixed cavity pressures, or, with a
  /// volume target, for (u, p) with the cavity volume constraints
  /// V_i(u) = W_i(p) (the pressures are then Lagrange multipliers of a
  /// bordered system outside the field blocks). One object per solve.
  ///
  /// A solve has three stages (docs/architecture.md, "Newton"):
  /// - reuse of the last solve's factorization, if it converged: chord
  ///   iterations of the bordered system (bordered_chords()), or one Euler
  ///   predictor step (euler_predictor());
  /// - modified Newton iterations (iterate()): a new tangent and
  ///   factorization, or a chord update on the held one while the residual
  ///   contracts fast (update()), each followed by a safeguarded step that
  ///   halves while an element inverts (step());
  /// - convergence on the per-block residual norms (|R_u| against the
  ///   residual where Newton started, |R_p| against the body volume) and
  ///   the cavity volume errors.
  /// Failures throw ExcNewtonDidNotConverge; Newton that continued from the
  /// chords' iterate and failed is first repeated from their start.
  class NewtonSolver
  {
  public:
    NewtonSolver(NewtonSystem                &problem,
                 dealii::Vector<double>      &pressures,
                 const double                 active_tension,
                 const Problem::VolumeTarget *target);

    NewtonReport
    solve();

  private:
    /// After the first factorization of a volume-constrained solve: if the
    /// tangent at the (predicted) start is indefinite, restart from the last
    /// accepted state (residual, tangent and factorization there).
    void
    restart_if_indefinite();

    /// After a later factorization of a volume-constrained solve: if the
    /// tangent at the iterate is indefinite, move back along the last update
    /// (halving it, at most three times) while it stays so; the residual,
    /// tangent and factorization are then those of the point reached.
    void
    back_off_if_indefinite();

    /// Residual (with_matrix: and tangent and dV/du) at the current u, and
    /// for a bordered solve the volume errors against W(p); false if an
    /// element inverted or the residual is not finite (decided on all ranks
    /// alike).
    bool
    assemble(std::array<double, 2> &norms, const bool with_matrix);

    /// du = -K^-1 R on the held factorization (a chord update), an iterative
    /// solver to the relative residual @p tolerance if > 0; false if the
    /// linear solver fails.
    bool
    chord_solve(const double tolerance = 0.0);

    /// Whether the updates are solved inexactly (ForcingTerm): Inexact
    /// Newton with an iterative solver, fixed cavity pressures.
    bool
    inexact() const;

    /// The |R_u| at which the solve has converged.
    double
    target_residual() const;

    /// Where the chord iterations of a bordered solve started (the
    /// predicted state), and whether Newton continues from their iterate.
    struct ChordStart
    {
      LA::MPI::Vector        u;
      dealii::Vector<double> pressures;
      bool                   newton_from_there = false;
    };

    /// Chord iterations of a bordered solve on the factorization of the last
    /// one, while they contract fast; true if they converged the solve.
    bool
    bordered_chords(ChordStart &start);

    /// Newton from the chords' start after Newton from their iterate failed
    /// with @p failure (logged); the iterations of both attempts counted.
    NewtonReport
    retry_from_chord_start(const ChordStart            &start,
                           const dealii::ExceptionBase &failure);

    /// Whether chord iterations converging at @p rate (|R_u| over the last
    /// one's) should go on: a rate below 0.3 that reaches the tolerance in at
    /// most three more.
    bool
    chords_worth_going_on(const double rate) const;

    /// Without volume constraints: one chord iteration on the last
    /// factorization (the Euler predictor of the new load); true if the
    /// iterate moved there (the residual is then assembled).
    bool
    euler_predictor();

    /// The modified Newton iterations from the current iterate.
    NewtonReport
    iterate(const bool start_assembled);

    /// When iterate() reuses the factorization. With the direct solver:
    /// after a Newton update that cut |R| tenfold (the iterate is where the
    /// tangent predicts the residual well), or a chord update that cut it
    /// fourfold, the next update reuses the factorization (a chord
    /// iteration: a residual and a back substitution instead of a tangent
    /// and a factorization, some 15 times cheaper at 10^5 DOFs); a slower
    /// one is followed by a new tangent, one that raised |R| is undone
    /// first; the first chord after a Newton update waits until |R| <= 0.1
    /// max|R| (further out a chord from a tangent at large rotations can
    /// throw the iterate far off); at most max_chord_iterations per solve.
    /// With an iterative solver, whose solves cost as much as a few
    /// preconditioner set-ups, the preconditioner is reused (with the trial
    /// point's tangent) only near the solution: once |R| is below 1e-3 of
    /// its largest value and the last update cut it tenfold, at most three
    /// times per solve.
    ///
    /// Anderson-accelerated chord iterations (direct solver, fixed cavity
    /// pressures; Chord acceleration depth > 0) damp the slow contraction
    /// of a chord on an older tangent, so: chords continue while each cuts
    /// |R_u| twofold (not fourfold); they follow a Newton update that cut
    /// |R_u| 2.5-fold to below 0.4 of its largest value (not tenfold to
    /// below 0.1); and the Euler predictor is continued by chords on the
    /// last solve's factorization while each cuts |R_u| twofold, the first
    /// that does not being undone (Newton from the iterate before it). On
    /// Land problem 2 at 129k DOFs: 8 factorizations instead of 13
    /// (docs/architecture.md, "Newton").
    struct ChordRules
    {
      static constexpr unsigned int max_chord_iterations = 20;
      bool                          direct               = true;
      bool                          accelerated          = false;
      /// The cut of |R_u| a chord must make to be followed by another.
      double chord_ratio = 0.25;
      /// The cut of |R_u| (and of |R_u| / the solve's reference) after which a
      /// Newton update is followed by a chord.
      double       newton_cut        = 0.1;
      unsigned int n_chord           = 0;
      bool         last_was_chord    = false;
      double       previous_residual = 0.0;
      /// The last update was a chord update of the direct solver, to be
      /// undone if it raised |R|.
      bool undo_chord = false;
      /// Chords continuing the Euler predictor (accelerated).
      bool predictor_chords = false;
      /// A Newton update (new tangent) was made in this solve: the first
      /// one is guarded (step()).
      bool newton_done = false;
      /// The linear tolerances of an inexact solve (inexact()).
      bool        inexact = false;
      ForcingTerm forcing{0.0};
    };
    /// The rules of a solve that starts with an assembled residual (@p
    /// start_assembled: after a chord of the Euler predictor) or not.
    ChordRules
    chord_rules(const bool start_assembled) const;
    /// Whether update @p it is a chord iteration; first undoes a chord
    /// update that raised |R| (accelerated: cut it less than twofold).
    bool
    next_is_chord(ChordRules &s, const unsigned int it, const double relative);
    /// Accelerates the update du (Anderson); a @p chord update at least
    /// @p chord_ratio as long as the last update is replaced by a Newton
    /// update. Returns whether the update is a chord update.
    bool
    accelerate(const bool              chord,
               const unsigned int      it,
               const double            relative,
               dealii::Vector<double> &dp,
               const double            chord_ratio);
    /// The safeguarded step along the update and the iteration's
    /// bookkeeping (trial tangent, update norms, chord count).
    void
    take_step(ChordRules                   &s,
              const bool                    chord,
              const unsigned int            it,
              const double                  relative,
              const dealii::Vector<double> &dp);

    /// The update du (and dp) of iteration @p it: on the held factorization
    /// (@p chord) or on a new one of the tangent assembled at the iterate;
    /// an iterative solver solves for du to the relative residual @p
    /// tolerance if > 0 (the forcing term).
    void
    update(const bool              chord,
           const unsigned int      it,
           const double            relative,
           dealii::Vector<double> &dp,
           const double            tolerance = 0.0);

    /// u += alpha du, p += alpha dp from the iterate, alpha halved while an
    /// element inverts (at most six times) and, if @p guarded (the first
    /// Newton update of a solve), while it raises |R_u| more than tenfold
    /// (at most three times; then the full step); the residual there (and
    /// the tangent if @p with_tangent). Returns alpha.
    double
    step(const dealii::Vector<double> &dp,
         const bool                    with_tangent,
         const unsigned int            it,
         const double                  relative,
         const bool                    guarded);

    /// The log line of iteration @p it.
    void
    log_iteration(const unsigned int           it,
                  const unsigned int           n_chord,
                  const bool                   last_was_chord,
                  const double                 relative,
                  const std::array<double, 2> &u_norm);

    double
    largest_volume_error() const;
    /// What failed (@p what) with the residual of every block, for the
    /// failure's message.
    std::string
    failure(const std::string &what) const;
    /// g = V(u) - W(p) [mm^3].
    dealii::Vector<double>
    volume_residual() const;
    /// |sum p_i b_i| for the b_i = @p B (taken as disjoint).
    double
    pressure_load(const std::vector<LA::MPI::Vector> &B) const;
    bool
    pressure_converged() const;
    bool
    converged(const double reference) const;
    /// The bordered update of du (and dp) with B = dV/du and W = K^-1 B of
    /// the factorized iterate; an error if the Schur complement is singular.
    void
    bordered_correction(const std::vector<LA::MPI::Vector> &B,
                        const std::vector<LA::MPI::Vector> &W,
                        dealii::Vector<double>             &dp,
                        const unsigned int                  it,
                        const double                        relative);
    /// Marks the solve converged (its factorization is worth reusing).
    NewtonReport &
    converged_now();
    void
    print_pressures() const;

    NewtonSystem                &m;
    dealii::Vector<double>      &pressures;
    const double                 active_tension;
    const Problem::VolumeTarget *target;
    const bool                   bordered;
    const bool                   mixed;
    /// Cavities of the volume constraints (0 without).
    const unsigned int           k;
    dealii::ConditionalOStream  &out;
    NewtonReport                 report;
    LA::MPI::Vector              du;
    std::vector<LA::MPI::Vector> w_volume;
    /// Block norms of the residual (u: force [mN]; p: volume [mm^3]) and of
    /// the last update.
    std::array<double, 2> residual = {{0.0, 0.0}};
    std::array<double, 2> du_norm  = {{0.0, 0.0}};
    /// The volume targets W(p) and dW/dp at the current pressures, and the
    /// relative volume errors (V_i(u) - W_i) / W_i.
    dealii::Vector<double>     target_volume, volume_error;
    dealii::FullMatrix<double> target_derivative;
    /// Residual scale of the relative tolerance: the displacement residual
    /// where the chords or Newton started (not an iterate's), and for a
    /// volume-constrained solve at least the cavity pressure load.
    double reference = 0;
    /// Timer totals at the start (the log's per-solve times).
    double assembly_start, solver_start;
    /// Whether the tangent at the iterate is assembled.
    bool tangent_ready;
    /// Whether no tangent was factorized yet in this solve (a predicted
    /// start whose tangent is indefinite is left for the last accepted
    /// state, see update()).
    bool first_factorization = true;
    /// The iterate before the last update (the safeguarded update's start).
    LA::MPI::Vector        u_start;
    dealii::Vector<double> pressure_start;
    /// Anderson acceleration of the chord iterations on one factorization.
    AndersonAcceleration anderson;
    /// |du| of the last update before its acceleration (the natural
    /// monotonicity test of the accelerated chords).
    double last_update_length = 0.0;
  };
} // namespace systole::Mechanics
