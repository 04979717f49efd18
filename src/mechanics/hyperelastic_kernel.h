#pragma once

// The quadrature-point kernel of the matrix-free mechanics operator
// (MatrixFreeTangent): first Piola-Kirchhoff stress and its directional
// derivative from one function, templated on the number type so that the
// same code runs on deal.II's VectorizedArray (a batch of cells) and on
// double (a future matrix-based path). Only deal.II's tensor header here.

#include <deal.II/base/tensor.h>

#include <cmath>

namespace systole::Mechanics
{
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
  struct NeoHookeanPenalty
  {
    double mu           = 10.0;   ///< shear modulus [kPa], > 0
    double bulk_modulus = 1000.0; ///< kappa [kPa], >= 0

    /// P(F) and, if @p H is not null, the directional derivative
    /// @f$dP = \frac{\partial P}{\partial F}[H]@f$ into @p dP (both [kPa]).
    /// The residual and the tangent (its action, and the cached 9 x 9
    /// tangent, built column by column) all come from this one function.
    /// @param[in] F deformation gradient [-], det F > 0 (not checked here).
    /// @param[in] H direction (a displacement gradient) [-], or nullptr.
    template <typename Number>
    void
    evaluate(const dealii::Tensor<2, 3, Number> &F,
             const dealii::Tensor<2, 3, Number> *H,
             dealii::Tensor<2, 3, Number>       &P,
             dealii::Tensor<2, 3, Number>       *dP) const
    {
      using std::pow;
      const Number J     = determinant(F);
      const auto   FinvT = transpose(invert(F));
      const Number I1    = scalar_product(F, F);
      const Number a     = mu * pow(J, -2.0 / 3.0);              // mu J^{-2/3}
      const Number g     = (0.5 * bulk_modulus) * (J * J - 1.0); // J U'(J)
      const auto   dev   = F - (I1 * (1.0 / 3.0)) * FinvT;
      P                  = a * dev + g * FinvT;
      if (H == nullptr)
        return;

      // dJ = J tr(F^-1 H), d(F^-T) = -F^-T H^T F^-T, dI1 = 2 F : H.
      const Number tr_H   = scalar_product(FinvT, *H);
      const Number dI1    = 2.0 * scalar_product(F, *H);
      const auto   dFinvT = -(FinvT * transpose(*H) * FinvT);
      const Number da     = (-2.0 / 3.0) * a * tr_H;
      const Number dg     = bulk_modulus * J * J * tr_H;
      *dP =
        da * dev +
        a * (*H - (dI1 * (1.0 / 3.0)) * FinvT - (I1 * (1.0 / 3.0)) * dFinvT) +
        dg * FinvT + g * dFinvT;
    }
  };
} // namespace systole::Mechanics
