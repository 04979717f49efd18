#include "inverse/least_squares.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>
#include <deal.II/lac/full_matrix.h>

#include <boost/math/distributions/students_t.hpp>
#include <petsctao.h>

#include <cmath>
#include <exception>
#include <limits>

namespace systole::Inverse
{
  namespace
  {
    void
    check(const PetscErrorCode code, const std::string &what)
    {
      AssertThrow(code == 0,
                  dealii::ExcMessage("PETSc TAO failed in " + what +
                                     " (error code " + std::to_string(code) +
                                     ")."));
    }

    /// What the TAO callbacks see. An exception of the model is kept and
    /// rethrown after TaoSolve (it must not cross PETSc's C frames).
    struct Context
    {
      const LeastSquaresProblem *problem = nullptr;
      unsigned int               n = 0, m = 0;
      unsigned int               evaluations = 0;
      std::vector<double>        x, r, J; ///< the last evaluation
      bool                       have    = false;
      std::exception_ptr         failure = nullptr;

      /// Evaluate at @p x_in unless that is the last point evaluated
      /// (TAO asks for the residual and the Jacobian at the same point; the
      /// model returns both at once).
      bool
      at(const std::vector<double> &x_in)
      {
        if (have && x_in == x)
          return true;
        if (failure)
          return false;
        try
          {
            r.assign(m, 0.0);
            J.assign(m * n, 0.0);
            problem->evaluate(x_in, r, &J);
            ++evaluations;
            x    = x_in;
            have = true;
            return true;
          }
        catch (...)
          {
            failure = std::current_exception();
            have    = false;
            return false;
          }
      }
    };

    std::vector<double>
    to_vector(const Vec v, const unsigned int n)
    {
      const PetscScalar *a;
      VecGetArrayRead(v, &a);
      std::vector<double> x(a, a + n);
      VecRestoreArrayRead(v, &a);
      return x;
    }

    PetscErrorCode
    residual_callback(Tao, Vec X, Vec F, void *ptr)
    {
      auto &c = *static_cast<Context *>(ptr);
      if (!c.at(to_vector(X, c.n)))
        return PETSC_ERR_USER;
      PetscScalar *f;
      VecGetArray(F, &f);
      for (unsigned int i = 0; i < c.m; ++i)
        f[i] = c.r[i];
      VecRestoreArray(F, &f);
      return 0;
    }

