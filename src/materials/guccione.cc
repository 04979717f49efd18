#include "materials/guccione.h"

#include "materials/symmetric_tensor_ops.h"

#include <array>
#include <cmath>

namespace systole::Materials
{
  const std::vector<LawEntry<GuccioneParameters>> &
  GuccioneParameters::entries()
  {
    using P                                     = GuccioneParameters;
    static const std::vector<LawEntry<P>> table = {
      {"C",
       &P::C,
       Range::positive,
       "Overall stiffness multiplying exp(Q) - 1. Units: kPa. Source: Land et "
       "al. 2015 problems 1 and 3 (2 kPa); canine fit about 0.88 kPa "
       "(Guccione 1991); must be > 0.",
       "set e.g. 2 kPa, Land et al. 2015"},
      {"b_f",
       &P::b_f,
       Range::positive,
       "Weight of the fibre strain E_ff^2 in Q. Units: none. Source: Land et "
       "al. 2015 (8); canine fit about 18.5 (Guccione 1991); must be > 0.",
       "set e.g. 8, Land et al. 2015"},
      {"b_t",
       &P::b_t,
       Range::positive,
       "Weight of the cross-fibre strains E_ss^2 + E_nn^2 + 2 E_sn^2 in Q. "
       "Units: none. Source: Land et al. 2015 (2); canine fit about 3.6 "
       "(Guccione 1991); must be > 0.",
       "set e.g. 2, Land et al. 2015"},
      {"b_fs",
       &P::b_fs,
       Range::positive,
       "Weight of the fibre shears 2 (E_fs^2 + E_fn^2) in Q. Units: none. "
       "Source: Land et al. 2015 (4); canine fit about 1.6 (Guccione 1991); "
       "must be > 0.",
       "set e.g. 4, Land et al. 2015"}};
    return table;
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
            SymmetricOps::add_outer(dH, w, M, M);
        }

    const double exp_Q = std::exp(Q);
    out.psi            = 0.5 * params.C * std::expm1(Q);
    out.S              = (params.C * exp_Q) * H;
    if (in.with_tangent)
      {
        SymmetricOps::add_outer(dH, 2.0, H, H);
        out.dS_dE = (params.C * exp_Q) * dH;
      }
  }


} // namespace systole::Materials
