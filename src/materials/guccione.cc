#include "materials/guccione.h"

#include <array>
#include <cmath>

namespace systole::Materials
{
  void
  GuccioneParameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Tools::to_string;
    const GuccioneParameters defaults;
    prm.declare_entry(
      "C",
      to_string(defaults.C),
      dealii::Patterns::Double(0.0),
      "Overall stiffness multiplying exp(Q) - 1. Units: kPa. Source: Land et "
      "al. 2015 problems 1 and 3 (2 kPa); canine fit about 0.88 kPa "
      "(Guccione 1991); must be > 0.");
    prm.declare_entry(
      "b_f",
      to_string(defaults.b_f),
      dealii::Patterns::Double(0.0),
      "Weight of the fibre strain E_ff^2 in Q. Units: none. Source: Land et "
      "al. 2015 (8); canine fit about 18.5 (Guccione 1991); must be > 0.");
    prm.declare_entry(
      "b_t",
      to_string(defaults.b_t),
      dealii::Patterns::Double(0.0),
      "Weight of the cross-fibre strains E_ss^2 + E_nn^2 + 2 E_sn^2 in Q. "
      "Units: none. Source: Land et al. 2015 (2); canine fit about 3.6 "
      "(Guccione 1991); must be > 0.");
    prm.declare_entry(
      "b_fs",
      to_string(defaults.b_fs),
      dealii::Patterns::Double(0.0),
      "Weight of the fibre shears 2 (E_fs^2 + E_fn^2) in Q. Units: none. "
      "Source: Land et al. 2015 (4); canine fit about 1.6 (Guccione 1991); "
      "must be > 0.");
  }


  GuccioneParameters
  GuccioneParameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path = {"Material", law_name};
    GuccioneParameters             p;
    p.C    = prm.get_double(path, "C");
    p.b_f  = prm.get_double(path, "b_f");
    p.b_t  = prm.get_double(path, "b_t");
    p.b_fs = prm.get_double(path, "b_fs");
    p.validate();
    return p;
  }


  void
  GuccioneParameters::validate() const
  {
    require_in_range(Range::positive,
                     law_name,
                     "C",
                     C,
                     "set e.g. 2 kPa, Land et al. 2015");
    require_in_range(Range::positive,
                     law_name,
                     "b_f",
                     b_f,
                     "set e.g. 8, Land et al. 2015");
    require_in_range(Range::positive,
                     law_name,
                     "b_t",
                     b_t,
                     "set e.g. 2, Land et al. 2015");
    require_in_range(Range::positive,
                     law_name,
                     "b_fs",
                     b_fs,
                     "set e.g. 4, Land et al. 2015");
  }


  void
  Guccione::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    using dealii::SymmetricTensor;

    const SymmetricTensor<2, 3> E =
      0.5 * (dealii::symmetrize(dealii::transpose(in.F) * in.F) -
             dealii::unit_symmetric_tensor<3>());

    const std::array<dealii::Tensor<1, 3>, 3> axes = {
      {in.basis.f, in.basis.s, in.basis.n}};
    const double weight[3][3] = {{params.b_f, params.b_fs, params.b_fs},
                                 {params.b_fs, params.b_t, params.b_t},
                                 {params.b_fs, params.b_t, params.b_t}};

    // Sum over the six independent local components E_ab = M_ab : E with
    // M_ab = sym(a x b); an off-diagonal pair appears twice in Q.
    double                Q = 0.0;
    SymmetricTensor<2, 3> H;  // dQ/dE / 2
    SymmetricTensor<4, 3> dH; // dH/dE
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = a; b < 3; ++b)
        {
          const SymmetricTensor<2, 3> M =
            dealii::symmetrize(dealii::outer_product(axes[a], axes[b]));
          const double E_ab = M * E;
          const double w    = (a == b ? 1.0 : 2.0) * weight[a][b];
          Q += w * E_ab * E_ab;
          H += (w * E_ab) * M;
          if (in.with_tangent)
            dH += w * dealii::outer_product(M, M);
        }

    const double exp_Q = std::exp(Q);
    out.psi            = 0.5 * params.C * std::expm1(Q);
    out.S              = (params.C * exp_Q) * H;
    if (in.with_tangent)
      out.dS_dE = (params.C * exp_Q) * (2.0 * dealii::outer_product(H, H) + dH);
  }


} // namespace systole::Materials
