#pragma once

#include <functional>
#include <string>
#include <vector>

namespace systole::Inverse
{
  /// A small bounded nonlinear least-squares problem
  /// @f$\min_{l \le x \le u} \frac12 \|r(x)\|^2@f$, r: R^n -> R^m (n <= m).
  struct LeastSquaresProblem
  {
    /// r(x) (size m) and, if @p jacobian is not null, the Jacobian
    /// dr/dx (m x n, row-major: J[i n + j] = dr_i/dx_j) at x. Called with
    /// the same x on every rank (a collective model may run inside); must
    /// return the same values on every rank. May throw.
    std::function<void(const std::vector<double> &x,
                       std::vector<double>       &r,
                       std::vector<double>       *jacobian)>
      evaluate;

    unsigned int        n_residuals = 0;
    std::vector<double> initial, lower, upper; ///< size n each
  };

  /// How to solve it (PETSc TAO).
  struct LeastSquaresSettings
  {
    /// TAOBRGN: bounded regularized Gauss-Newton (l2prox damping, the
    /// default), TAO's bounded Newton line search inside.
    std::string method = "brgn";
    /// Weight of TAOBRGN's l2prox damping (0.5 w |x - x_k|^2). TAO's
    /// default 1e-4 dominates J^T J along the valley of two correlated
    /// parameters whose relative residuals are a few percent (J^T J
    /// eigenvalues ~1e-6), and the steps crawl (30 iterations without
    /// convergence on the synthetic round trip); 1e-12 leaves Gauss-Newton
    /// (5 iterations there).
    double       regularizer_weight = 1e-12;
    unsigned int max_iterations     = 30;
    /// Stop when |J^T r| <= this (absolute gradient of 1/2 |r|^2).
    double gradient_tolerance = 1e-10;
    /// ... or when |J^T r| <= this times its initial value.
    double relative_gradient_tolerance = 1e-8;
    /// ... or when the objective 1/2 |r|^2 changed by at most this fraction
    /// over each of the last 3 iterations (stagnation, TAO_CONVERGED_USER):
    /// at a bound-constrained optimum with finite-difference derivatives the
    /// gradient tests may never be met.
    double stagnation_tolerance = 1e-9;
    /// ... or when |r| <= this (the data matched; TAO_CONVERGED_USER), for
    /// residuals with a noise floor (0: off).
    double residual_tolerance = 0;
    /// PETSc options prefix (e.g. -calibration_tao_monitor on the command
    /// line).
    std::string options_prefix = "calibration_";
  };

  /// The solution and what the linearisation at it says about it.
  struct LeastSquaresResult
  {
    std::vector<double> x;                 ///< fitted (size n)
    std::vector<double> residual;          ///< r(x) (size m)
    std::vector<double> jacobian;          ///< J(x), m x n row-major
    double              residual_norm = 0; ///< |r(x)|
    unsigned int        iterations    = 0; ///< TAO iterations
    unsigned int        evaluations   = 0; ///< calls of evaluate()
    std::string         reason;            ///< TAO's converged reason
    bool                converged = false; ///< reason > 0
    /// Which bounds are active at x (|x - bound| <= 1e-8 (1 + |bound|)).
    std::vector<bool> at_bound;

    // Statistics of the fit (Covariance below).
    double              sigma2 = 0;         ///< RSS / (m - n)
    std::vector<double> covariance;         ///< sigma2 (J^T J)^-1, n x n
    std::vector<double> standard_deviation; ///< sqrt of the diagonal
    double              t_quantile = 0;     ///< t_{0.975, m - n}
    std::vector<double> lower_95, upper_95; ///< x -+ t sd
  };

  /// Solve @p problem with TAO (one TAO object per rank on PETSC_COMM_SELF,
  /// all ranks iterating alike), then evaluate r and J at the solution and
  /// fill the statistics (fit_statistics()). Throws ExcMessage on a TAO
  /// error.
  LeastSquaresResult
  solve_least_squares(const LeastSquaresProblem  &problem,
                      const LeastSquaresSettings &settings);

  /// The statistics of a least-squares fit at its solution @p result.x from
  /// its residual and Jacobian: sigma^2 = RSS/(m - n), the covariance
  /// sigma^2 (J^T J)^-1, standard deviations and the 95 % intervals x -+
  /// t_{0.975, m-n} sd (Student's t; NaN where m = n). Throws if J^T J is
  /// singular (a parameter without influence on the residuals).
  void
  fit_statistics(LeastSquaresResult &result);
} // namespace systole::Inverse
