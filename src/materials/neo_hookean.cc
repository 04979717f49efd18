#include "materials/neo_hookean.h"

#include <deal.II/physics/elasticity/standard_tensors.h>

#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  void
  NeoHookean::Parameters::declare(dealii::ParameterHandler &prm)
  {
    prm.declare_entry(
      "mu",
      dealii::Patterns::Tools::to_string(Parameters().mu),
      dealii::Patterns::Double(0.0),
      "Shear modulus of the isochoric neo-Hookean energy mu/2 (J^{-2/3} I1 - "
      "3). Units: kPa. Range: illustrative default 10 kPa; passive "
      "myocardium is of order 1-10 kPa at small strain; must be > 0.");
  }


  NeoHookean::Parameters
  NeoHookean::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    Parameters p;
    p.mu = prm.get_double({"Material", law_name}, "mu");
    p.validate();
    return p;
  }


  void
  NeoHookean::Parameters::validate() const
  {
    AssertThrow(std::isfinite(mu) && mu > 0.0,
                dealii::ExcMessage(
                  "Material / neo-Hookean / mu = " +
                  dealii::Patterns::Tools::to_string(mu) +
                  " must be > 0; set a positive shear modulus (e.g. 10 kPa)."));
  }


  NeoHookean::NeoHookean(const Parameters &parameters)
    : params(parameters)
  {
    params.validate();
  }


  void
  NeoHookean::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    using dealii::SymmetricTensor;

    const double J = dealii::determinant(in.F);
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));

    const SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
    const SymmetricTensor<2, 3> C =
      dealii::symmetrize(dealii::transpose(in.F) * in.F);
    const SymmetricTensor<2, 3> C_inv  = dealii::invert(C);
    const double                I1     = dealii::trace(C);
    const double                J_m23  = std::pow(J, -2.0 / 3.0);
    const double                I1_bar = J_m23 * I1;

    // d Ibar1/dC = J^{-2/3} (I - I1/3 C^{-1}), and its derivative (Holzapfel
    // 2000, sec. 6.6) written with dC^{-1}/dC = -C^{-1} (.) C^{-1}.
    const SymmetricTensor<2, 3> dI1_bar = J_m23 * (I - (I1 / 3.0) * C_inv);
    const SymmetricTensor<4, 3> d2I1_bar =
      J_m23 *
      (-(1.0 / 3.0) *
         (dealii::outer_product(I, C_inv) + dealii::outer_product(C_inv, I)) +
       (I1 / 9.0) * dealii::outer_product(C_inv, C_inv) -
       (I1 / 3.0) *
         dealii::Physics::Elasticity::StandardTensors<3>::dC_inv_dC(in.F));

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2.
    out.psi   = 0.5 * params.mu * (I1_bar - 3.0);
    out.S     = params.mu * dI1_bar;
    out.dS_dE = (2.0 * params.mu) * d2I1_bar;
  }


  std::string
  NeoHookean::name() const
  {
    return law_name;
  }


  const NeoHookean::Parameters &
  NeoHookean::parameters() const
  {
    return params;
  }
} // namespace systole::Materials
