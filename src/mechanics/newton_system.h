#pragma once

// Internal to src/mechanics: what Newton's method (NewtonSolver, newton.h)
// sees of the mechanics problem. Problem::Impl implements it; the solver
// needs no other access to the problem.

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "base/linear_algebra.h"
#include "mechanics/field_layout.h"
#include "mechanics/linear_solver.h"
#include "mechanics/parameters.h"

#include <array>
#include <string>
#include <vector>

namespace systole::Mechanics
{
  /// A linear solve or factorization that threw @p e at Newton iteration
  /// @p iteration (relative residual @p relative): throws
  /// ExcNewtonDidNotConverge with the solver's message in one line.
  void
  throw_linear_solver_failure(const dealii::ExceptionBase &e,
                              const unsigned int           iteration,
                              const double                 relative);

  /// Euclidean norms of the two blocks (u, p) of a vector in the layout of
  /// @p layout (collective).
  std::array<double, 2>
  block_norms(const FieldLayout &layout, const LA::MPI::Vector &v);

  /// The displacements saved for a retry and the predictor (save(),
  /// restore(), predict()).
  struct SolutionHistory
  {
    LA::MPI::Vector u_saved;     ///< owned
    LA::MPI::Vector u_previous;  ///< owned, the save() before u_saved
    LA::MPI::Vector u_before;    ///< owned, the save() before u_previous
    LA::MPI::Vector u_predicted; ///< owned, the last predict()
    unsigned int    n_saves = 0;
  };

  /// The linear solver holds a factorization (or preconditioner) of the
  /// tangent of an earlier Newton iteration: where it was assembled, so that
  /// chord iterations can reuse it and a checkpoint can rebuild it.
  struct Factorization
  {
    /// Whether there is one; for a bordered solve B0 = [dV_i/du] and W0 =
    /// K^-1 B0 of that iterate (for the chord iterations that start a
    /// solve).
    bool                         held = false;
    std::vector<LA::MPI::Vector> volume_derivatives, w;
    /// The volume_rows of that iterate.
    std::vector<LA::MPI::Vector> volume_rows;
    /// The last solve converged: the factorization is that of an iterate
    /// near its solution (not of a diverged one).
    bool last_solve_converged = false;
    /// Where that tangent was assembled: the iterate (owned), its pressures,
    /// the uniform and the per-point active tension (by active cell index).
    LA::MPI::Vector                  u;
    dealii::Vector<double>           pressures;
    double                           active_tension = 0;
    std::vector<std::vector<double>> tension;
    /// With a tension model: its inputs at the factorized iterate, per
    /// point its accepted state, stretch and calcium (flat per cell), and
    /// the step.
    std::vector<std::vector<double>> model_inputs;
    double                           tension_time = 0, tension_time_step = 0;
    /// Of the low-rank part of the tangent (Woodbury): v_j, z_j = tangent^-1
    /// u_j and (I + V^T Z)^-1, applied by linear_solve().
    std::vector<LA::MPI::Vector> low_rank_v, low_rank_z;
    dealii::FullMatrix<double>   low_rank_inverse;
  };

  /// The mechanics problem as Newton's method sees it: the fixed data of
  /// the solves, the iterate, the residual and the tangent at it, and the
  /// linear solver with the factorization it holds.
  class NewtonSystem
  {
  public:
    virtual ~NewtonSystem() = default;

    /// The parameters (tolerances, iteration limits, reuse of the
    /// factorization).
    virtual const Parameters &
    parameters() const = 0;
    /// The fields and their blocks.
    virtual const FieldLayout &
    layout() const = 0;
    /// Reference volume of the body [mm^3] (the scale of the pressure rows).
    virtual double
    body_volume() const = 0;
    /// Cavities of the volume constraints, and the names of the pressure
    /// parts (for messages).
    virtual unsigned int
    n_cavities() const = 0;
    virtual const std::vector<std::string> &
    pressure_names() const = 0;
    /// @p v sized as the iterate (owned entries).
    virtual void
    reinit_vector(LA::MPI::Vector &v) const = 0;
    /// The detail log, the timers and a timer section's total [s].
    virtual dealii::ConditionalOStream &
    log() const = 0;
    virtual dealii::TimerOutput &
    timers() const = 0;
    virtual double
    seconds_in(const std::string &section) const = 0;

    /// The displacement (owned entries), set and moved as a whole.
    virtual const LA::MPI::Vector &
    iterate() const = 0;
    virtual void
    set_iterate(const LA::MPI::Vector &u) = 0;
    /// iterate += @p a @p du.
    virtual void
    add_to_iterate(const double a, const LA::MPI::Vector &du) = 0;
    /// The accepted states saved for retries.
    virtual const SolutionHistory &
    solution_history() const = 0;

    /// Residual (and, if @p with_matrix, tangent) at the iterate for the
    /// given loads; the l2 norm of the constrained residual. Throws
    /// ExcInvertedElement collectively where J <= 0. With
    /// @p with_volume_derivative also dV_i/du (volume_derivatives(),
    /// volume_rows()).
    virtual double
    assemble(const dealii::Vector<double> &pressures,
             const double                  active_tension,
             const bool                    with_matrix,
             const bool                    with_volume_derivative) = 0;
    /// The residual of the last assembly (owned; the solver negates it in
    /// place for the solves).
    virtual LA::MPI::Vector &
    residual() = 0;
    /// Cavity volumes at the iterate (collective).
    virtual dealii::Vector<double>
    cavity_volumes_now() const = 0;
    /// Of the last assembly with volume derivatives: the loads per unit
    /// pressure and dV_i/du (condensed).
    virtual const std::vector<LA::MPI::Vector> &
    volume_derivatives() const = 0;
    virtual const std::vector<LA::MPI::Vector> &
    volume_rows() const = 0;

    /// The linear solver.
    virtual const LinearSolver &
    linear_solver() const = 0;
    /// Factorize (or build the preconditioner of) the tangent as last
    /// assembled.
    virtual void
    setup_linear_solver() = 0;
    /// After setup_linear_solver(): the low-rank part of the tangent
    /// (collective; nothing without one).
    virtual void
    factorize_low_rank() = 0;
    /// Solve tangent x = b on the held factorization and distribute the
    /// constraints; linear solver failures are thrown as Newton failures
    /// (@p iteration, @p relative name them). An iterative solver stops at
    /// the relative residual @p tolerance if > 0, else at its own.
    virtual unsigned int
    linear_solve(LA::MPI::Vector       &x,
                 const LA::MPI::Vector &b,
                 const unsigned int     iteration,
                 const double           relative,
                 const double           tolerance) = 0;
    /// Where the held factorization was assembled.
    virtual Factorization &
    factorization() = 0;
    /// Copy the tension inputs of the iterate into factorization() (and the
    /// dynamic state), for a checkpoint to rebuild that tangent.
    virtual void
    remember_factorized_tension() = 0;
  };
} // namespace systole::Mechanics
