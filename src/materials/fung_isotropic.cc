#include "materials/fung_isotropic.h"

#include "materials/isochoric_invariants.h"

#include <cmath>

namespace systole::Materials
{
  void
  FungIsotropicParameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Tools::to_string;
    const FungIsotropicParameters defaults;
    prm.declare_entry(
      "mu",
      to_string(defaults.mu),
      dealii::Patterns::Double(0.0),
      "Stress scale mu of the isochoric Fung energy mu/2 (exp(gamma "
      "(J^{-2/3} I1 - 3)) - 1); the small-strain shear modulus is mu gamma. "
      "Units: kPa. Range: illustrative default 10 kPa (with gamma = 1 a "
      "shear modulus of 10 kPa, as the neo-Hookean default); must be > 0.");
    prm.declare_entry(
      "gamma",
      to_string(defaults.gamma),
      dealii::Patterns::Double(0.0),
      "Exponent gamma of the isochoric Fung energy: how fast the law "
      "stiffens with J^{-2/3} I1 - 3 (gamma -> 0 with mu gamma fixed gives "
      "neo-Hookean; gamma = 1/2, mu = C is the small-strain match of the "
      "isotropic Guccione law of Land problem 2). Units: none. Range: "
      "illustrative default 1, of order 1-10 for soft tissue; must be > 0.");
  }


  FungIsotropicParameters
  FungIsotropicParameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path = {"Material", law_name};
    FungIsotropicParameters        p;
    p.mu    = prm.get_double(path, "mu");
    p.gamma = prm.get_double(path, "gamma");
    p.validate();
    return p;
  }


  void
  FungIsotropicParameters::validate() const
  {
    require_in_range(Range::positive, law_name, "mu", mu, "set e.g. 10 kPa");
    require_in_range(
      Range::positive,
      law_name,
      "gamma",
      gamma,
      "set e.g. 1 (for gamma = 0 use neo-Hookean with mu = the shear modulus)");
  }


  void
  FungIsotropic::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    const IsochoricInvariants inv =
      isochoric_invariants(in, InvariantSet::Ibar1);
    const double x = params.gamma * (inv.I1_bar - 3.0);

    // W = mu/2 (e^x - 1): W_1 = dW/dIbar1 = mu gamma/2 e^x,
    // W_11 = gamma W_1; expm1 keeps W accurate at small strain.
    const double W_1  = 0.5 * params.mu * params.gamma * std::exp(x);
    const double W_11 = params.gamma * W_1;

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2.
    out.psi = 0.5 * params.mu * std::expm1(x);
    out.S   = (2.0 * W_1) * inv.dI1_bar;
    if (!in.with_tangent)
      return;
    out.dS_dE = 4.0 * (W_11 * dealii::outer_product(inv.dI1_bar, inv.dI1_bar) +
                       W_1 * inv.d2I1_bar);
  }


} // namespace systole::Materials
