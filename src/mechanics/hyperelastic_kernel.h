#pragma once

// The quadrature-point kernel of the matrix-free mechanics operator
// (MatrixFreeTangent): first Piola-Kirchhoff stress and its directional
// derivative from one set of functions, templated on the number type so
// that the same code runs on deal.II's VectorizedArray (a batch of cells)
// and on double (a future matrix-based path); and the first elasticity
// tangent from (F, S, dS/dE), shared by the matrix-based assembly and the
// general matrix-free tangent. Only deal.II's tensor headers here.

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <cmath>

namespace systole::Mechanics
{
  /// The Levi-Civita symbol as its six signed permutations (i, j, k, sign):
  /// the derivative of the area vector cof(F) N of a face (follower
  /// pressure) in the assembly and in the matrix-free tangent.
  inline constexpr int levi_civita[6][4] = {{0, 1, 2, 1},
                                            {1, 2, 0, 1},
                                            {2, 0, 1, 1},
                                            {0, 2, 1, -1},
                                            {2, 1, 0, -1},
                                            {1, 0, 2, -1}};

  /// The first elasticity tangent @f$\mathbb{A} = \partial P/\partial F@f$
  /// of a point from the deformation gradient @p F, the second
  /// Piola-Kirchhoff stress @p S [kPa] and its tangent @p dS_dE [kPa]:
  /// @f$A_{iJkL} = F_{iI} (\partial S/\partial E)_{IJKL} F_{kK} +
  /// \delta_{ik} S_{JL}@f$ (material and geometric stiffness; P = F S),
  /// so that dP = A : dF. The one conversion of the mechanics: the
  /// matrix-based assembly (add_stress_point) and the general matrix-free
  /// tangent (Problem::matrix_free_tangent()) both use it.
  template <typename Number>
  dealii::Tensor<4, 3, Number>
  first_elasticity_tangent(const dealii::Tensor<2, 3, Number>          &F,
                           const dealii::SymmetricTensor<2, 3, Number> &S,
                           const dealii::SymmetricTensor<4, 3, Number> &dS_dE)
  {
    // dS/dE copied out once (SymmetricTensor's access is not free), then
    // T_cJKL = F_cI C_IJKL and A_cJdL = T_cJKL F_dK + delta_cd S_JL.
    Number C[3][3][3][3], T[3][3][3][3];
    for (unsigned int I = 0; I < 3; ++I)
      for (unsigned int J = 0; J < 3; ++J)
        for (unsigned int K = 0; K < 3; ++K)
          for (unsigned int L = 0; L < 3; ++L)
            C[I][J][K][L] = dS_dE[I][J][K][L];
    for (unsigned int c = 0; c < 3; ++c)
      for (unsigned int J = 0; J < 3; ++J)
        for (unsigned int K = 0; K < 3; ++K)
          for (unsigned int L = 0; L < 3; ++L)
            T[c][J][K][L] = F[c][0] * C[0][J][K][L] + F[c][1] * C[1][J][K][L] +
                            F[c][2] * C[2][J][K][L];
    dealii::Tensor<4, 3, Number> A;
    for (unsigned int c = 0; c < 3; ++c)
      for (unsigned int J = 0; J < 3; ++J)
        for (unsigned int d = 0; d < 3; ++d)
          for (unsigned int L = 0; L < 3; ++L)
            A[c][J][d][L] = T[c][J][0][L] * F[d][0] + T[c][J][1][L] * F[d][1] +
                            T[c][J][2][L] * F[d][2] +
                            (c == d ? S[J][L] : Number(0.0));
    return A;
  }

