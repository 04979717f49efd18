#include "materials/mooney_rivlin.h"

#include "materials/isochoric_invariants.h"

#include <cmath>

namespace systole::Materials
{
  const std::vector<LawEntry<MooneyRivlinParameters>> &
  MooneyRivlinParameters::entries()
  {
    using P                                     = MooneyRivlinParameters;
    static const std::vector<LawEntry<P>> table = {
      {"c1",
       &P::c1,
       Range::non_negative,
       "Weight of the isochoric first invariant, c1 (J^{-2/3} I1 - 3). Units: "
       "kPa. Range: illustrative default 4 kPa (small-strain shear modulus "
       "2 (c1 + c2) = 10 kPa); >= 0, with c1 + c2 > 0.",
       "set e.g. 4 kPa"},
      {"c2",
       &P::c2,
       Range::non_negative,
       "Weight of the isochoric second invariant, c2 (J^{-4/3} I2 - 3). Units: "
       "kPa. Range: illustrative default 1 kPa; >= 0 (0 gives neo-Hookean with "
       "mu = 2 c1), with c1 + c2 > 0.",
       "set e.g. 1 kPa"}};
    return table;
  }


  void
  MooneyRivlinParameters::validate_more() const
  {
    AssertThrow(c1 + c2 > 0.0,
                dealii::ExcMessage(
                  "Material / Mooney-Rivlin / c1 and c2 are both zero, which "
                  "leaves no shear stiffness; set c1 > 0 (e.g. 4 kPa)."));
  }


  void
  MooneyRivlin::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    const IsochoricInvariants inv =
      isochoric_invariants(in, InvariantSet::Ibar1_and_Ibar2);

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2 (W linear in the invariants).
    out.psi = params.c1 * (inv.I1_bar - 3.0) + params.c2 * (inv.I2_bar - 3.0);
    out.S   = 2.0 * (params.c1 * inv.dI1_bar + params.c2 * inv.dI2_bar);
    if (!in.with_tangent)
      return;
    out.dS_dE = 4.0 * (params.c1 * inv.d2I1_bar + params.c2 * inv.d2I2_bar);
  }


} // namespace systole::Materials