    PetscErrorCode
    jacobian_callback(Tao, Vec X, Mat J, Mat, void *ptr)
    {
      auto &c = *static_cast<Context *>(ptr);
      if (!c.at(to_vector(X, c.n)))
        return PETSC_ERR_USER;
      for (unsigned int i = 0; i < c.m; ++i)
        for (unsigned int j = 0; j < c.n; ++j)
          MatSetValue(J, i, j, c.J[i * c.n + j], INSERT_VALUES);
      MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY);
      MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY);
      return 0;
    }

    /// TAO's default tests, then stagnation of the objective.
    struct Stagnation
    {
      double              tolerance = 0;
      double              floor     = 0; ///< of the objective
      std::vector<double> history;
    };

    PetscErrorCode
    convergence_test(Tao tao, void *ptr)
    {
      PetscErrorCode code = TaoDefaultConvergenceTest(tao, nullptr);
      if (code != 0)
        return code;
      TaoConvergedReason reason;
      PetscInt           its;
      PetscReal          f, gnorm, cnorm, xdiff;
      TaoGetSolutionStatus(tao, &its, &f, &gnorm, &cnorm, &xdiff, &reason);
      if (reason != TAO_CONTINUE_ITERATING)
        return 0;
      auto &s = *static_cast<Stagnation *>(ptr);
      if (f <= s.floor)
        {
          TaoSetConvergedReason(tao, TAO_CONVERGED_USER);
          return 0;
        }
      s.history.push_back(f);
      const unsigned int k = s.history.size();
      if (k >= 4)
        {
          bool stagnant = true;
          for (unsigned int i = k - 3; i < k; ++i)
            stagnant = stagnant && std::abs(s.history[i - 1] - s.history[i]) <=
                                     s.tolerance * std::abs(s.history[i - 1]);
          if (stagnant)
            TaoSetConvergedReason(tao, TAO_CONVERGED_USER);
        }
      return 0;
    }

    Vec
    make_vector(const std::vector<double> &values)
    {
      Vec v;
      check(VecCreateSeq(PETSC_COMM_SELF, values.size(), &v), "VecCreateSeq");
      for (unsigned int i = 0; i < values.size(); ++i)
        VecSetValue(v, i, values[i], INSERT_VALUES);
      VecAssemblyBegin(v);
      VecAssemblyEnd(v);
      return v;
    }
  } // namespace

  LeastSquaresResult
  solve_least_squares(const LeastSquaresProblem  &problem,
                      const LeastSquaresSettings &settings)
  {
    const unsigned int n = problem.initial.size();
    const unsigned int m = problem.n_residuals;
    AssertThrow(n >= 1 && m >= n && problem.lower.size() == n &&
                  problem.upper.size() == n,
                dealii::ExcMessage(
                  "Least squares: need 1 <= n <= m parameters (n = " +
                  std::to_string(n) + ", m = " + std::to_string(m) +
                  ") and one lower and one upper bound each."));

    Context context;
    context.problem = &problem;
    context.n       = n;
    context.m       = m;

    Tao tao;
    check(TaoCreate(PETSC_COMM_SELF, &tao), "TaoCreate");
    check(TaoSetType(tao, settings.method.c_str()), "TaoSetType");
    check(TaoSetOptionsPrefix(tao, settings.options_prefix.c_str()),
          "TaoSetOptionsPrefix");
    Vec x = make_vector(problem.initial), lower = make_vector(problem.lower),
        upper = make_vector(problem.upper),
        f     = make_vector(std::vector<double>(m));
    Mat J;
    check(MatCreateSeqDense(PETSC_COMM_SELF, m, n, nullptr, &J),
          "MatCreateSeqDense");
    check(TaoSetSolution(tao, x), "TaoSetSolution");
    check(TaoSetVariableBounds(tao, lower, upper), "TaoSetVariableBounds");
    check(TaoSetResidualRoutine(tao, f, residual_callback, &context),
          "TaoSetResidualRoutine");
    check(TaoSetJacobianResidualRoutine(tao, J, J, jacobian_callback, &context),
          "TaoSetJacobianResidualRoutine");
    check(TaoSetTolerances(tao,
                           settings.gradient_tolerance,
                           0.0,
                           settings.relative_gradient_tolerance),
          "TaoSetTolerances");
    check(TaoSetMaximumIterations(tao, settings.max_iterations),
          "TaoSetMaximumIterations");
    Stagnation stagnation;
    stagnation.tolerance = settings.stagnation_tolerance;
    stagnation.floor =
      0.5 * settings.residual_tolerance * settings.residual_tolerance;
    // TAOBRGN iterates with its subsolver (bounded Newton line search),
    // whose convergence test decides; the outer one is not consulted.
    Tao iterating = tao;
    if (settings.method == TAOBRGN)
      check(TaoBRGNGetSubsolver(tao, &iterating), "TaoBRGNGetSubsolver");
    check(TaoSetConvergenceTest(iterating, convergence_test, &stagnation),
          "TaoSetConvergenceTest");
    if (settings.method == TAOBRGN)
      check(TaoBRGNSetRegularizerWeight(tao, settings.regularizer_weight),
            "TaoBRGNSetRegularizerWeight");
    check(TaoSetFromOptions(tao), "TaoSetFromOptions");
    // A failed evaluation returns an error code through TAO: keep PETSc
    // from printing its traceback (the model's own exception is rethrown
    // below, one clear message).
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    const PetscErrorCode solved = TaoSolve(tao);
    PetscPopErrorHandler();
    if (context.failure)
      {
        TaoDestroy(&tao);
        VecDestroy(&x), VecDestroy(&lower), VecDestroy(&upper), VecDestroy(&f);
        MatDestroy(&J);
        std::rethrow_exception(context.failure);
      }
    check(solved, "TaoSolve");

    LeastSquaresResult result;
    TaoConvergedReason reason;
    PetscInt           iterations;
    TaoGetConvergedReason(tao, &reason);
    TaoGetIterationNumber(tao, &iterations);
    result.iterations = iterations;
    result.reason     = TaoConvergedReasons[reason];
    result.converged  = reason > 0;
    result.x          = to_vector(x, n);
    TaoDestroy(&tao);
    VecDestroy(&x), VecDestroy(&lower), VecDestroy(&upper), VecDestroy(&f);
    MatDestroy(&J);

    // r and J at the solution (the last evaluation may be a rejected trial
    // point).
    AssertThrow(context.at(result.x), dealii::ExcInternalError());
    if (context.failure)
      std::rethrow_exception(context.failure);
    result.residual    = context.r;
    result.jacobian    = context.J;
    result.evaluations = context.evaluations;
    double rss         = 0;
    for (const double ri : result.residual)
      rss += ri * ri;
    result.residual_norm = std::sqrt(rss);
    result.at_bound.resize(n);
    for (unsigned int j = 0; j < n; ++j)
      result.at_bound[j] = std::abs(result.x[j] - problem.lower[j]) <=
                             1e-8 * (1 + std::abs(problem.lower[j])) ||
                           std::abs(result.x[j] - problem.upper[j]) <=
                             1e-8 * (1 + std::abs(problem.upper[j]));
    fit_statistics(result);
    return result;
  }

  void
  fit_statistics(LeastSquaresResult &result)
  {
    const unsigned int n = result.x.size();
    const unsigned int m = result.residual.size();
    AssertThrow(result.jacobian.size() == m * n, dealii::ExcInternalError());
    double rss = 0;
    for (const double ri : result.residual)
      rss += ri * ri;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    result.sigma2    = m > n ? rss / (m - n) : nan;

    dealii::FullMatrix<double> JtJ(n, n);
    for (unsigned int a = 0; a < n; ++a)
      for (unsigned int b = 0; b < n; ++b)
        for (unsigned int i = 0; i < m; ++i)
          JtJ(a, b) += result.jacobian[i * n + a] * result.jacobian[i * n + b];
    // Singular when a column of J vanishes (or two are parallel): the data
    // cannot tell that parameter apart.
    double largest = 0;
    for (unsigned int a = 0; a < n; ++a)
      largest = std::max(largest, JtJ(a, a));
    for (unsigned int a = 0; a < n; ++a)
      AssertThrow(JtJ(a, a) > 1e-14 * largest && largest > 0,
                  dealii::ExcMessage(
                    "The residuals do not depend on fitted parameter " +
                    std::to_string(a + 1) +
                    " (a zero column of the Jacobian): it cannot be fitted "
                    "to these data. Remove it from Calibration / Parameters."));
    dealii::FullMatrix<double> inverse(n, n);
    inverse.invert(JtJ);

    result.covariance.assign(n * n, 0.0);
    result.standard_deviation.assign(n, nan);
    result.lower_95.assign(n, nan);
    result.upper_95.assign(n, nan);
    result.t_quantile =
      m > n
        ? boost::math::quantile(boost::math::students_t_distribution<double>(m -
                                                                             n),
                                0.975)
        : nan;
    for (unsigned int a = 0; a < n; ++a)
      for (unsigned int b = 0; b < n; ++b)
        result.covariance[a * n + b] = result.sigma2 * inverse(a, b);
    for (unsigned int a = 0; a < n; ++a)
      {
        result.standard_deviation[a] = std::sqrt(result.covariance[a * n + a]);
        result.lower_95[a] =
          result.x[a] - result.t_quantile * result.standard_deviation[a];
        result.upper_95[a] =
          result.x[a] + result.t_quantile * result.standard_deviation[a];
      }
  }
} // namespace systole::Inverse
