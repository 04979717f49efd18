#include "materials/fung_isotropic.h"

#include "materials/isochoric_invariants.h"

#include <cmath>

namespace systole::Materials
{
  const std::vector<LawEntry<FungIsotropicParameters>> &
  FungIsotropicParameters::entries()
  {
    using P                                     = FungIsotropicParameters;
    static const std::vector<LawEntry<P>> table = {
      {"mu",
       &P::mu,
       Range::positive,
       "Stress scale mu of the isochoric Fung energy mu/2 (exp(gamma "
       "(J^{-2/3} I1 - 3)) - 1); the small-strain shear modulus is mu gamma. "
       "Units: kPa. Range: illustrative default 10 kPa (with gamma = 1 a "
       "shear modulus of 10 kPa, as the neo-Hookean default); must be > 0.",
       "set e.g. 10 kPa"},
      {"gamma",
       &P::gamma,
       Range::positive,
       "Exponent gamma of the isochoric Fung energy: how fast the law "
       "stiffens with J^{-2/3} I1 - 3 (gamma -> 0 with mu gamma fixed gives "
       "neo-Hookean; gamma = 1/2, mu = C is the small-strain match of the "
       "isotropic Guccione law of Land problem 2). Units: none. Range: "
       "illustrative default 1, of order 1-10 for soft tissue; must be > 0.",
       "set e.g. 1 (for gamma = 0 use neo-Hookean with mu = the shear "
       "modulus)"}};
    return table;
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
