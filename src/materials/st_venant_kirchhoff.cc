#include "materials/st_venant_kirchhoff.h"

#include <cmath>

namespace systole::Materials
{
  void
  StVenantKirchhoffParameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Tools::to_string;
    const StVenantKirchhoffParameters defaults;
    prm.declare_entry(
      "lambda",
      to_string(defaults.lambda),
      dealii::Patterns::Double(0.0),
      "First Lame parameter, weight of (tr E)^2 / 2. Units: kPa. Range: "
      "illustrative default 40 kPa (Poisson ratio 0.4 with mu = 10 kPa); "
      ">= 0.");
    prm.declare_entry(
      "mu",
      to_string(defaults.mu),
      dealii::Patterns::Double(0.0),
      "Shear modulus, weight of E:E. Units: kPa. Range: illustrative default "
      "10 kPa; must be > 0.");
  }


  StVenantKirchhoffParameters
  StVenantKirchhoffParameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path = {"Material", law_name};
    StVenantKirchhoffParameters    p;
    p.lambda = prm.get_double(path, "lambda");
    p.mu     = prm.get_double(path, "mu");
    p.validate();
    return p;
  }


  void
  StVenantKirchhoffParameters::validate() const
  {
    require_in_range(Range::non_negative,
                     law_name,
                     "lambda",
                     lambda,
                     "set e.g. 40 kPa");
    require_in_range(Range::positive, law_name, "mu", mu, "set e.g. 10 kPa");
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
