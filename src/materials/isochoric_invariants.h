#pragma once

#include <deal.II/base/symmetric_tensor.h>

#include "materials/passive_law.h"

namespace systole::Materials
{
  /// Which isochoric invariants isochoric_invariants() computes.
  enum class InvariantSet
  {
    Ibar1,          ///< @f$\bar I_1@f$ only
    Ibar1_and_Ibar2 ///< @f$\bar I_1@f$ and @f$\bar I_2@f$
  };

  /// The isochoric invariants @f$\bar I_1 = J^{-2/3} I_1@f$,
  /// @f$\bar I_2 = J^{-4/3} I_2@f$ of @f$C = F^T F@f$ and their derivatives
  /// with respect to C, shared by the isotropic passive laws (Holzapfel 2000,
  /// Nonlinear Solid Mechanics, sec. 6.6):
  /// @f$\partial\bar I_1/\partial C = J^{-2/3}(I - \frac13 I_1 C^{-1})@f$,
  /// @f$\partial\bar I_2/\partial C = J^{-4/3}(G - \frac23 I_2 C^{-1})@f$
  /// with @f$G = \partial I_2/\partial C = I_1 I - C@f$, and the second
  /// derivatives written with @f$\partial C^{-1}/\partial C = -C^{-1}\odot
  /// C^{-1}@f$. A law then has @f$S = 2\,\partial W/\partial C@f$ and
  /// @f$dS/dE = 4\,\partial^2 W/\partial C^2@f$ from its own
  /// @f$\partial W/\partial\bar I_a@f$.
  struct IsochoricInvariants
  {
    dealii::SymmetricTensor<2, 3> C; ///< right Cauchy-Green tensor F^T F [-]
    double                        J  = 1.0; ///< det F [-]
    double                        I1 = 3.0; ///< tr C [-]
    double I2     = 3.0; ///< (I1^2 - C:C)/2 [-] (Ibar1_and_Ibar2 only)
    double J_m23  = 1.0; ///< J^{-2/3} [-]
    double J_m43  = 1.0; ///< J^{-4/3} [-]
    double I1_bar = 3.0; ///< J^{-2/3} I1 [-]
    double I2_bar = 3.0; ///< J^{-4/3} I2 [-] (Ibar1_and_Ibar2 only)
    dealii::SymmetricTensor<2, 3> dI1_bar; ///< d Ibar1/dC [-]
    dealii::SymmetricTensor<2, 3> dI2_bar; ///< d Ibar2/dC [-] (Ibar1_and_Ibar2)
    /// d2 Ibar1/dC2 [-] (only when PassiveInput::with_tangent)
    dealii::SymmetricTensor<4, 3> d2I1_bar;
    /// d2 Ibar2/dC2 [-] (only with tangent and Ibar1_and_Ibar2)
    dealii::SymmetricTensor<4, 3> d2I2_bar;
  };

  /// Invariants of in.F and their derivatives (see IsochoricInvariants); the
  /// second derivatives only when in.with_tangent is true, the members for
  /// Ibar2 only for InvariantSet::Ibar1_and_Ibar2 (else left at their
  /// defaults).
  /// @throws ExcNonPositiveVolumeRatio if det F <= 0.
  IsochoricInvariants
  isochoric_invariants(const PassiveInput &in, const InvariantSet which);
} // namespace systole::Materials
