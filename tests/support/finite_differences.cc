#include "support/finite_differences.h"

#include <deal.II/base/exceptions.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace test_support
{
  namespace
  {
    using systole::Materials::PassiveInput;
    using systole::Materials::PassiveOutput;

    /// Output at the input whose Green-Lagrange strain is E(in.F) + dE.
    PassiveOutput
    evaluate_at(const MaterialEvaluator             &evaluate,
                const PassiveInput                  &in,
                const dealii::SymmetricTensor<2, 3> &dE)
    {
      PassiveInput perturbed = in;
      perturbed.F            = perturb_green_lagrange(in.F, dE);
      PassiveOutput out;
      evaluate(perturbed, out);
      return out;
    }

    double
    relative(const double difference, const double reference)
    {
      return reference > 0.0 ? difference / reference : difference;
    }
  } // namespace


  MaterialEvaluator
  evaluator_of(const systole::Materials::PassiveLaw &law)
  {
    return [&law](const PassiveInput &in, PassiveOutput &out) {
      law.evaluate(in, out);
    };
  }


  dealii::SymmetricTensor<2, 3>
  strain_direction(const unsigned int i, const unsigned int j)
  {
    dealii::SymmetricTensor<2, 3> D;
    D[i][j] = (i == j ? 1.0 : 0.5); // sets both (i, j) and (j, i)
    return D;
  }


  dealii::Tensor<2, 3>
  upper_cholesky_factor(const dealii::SymmetricTensor<2, 3> &C)
  {
    const auto root = [](const double x) {
      AssertThrow(x > 0.0,
                  dealii::ExcMessage("upper_cholesky_factor: the tensor is "
                                     "not positive definite."));
      return std::sqrt(x);
    };
    dealii::Tensor<2, 3> R;
    R[0][0] = root(C[0][0]);
    R[0][1] = C[0][1] / R[0][0];
    R[0][2] = C[0][2] / R[0][0];
    R[1][1] = root(C[1][1] - R[0][1] * R[0][1]);
    R[1][2] = (C[1][2] - R[0][1] * R[0][2]) / R[1][1];
    R[2][2] = root(C[2][2] - R[0][2] * R[0][2] - R[1][2] * R[1][2]);
    return R;
  }


  dealii::Tensor<2, 3>
  perturb_green_lagrange(const dealii::Tensor<2, 3>          &F,
                         const dealii::SymmetricTensor<2, 3> &dE)
  {
    const dealii::SymmetricTensor<2, 3> C =
      dealii::symmetrize(dealii::transpose(F) * F);
    const dealii::Tensor<2, 3> R        = upper_cholesky_factor(C);
    const dealii::Tensor<2, 3> R_new    = upper_cholesky_factor(C + 2.0 * dE);
    const dealii::Tensor<2, 3> rotation = F * dealii::invert(R);
    return rotation * R_new;
  }


  std::vector<double>
  FdStudy::observed_orders() const
  {
    std::vector<double> orders;
    for (unsigned int k = 0; k + 1 < errors.size(); ++k)
      orders.push_back(std::log(errors[k] / errors[k + 1]) /
                       std::log(steps[k] / steps[k + 1]));
    return orders;
  }


  std::string
  FdStudy::describe() const
  {
    std::ostringstream text;
    text << std::scientific << std::setprecision(2) << "relative FD errors:";
    for (unsigned int k = 0; k < errors.size(); ++k)
      text << " " << errors[k] << " (h = " << steps[k] << ")";
    text << std::fixed << std::setprecision(3) << "; observed orders:";
    for (const double order : observed_orders())
      text << " " << order;
    return text.str();
  }


  FdStudy
  fd_study_of_stress(const MaterialEvaluator   &evaluate,
                     const PassiveInput        &in,
                     const std::vector<double> &steps)
  {
    PassiveOutput exact;
    evaluate(in, exact);

    FdStudy study;
    study.steps = steps;
    for (const double h : steps)
      {
        dealii::SymmetricTensor<2, 3> S_fd;
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = i; j < 3; ++j)
            {
              const dealii::SymmetricTensor<2, 3> D = strain_direction(i, j);
              const double plus  = evaluate_at(evaluate, in, h * D).psi;
              const double minus = evaluate_at(evaluate, in, -h * D).psi;
              S_fd[i][j]         = (plus - minus) / (2.0 * h);
            }
        study.errors.push_back(
          relative((S_fd - exact.S).norm(), exact.S.norm()));
      }
    return study;
  }


  FdStudy
  fd_study_of_tangent(const MaterialEvaluator   &evaluate,
                      const PassiveInput        &in,
                      const std::vector<double> &steps)
  {
    PassiveOutput exact;
    evaluate(in, exact);

    FdStudy study;
    study.steps = steps;
    for (const double h : steps)
      {
        dealii::SymmetricTensor<4, 3> tangent_fd;
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = k; l < 3; ++l)
            {
              const dealii::SymmetricTensor<2, 3> D = strain_direction(k, l);
              const dealii::SymmetricTensor<2, 3> dS =
                (evaluate_at(evaluate, in, h * D).S -
                 evaluate_at(evaluate, in, -h * D).S) /
                (2.0 * h);
              for (unsigned int i = 0; i < 3; ++i)
                for (unsigned int j = i; j < 3; ++j)
                  tangent_fd[i][j][k][l] = dS[i][j];
            }
        study.errors.push_back(
          relative((tangent_fd - exact.dS_dE).norm(), exact.dS_dE.norm()));
      }
    return study;
  }
} // namespace test_support
