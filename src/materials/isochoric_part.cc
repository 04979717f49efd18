#include "materials/isochoric_part.h"

#include "materials/symmetric_tensor_ops.h"
#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  IsochoricPart::IsochoricPart(const PassiveLaw &law)
    : law(law)
  {}

  void
  IsochoricPart::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    using dealii::SymmetricTensor;
    const double J = dealii::determinant(in.F);
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    PassiveInput bar = in;
    bar.F            = std::cbrt(1.0 / J) * in.F;
    PassiveOutput law_out;
    law.evaluate(bar, law_out);

    const SymmetricTensor<2, 3> C =
      dealii::symmetrize(dealii::transpose(in.F) * in.F);
    const SymmetricTensor<2, 3> C_inv = dealii::invert(C);
    const double                J_m23 = std::pow(J, -2.0 / 3.0);
    const SymmetricTensor<2, 3> S_bar = law_out.S;
    const double                trace = J_m23 * (S_bar * C);
    // S = J^-2/3 P : S_bar with P = I - C^-1 x C / 3.
    const SymmetricTensor<2, 3> S = J_m23 * S_bar - (trace / 3.0) * C_inv;
    out.psi                       = law_out.psi;
    out.S                         = S;
    if (!in.with_tangent)
      return;
    // P : D : P^T = D - (C^-1 x (C : D) + (D : C) x C^-1) / 3
    //   + (C : D : C) C^-1 x C^-1 / 9, D = dS_bar/dE_bar (P = I - C^-1 x
    // C / 3 is a rank-one update of the identity).
    namespace ops                      = SymmetricOps;
    const SymmetricTensor<4, 3> &D     = law_out.dS_dE;
    const SymmetricTensor<2, 3>  C_D   = ops::contract(C, D);
    const SymmetricTensor<2, 3>  D_C   = ops::contract(D, C);
    const double                 J_m43 = J_m23 * J_m23;
    out.dS_dE                          = J_m43 * D;
    ops::add_outer(out.dS_dE, -J_m43 / 3.0, C_inv, C_D);
    ops::add_outer(out.dS_dE, -J_m43 / 3.0, D_C, C_inv);
    ops::add_outer(out.dS_dE, J_m43 * (C_D * C) / 9.0, C_inv, C_inv);
    // + 2/3 tr P_tilde, P_tilde = C^-1 (.) C^-1 - C^-1 x C^-1 / 3
    // (C^-1 (.) C^-1 = -dC^-1/dC); - 2/3 (C^-1 x S + S x C^-1).
    ops::add_symmetric_product(out.dS_dE, (2.0 / 3.0) * trace, C_inv);
    ops::add_outer(out.dS_dE, -(2.0 / 9.0) * trace, C_inv, C_inv);
    ops::add_symmetric_outer(out.dS_dE, -2.0 / 3.0, C_inv, S);
  }

  std::string
  IsochoricPart::name() const
  {
    return law.name() + " (isochoric part)";
  }
} // namespace systole::Materials
