#include "materials/isochoric_part.h"

#include <deal.II/physics/elasticity/standard_tensors.h>

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
    const SymmetricTensor<4, 3> identity = dealii::identity_tensor<3>();
    const SymmetricTensor<4, 3> P =
      identity - (1.0 / 3.0) * dealii::outer_product(C_inv, C);
    const SymmetricTensor<4, 3> P_T =
      identity - (1.0 / 3.0) * dealii::outer_product(C, C_inv);
    // C^-1 (.) C^-1 = -dC^-1/dC (deal.II's dC_inv_dC).
    const SymmetricTensor<4, 3> P_tilde =
      -dealii::Physics::Elasticity::StandardTensors<3>::dC_inv_dC(in.F) -
      (1.0 / 3.0) * dealii::outer_product(C_inv, C_inv);
    out.dS_dE = (J_m23 * J_m23) * (P * law_out.dS_dE * P_T) +
                (2.0 / 3.0) * trace * P_tilde -
                (2.0 / 3.0) * (dealii::outer_product(C_inv, S) +
                               dealii::outer_product(S, C_inv));
  }

  std::string
  IsochoricPart::name() const
  {
    return law.name() + " (isochoric part)";
  }
} // namespace systole::Materials
