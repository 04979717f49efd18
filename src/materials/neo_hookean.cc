#include "materials/neo_hookean.h"

#include "materials/isochoric_invariants.h"

#include <cmath>

namespace systole::Materials
{
  const std::vector<LawEntry<NeoHookeanParameters>> &
  NeoHookeanParameters::entries()
  {
    static const std::vector<LawEntry<NeoHookeanParameters>> table = {
      {"mu",
       &NeoHookeanParameters::mu,
       Range::positive,
       "Shear modulus of the isochoric neo-Hookean energy mu/2 (J^{-2/3} I1 - "
       "3). Units: kPa. Range: illustrative default 10 kPa; passive "
       "myocardium is of order 1-10 kPa at small strain; must be > 0.",
       "set a positive shear modulus (e.g. 10 kPa)"}};
    return table;
  }


  void
  NeoHookean::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    const IsochoricInvariants inv =
      isochoric_invariants(in, InvariantSet::Ibar1);

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2.
    out.psi = 0.5 * params.mu * (inv.I1_bar - 3.0);
    out.S   = params.mu * inv.dI1_bar;
    if (!in.with_tangent)
      return;
    out.dS_dE = (2.0 * params.mu) * inv.d2I1_bar;
  }


} // namespace systole::Materials
