#include "materials/isochoric_invariants.h"

#include <deal.II/physics/elasticity/standard_tensors.h>

#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  IsochoricInvariants
  isochoric_invariants(const PassiveInput &in, const InvariantSet which)
  {
    using dealii::outer_product;
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

    const SymmetricTensor<4, 3> dC_inv_dC =
      dealii::Physics::Elasticity::StandardTensors<3>::dC_inv_dC(in.F);
    inv.d2I1_bar =
      inv.J_m23 *
      (-(1.0 / 3.0) * (outer_product(I, C_inv) + outer_product(C_inv, I)) +
       (I1 / 9.0) * outer_product(C_inv, C_inv) - (I1 / 3.0) * dC_inv_dC);
    // d2I2/dC2 = I x I - II.
    if (second)
      inv.d2I2_bar =
        inv.J_m43 *
        (outer_product(I, I) - dealii::identity_tensor<3>() -
         (2.0 / 3.0) * (outer_product(G, C_inv) + outer_product(C_inv, G)) +
         (4.0 * inv.I2 / 9.0) * outer_product(C_inv, C_inv) -
         (2.0 * inv.I2 / 3.0) * dC_inv_dC);
    return inv;
  }
} // namespace systole::Materials
