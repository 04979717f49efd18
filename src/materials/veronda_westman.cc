#include "materials/veronda_westman.h"

#include <deal.II/physics/elasticity/standard_tensors.h>

#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  void
  VerondaWestman::Parameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Tools::to_string;
    const Parameters defaults;
    prm.declare_entry(
      "c1",
      to_string(defaults.c1),
      dealii::Patterns::Double(0.0),
      "Stress scale c1 of the Veronda-Westman energy c1 (exp(gamma (J^{-2/3} "
      "I1 - 3)) - 1) - c1 gamma/2 (J^{-4/3} I2 - 3); the small-strain shear "
      "modulus is c1 gamma. Units: kPa. Range: illustrative default 10 kPa "
      "(with gamma = 1 a shear modulus of 10 kPa, as the neo-Hookean "
      "default); must be > 0.");
    prm.declare_entry(
      "gamma",
      to_string(defaults.gamma),
      dealii::Patterns::Double(0.0),
      "Exponent gamma of the Veronda-Westman energy (it also sets the weight "
      "-c1 gamma/2 of the second invariant). Units: none. Range: "
      "illustrative default 1, of order 1-10 for soft tissue; must be > 0.");
  }


  VerondaWestman::Parameters
  VerondaWestman::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path = {"Material", law_name};
    Parameters                     p;
    p.c1    = prm.get_double(path, "c1");
    p.gamma = prm.get_double(path, "gamma");
    p.validate();
    return p;
  }


  void
  VerondaWestman::Parameters::validate() const
  {
    using dealii::Patterns::Tools::to_string;
    AssertThrow(std::isfinite(c1) && c1 > 0.0,
                dealii::ExcMessage(
                  "Material / Veronda-Westman / c1 = " + to_string(c1) +
                  " must be > 0; set e.g. 10 kPa."));
    AssertThrow(std::isfinite(gamma) && gamma > 0.0,
                dealii::ExcMessage(
                  "Material / Veronda-Westman / gamma = " + to_string(gamma) +
                  " must be > 0; set e.g. 1."));
  }


  VerondaWestman::VerondaWestman(const Parameters &parameters)
    : params(parameters)
  {
    params.validate();
  }


  void
  VerondaWestman::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    using dealii::outer_product;
    using dealii::SymmetricTensor;

    const double J = dealii::determinant(in.F);
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));

    const SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
    const SymmetricTensor<2, 3> C =
      dealii::symmetrize(dealii::transpose(in.F) * in.F);
    const SymmetricTensor<2, 3> C_inv = dealii::invert(C);
    const double                I1    = dealii::trace(C);
    const double                I2    = 0.5 * (I1 * I1 - C * C);
    const double                J_m23 = std::pow(J, -2.0 / 3.0);
    const double                J_m43 = J_m23 * J_m23;

    // Derivatives of the isochoric invariants as in mooney_rivlin.cc:
    // d Ibar1/dC = J^{-2/3} (I - I1/3 C^{-1}),
    // d Ibar2/dC = J^{-4/3} (G - 2/3 I2 C^{-1}), G = dI2/dC = I1 I - C.
    const SymmetricTensor<2, 3> dI1_bar = J_m23 * (I - (I1 / 3.0) * C_inv);
    const SymmetricTensor<2, 3> G       = I1 * I - C;
    const SymmetricTensor<2, 3> dI2_bar =
      J_m43 * (G - (2.0 * I2 / 3.0) * C_inv);

    // W_1 = dW/dIbar1 = c1 gamma e^x, W_11 = gamma W_1, W_2 = -c1 gamma/2
    // (constant), x = gamma (Ibar1 - 3).
    const double x    = params.gamma * (J_m23 * I1 - 3.0);
    const double W_1  = params.c1 * params.gamma * std::exp(x);
    const double W_11 = params.gamma * W_1;
    const double W_2  = -0.5 * params.c1 * params.gamma;

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2.
    out.psi = params.c1 * std::expm1(x) + W_2 * (J_m43 * I2 - 3.0);
    out.S   = 2.0 * (W_1 * dI1_bar + W_2 * dI2_bar);
    if (!in.with_tangent)
      return;
    const SymmetricTensor<4, 3> dC_inv_dC =
      dealii::Physics::Elasticity::StandardTensors<3>::dC_inv_dC(in.F);
    const SymmetricTensor<4, 3> d2I1_bar =
      J_m23 *
      (-(1.0 / 3.0) * (outer_product(I, C_inv) + outer_product(C_inv, I)) +
       (I1 / 9.0) * outer_product(C_inv, C_inv) - (I1 / 3.0) * dC_inv_dC);
    const SymmetricTensor<4, 3> d2I2_bar =
      J_m43 *
      (outer_product(I, I) - dealii::identity_tensor<3>() -
       (2.0 / 3.0) * (outer_product(G, C_inv) + outer_product(C_inv, G)) +
       (4.0 * I2 / 9.0) * outer_product(C_inv, C_inv) -
       (2.0 * I2 / 3.0) * dC_inv_dC);
    out.dS_dE = 4.0 * (W_11 * outer_product(dI1_bar, dI1_bar) + W_1 * d2I1_bar +
                       W_2 * d2I2_bar);
  }


  std::string
  VerondaWestman::name() const
  {
    return law_name;
  }


  const VerondaWestman::Parameters &
  VerondaWestman::parameters() const
  {
    return params;
  }
} // namespace systole::Materials
