#include "materials/mooney_rivlin.h"

#include <deal.II/physics/elasticity/standard_tensors.h>

#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  void
  MooneyRivlin::Parameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Tools::to_string;
    const Parameters defaults;
    prm.declare_entry(
      "c1",
      to_string(defaults.c1),
      dealii::Patterns::Double(0.0),
      "Weight of the isochoric first invariant, c1 (J^{-2/3} I1 - 3). Units: "
      "kPa. Range: illustrative default 4 kPa (small-strain shear modulus "
      "2 (c1 + c2) = 10 kPa); >= 0, with c1 + c2 > 0.");
    prm.declare_entry(
      "c2",
      to_string(defaults.c2),
      dealii::Patterns::Double(0.0),
      "Weight of the isochoric second invariant, c2 (J^{-4/3} I2 - 3). Units: "
      "kPa. Range: illustrative default 1 kPa; >= 0 (0 gives neo-Hookean with "
      "mu = 2 c1), with c1 + c2 > 0.");
  }


  MooneyRivlin::Parameters
  MooneyRivlin::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path = {"Material", law_name};
    Parameters                     p;
    p.c1 = prm.get_double(path, "c1");
    p.c2 = prm.get_double(path, "c2");
    p.validate();
    return p;
  }


  void
  MooneyRivlin::Parameters::validate() const
  {
    using dealii::Patterns::Tools::to_string;
    AssertThrow(std::isfinite(c1) && c1 >= 0.0,
                dealii::ExcMessage(
                  "Material / Mooney-Rivlin / c1 = " + to_string(c1) +
                  " must be >= 0; set e.g. 4 kPa."));
    AssertThrow(std::isfinite(c2) && c2 >= 0.0,
                dealii::ExcMessage(
                  "Material / Mooney-Rivlin / c2 = " + to_string(c2) +
                  " must be >= 0; set e.g. 1 kPa."));
    AssertThrow(c1 + c2 > 0.0,
                dealii::ExcMessage(
                  "Material / Mooney-Rivlin / c1 and c2 are both zero, which "
                  "leaves no shear stiffness; set c1 > 0 (e.g. 4 kPa)."));
  }


  MooneyRivlin::MooneyRivlin(const Parameters &parameters)
    : params(parameters)
  {
    params.validate();
  }


  void
  MooneyRivlin::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    using dealii::outer_product;
    using dealii::SymmetricTensor;

    const double J = dealii::determinant(in.F);
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));

    const SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
    const SymmetricTensor<2, 3> C =
      dealii::symmetrize(dealii::transpose(in.F) * in.F);
    const SymmetricTensor<2, 3> C_inv = dealii::invert(C);
    const SymmetricTensor<4, 3> dC_inv_dC =
      dealii::Physics::Elasticity::StandardTensors<3>::dC_inv_dC(in.F);
    const double I1    = dealii::trace(C);
    const double I2    = 0.5 * (I1 * I1 - C * C);
    const double J_m23 = std::pow(J, -2.0 / 3.0);
    const double J_m43 = J_m23 * J_m23;

    // First invariant: d Ibar1/dC = J^{-2/3} (I - I1/3 C^{-1}).
    const SymmetricTensor<2, 3> dI1_bar = J_m23 * (I - (I1 / 3.0) * C_inv);
    const SymmetricTensor<4, 3> d2I1_bar =
      J_m23 *
      (-(1.0 / 3.0) * (outer_product(I, C_inv) + outer_product(C_inv, I)) +
       (I1 / 9.0) * outer_product(C_inv, C_inv) - (I1 / 3.0) * dC_inv_dC);

    // Second invariant: dI2/dC = I1 I - C =: G, d2I2/dC2 = I x I - II, and
    // d Ibar2/dC = J^{-4/3} (G - 2/3 I2 C^{-1}).
    const SymmetricTensor<2, 3> G = I1 * I - C;
    const SymmetricTensor<2, 3> dI2_bar =
      J_m43 * (G - (2.0 * I2 / 3.0) * C_inv);
    const SymmetricTensor<4, 3> d2I2_bar =
      J_m43 *
      (outer_product(I, I) - dealii::identity_tensor<3>() -
       (2.0 / 3.0) * (outer_product(G, C_inv) + outer_product(C_inv, G)) +
       (4.0 * I2 / 9.0) * outer_product(C_inv, C_inv) -
       (2.0 * I2 / 3.0) * dC_inv_dC);

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2 (W linear in the invariants).
    out.psi   = params.c1 * (J_m23 * I1 - 3.0) + params.c2 * (J_m43 * I2 - 3.0);
    out.S     = 2.0 * (params.c1 * dI1_bar + params.c2 * dI2_bar);
    out.dS_dE = 4.0 * (params.c1 * d2I1_bar + params.c2 * d2I2_bar);
  }


  std::string
  MooneyRivlin::name() const
  {
    return law_name;
  }


  const MooneyRivlin::Parameters &
  MooneyRivlin::parameters() const
  {
    return params;
  }
} // namespace systole::Materials
