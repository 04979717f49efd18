#include "materials/st_venant_kirchhoff.h"

#include <cmath>

namespace systole::Materials
{
  const std::vector<LawEntry<StVenantKirchhoffParameters>> &
  StVenantKirchhoffParameters::entries()
  {
    using P                                     = StVenantKirchhoffParameters;
    static const std::vector<LawEntry<P>> table = {
      {"lambda",
       &P::lambda,
       Range::non_negative,
       "First Lame parameter, weight of (tr E)^2 / 2. Units: kPa. Range: "
       "illustrative default 40 kPa (Poisson ratio 0.4 with mu = 10 kPa); "
       ">= 0.",
       "set e.g. 40 kPa"},
      {"mu",
       &P::mu,
       Range::positive,
       "Shear modulus, weight of E:E. Units: kPa. Range: illustrative default "
       "10 kPa; must be > 0.",
       "set e.g. 10 kPa"}};
    return table;
  }


  void
  StVenantKirchhoff::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    const dealii::SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
    const dealii::SymmetricTensor<2, 3> E =
      0.5 * (dealii::symmetrize(dealii::transpose(in.F) * in.F) - I);
    const double tr_E = dealii::trace(E);

    out.psi   = 0.5 * params.lambda * tr_E * tr_E + params.mu * (E * E);
    out.S     = (params.lambda * tr_E) * I + (2.0 * params.mu) * E;
    out.dS_dE = params.lambda * dealii::outer_product(I, I) +
                (2.0 * params.mu) * dealii::identity_tensor<3>();
  }


} // namespace systole::Materials
