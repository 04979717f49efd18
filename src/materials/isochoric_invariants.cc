#include "materials/isochoric_invariants.h"

#include "materials/symmetric_tensor_ops.h"
#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  IsochoricInvariants
  isochoric_invariants(const PassiveInput &in, const InvariantSet which)
  {
    using dealii::SymmetricTensor;

    IsochoricInvariants inv;
    inv.J = dealii::determinant(in.F);
    AssertThrow(inv.J > 0.0, ExcNonPositiveVolumeRatio(inv.J));

    const SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
    inv.C = dealii::symmetrize(dealii::transpose(in.F) * in.F);
    const SymmetricTensor<2, 3> &C     = inv.C;
    const SymmetricTensor<2, 3>  C_inv = dealii::invert(C);
    const bool   second = (which == InvariantSet::Ibar1_and_Ibar2);
    const double I1     = dealii::trace(C);
    inv.I1              = I1;
    inv.J_m23           = std::pow(inv.J, -2.0 / 3.0);
    inv.J_m43           = inv.J_m23 * inv.J_m23;
    inv.I1_bar          = inv.J_m23 * I1;
    inv.dI1_bar         = inv.J_m23 * (I - (I1 / 3.0) * C_inv);

    // G = dI2/dC.
    const SymmetricTensor<2, 3> G = I1 * I - C;
    if (second)
      {
        inv.I2      = 0.5 * (I1 * I1 - C * C);
        inv.I2_bar  = inv.J_m43 * inv.I2;
        inv.dI2_bar = inv.J_m43 * (G - (2.0 * inv.I2 / 3.0) * C_inv);
      }
    if (!in.with_tangent)
      return inv;

    // On the raw storage (SymmetricOps): dC^-1/dC = -C^-1 (.) C^-1.
    namespace ops  = SymmetricOps;
    const double a = inv.J_m23;
    inv.d2I1_bar   = SymmetricTensor<4, 3>();
    ops::add_symmetric_product(inv.d2I1_bar, a * I1 / 3.0, C_inv);
    ops::add_symmetric_outer(inv.d2I1_bar, -a / 3.0, I, C_inv);
    ops::add_outer(inv.d2I1_bar, a * I1 / 9.0, C_inv, C_inv);
    // d2I2/dC2 = I x I - II (II = I (.) I).
    if (second)
      {
        const double b = inv.J_m43;
        inv.d2I2_bar   = SymmetricTensor<4, 3>();
        ops::add_outer(inv.d2I2_bar, b, I, I);
        ops::add_symmetric_product(inv.d2I2_bar, -b, I);
        ops::add_symmetric_outer(inv.d2I2_bar, -2.0 * b / 3.0, G, C_inv);
        ops::add_outer(inv.d2I2_bar, 4.0 * b * inv.I2 / 9.0, C_inv, C_inv);
        ops::add_symmetric_product(inv.d2I2_bar, 2.0 * b * inv.I2 / 3.0, C_inv);
      }
    return inv;
  }
} // namespace systole::Materials
