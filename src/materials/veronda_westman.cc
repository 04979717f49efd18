#include "materials/veronda_westman.h"

#include "materials/isochoric_invariants.h"

#include <cmath>

namespace systole::Materials
{
  const std::vector<LawEntry<VerondaWestmanParameters>> &
  VerondaWestmanParameters::entries()
  {
    using P                                     = VerondaWestmanParameters;
    static const std::vector<LawEntry<P>> table = {
      {"c1",
       &P::c1,
       Range::positive,
       "Stress scale c1 of the Veronda-Westman energy c1 (exp(gamma (J^{-2/3} "
       "I1 - 3)) - 1) - c1 gamma/2 (J^{-4/3} I2 - 3); the small-strain shear "
       "modulus is c1 gamma. Units: kPa. Range: illustrative default 10 kPa "
       "(with gamma = 1 a shear modulus of 10 kPa, as the neo-Hookean "
       "default); must be > 0.",
       "set e.g. 10 kPa"},
      {"gamma",
       &P::gamma,
       Range::positive,
       "Exponent gamma of the Veronda-Westman energy (it also sets the weight "
       "-c1 gamma/2 of the second invariant). Units: none. Range: "
       "illustrative default 1, of order 1-10 for soft tissue; must be > 0.",
       "set e.g. 1"}};
    return table;
  }


  void
  VerondaWestman::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    const IsochoricInvariants inv =
      isochoric_invariants(in, InvariantSet::Ibar1_and_Ibar2);

    // W_1 = dW/dIbar1 = c1 gamma e^x, W_11 = gamma W_1, W_2 = -c1 gamma/2
    // (constant), x = gamma (Ibar1 - 3).
    const double x    = params.gamma * (inv.I1_bar - 3.0);
    const double W_1  = params.c1 * params.gamma * std::exp(x);
    const double W_11 = params.gamma * W_1;
    const double W_2  = -0.5 * params.c1 * params.gamma;

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2.
    out.psi = params.c1 * std::expm1(x) + W_2 * (inv.I2_bar - 3.0);
    out.S   = 2.0 * (W_1 * inv.dI1_bar + W_2 * inv.dI2_bar);
    if (!in.with_tangent)
      return;
    out.dS_dE = 4.0 * (W_11 * dealii::outer_product(inv.dI1_bar, inv.dI1_bar) +
                       W_1 * inv.d2I1_bar + W_2 * inv.d2I2_bar);
  }


} // namespace systole::Materials