  /// Compressible neo-Hookean law of the penalty (displacement-only)
  /// formulation: the isochoric neo-Hookean energy plus the Simo-Taylor
  /// volumetric penalty, the sum Materials::NeoHookean +
  /// Materials::VolumetricLaw("Simo-Taylor") of the matrix-based mechanics:
  /// @f[
  ///   W(F) = \frac{\mu}{2}\left(J^{-2/3} I_1 - 3\right)
  ///        + \frac{\kappa}{4}\left(J^2 - 1 - 2\ln J\right),
  ///   \quad I_1 = F:F,\ J = \det F,
  /// @f]
  /// @f$P = \partial W/\partial F = \mu J^{-2/3}(F - \frac{I_1}{3}F^{-T})
  ///  + \frac{\kappa}{2}(J^2 - 1) F^{-T}@f$ [kPa].
  ///
  /// The evaluation is split in two: state() does the expensive part once
  /// per point (determinant, inverse, power), stress() and linearization()
  /// are then products and sums only. The residual, the tangent's action and
  /// the cached 9 x 9 tangent (built column by column from linearization())
  /// all come from these functions.
  struct NeoHookeanPenalty
  {
    double mu           = 10.0;   ///< shear modulus [kPa], > 0
    double bulk_modulus = 1000.0; ///< kappa [kPa], >= 0

    /// What stress() and linearization() need at one point.
    template <typename Number>
    struct State
    {
      dealii::Tensor<2, 3, Number> F;     ///< deformation gradient [-]
      dealii::Tensor<2, 3, Number> FinvT; ///< F^{-T} [-]
      Number                       a;     ///< mu J^{-2/3} [kPa]
      Number                       g;     ///< J U'(J) = kappa (J^2 - 1)/2 [kPa]
      Number                       kJ2;   ///< kappa J^2 [kPa]
      Number                       I1_3;  ///< I_1 / 3 [-]

      /// Numbers per point when stored.
      static constexpr unsigned int n_numbers = 22;
    };

    /// The state at @p F [-] (det F > 0, not checked here).
    template <typename Number>
    State<Number>
    state(const dealii::Tensor<2, 3, Number> &F) const
    {
      using std::pow;
      State<Number> s;
      const Number  J = determinant(F);
      s.F             = F;
      s.FinvT         = transpose(invert(F));
      s.a             = mu * pow(J, -2.0 / 3.0);
      s.g             = (0.5 * bulk_modulus) * (J * J - 1.0);
      s.kJ2           = bulk_modulus * J * J;
      s.I1_3          = scalar_product(F, F) * (1.0 / 3.0);
      return s;
    }

    /// P [kPa] at the point of @p s.
    template <typename Number>
    dealii::Tensor<2, 3, Number>
    stress(const State<Number> &s) const
    {
      return s.a * (s.F - s.I1_3 * s.FinvT) + s.g * s.FinvT;
    }

    /// dP = (dP/dF)[H] [kPa] at the point of @p s, for the direction @p H
    /// (a displacement gradient) [-]. With dJ = J tr(F^-1 H),
    /// d(F^-T) = -F^-T H^T F^-T, dI1 = 2 F : H.
    template <typename Number>
    dealii::Tensor<2, 3, Number>
    linearization(const State<Number>                &s,
                  const dealii::Tensor<2, 3, Number> &H) const
    {
      const Number tr_H   = scalar_product(s.FinvT, H);
      const Number dI1_3  = (2.0 / 3.0) * scalar_product(s.F, H);
      const auto   dFinvT = -(s.FinvT * transpose(H) * s.FinvT);
      const Number da     = (-2.0 / 3.0) * s.a * tr_H;
      return da * (s.F - s.I1_3 * s.FinvT) +
             s.a * (H - dI1_3 * s.FinvT - s.I1_3 * dFinvT) +
             (s.kJ2 * tr_H) * s.FinvT + s.g * dFinvT;
    }

    /// P(F) and, if @p H is not null, dP = (dP/dF)[H] into @p dP (both
    /// [kPa]): state(), stress() and linearization() in one call.
    template <typename Number>
    void
    evaluate(const dealii::Tensor<2, 3, Number> &F,
             const dealii::Tensor<2, 3, Number> *H,
             dealii::Tensor<2, 3, Number>       &P,
             dealii::Tensor<2, 3, Number>       *dP) const
    {
      const State<Number> s = state(F);
      P                     = stress(s);
      if (H != nullptr)
        *dP = linearization(s, *H);
    }
  };
} // namespace systole::Mechanics
