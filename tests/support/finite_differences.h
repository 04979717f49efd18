#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law.h"

#include <functional>
#include <string>
#include <vector>

/// @file
/// Central-difference studies of hyperelastic laws in the Green-Lagrange
/// strain E, for the "observed order" checks of STYLE.md 2.9.
///
/// Method. A law sees F only through C = F^T F (it is objective), so E is
/// perturbed by building a deformation gradient whose right Cauchy-Green
/// tensor is exactly C + 2 dE: with R and R' the upper Cholesky factors of
/// C and C + 2 dE (C = R^T R), F' = (F R^{-1}) R'. F R^{-1} is the rotation
/// of the QR decomposition of F, so F'^T F' = R'^T R' = C + 2 dE, F' = F at
/// dE = 0, and F' is smooth in dE (no eigen-decomposition, no branch).
/// The six independent components of E are perturbed one at a time along
/// strain_direction(i, j), for which A : D = A_ij for every symmetric A; so
/// the central difference of psi along D is S_ij and that of S is
/// dS/dE[.][.][i][j].

namespace test_support
{
  /// psi, S and dS/dE at one point: a PassiveLaw, or anything wrapped to
  /// look like one (e.g. a VolumetricLaw via add_to()).
  using MaterialEvaluator =
    std::function<void(const systole::Materials::PassiveInput &,
                       systole::Materials::PassiveOutput &)>;

  /// Evaluator of @p law (which must outlive the result).
  MaterialEvaluator
  evaluator_of(const systole::Materials::PassiveLaw &law);

  /// The unit direction of the independent strain component (i, j):
  /// e_i x e_i for i = j and (e_i x e_j + e_j x e_i)/2 otherwise.
  dealii::SymmetricTensor<2, 3>
  strain_direction(const unsigned int i, const unsigned int j);

  /// Upper triangular R with R^T R = @p C (Cholesky); throws ExcMessage if
  /// @p C is not positive definite.
  dealii::Tensor<2, 3>
  upper_cholesky_factor(const dealii::SymmetricTensor<2, 3> &C);

  /// F' with F'^T F' = F^T F + 2 @p dE exactly, i.e. E(F') = E(F) + dE, and
  /// F' = F at dE = 0 (see the file documentation).
  dealii::Tensor<2, 3>
  perturb_green_lagrange(const dealii::Tensor<2, 3>          &F,
                         const dealii::SymmetricTensor<2, 3> &dE);

  /// Errors of central differences at a sequence of step sizes.
  struct FdStudy
  {
    std::vector<double> steps;  ///< step sizes h in E [-], decreasing
    std::vector<double> errors; ///< |FD(h) - analytic| / |analytic| [-]

    /// log(e_k / e_{k+1}) / log(h_k / h_{k+1}) for consecutive steps (2 for
    /// a consistent derivative while truncation error dominates).
    std::vector<double>
    observed_orders() const;

    /// Steps, errors and orders as text, for INFO().
    std::string
    describe() const;
  };

  /// Compares S with the central differences of psi in the six components of
  /// E, at each of @p steps. Norms are Frobenius norms.
  FdStudy
  fd_study_of_stress(const MaterialEvaluator                &evaluate,
                     const systole::Materials::PassiveInput &in,
                     const std::vector<double>              &steps);

  /// Compares dS/dE with the central differences of S in the six components
  /// of E, at each of @p steps.
  FdStudy
  fd_study_of_tangent(const MaterialEvaluator                &evaluate,
                      const systole::Materials::PassiveInput &in,
                      const std::vector<double>              &steps);
} // namespace test_support
