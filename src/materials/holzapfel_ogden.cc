#include "materials/holzapfel_ogden.h"

#include "materials/isochoric_invariants.h"
#include "materials/symmetric_tensor_ops.h"

#include <cmath>

namespace systole::Materials
{
  namespace
  {
    /// Value and first two derivatives of a scalar function.
    struct Scalar3
    {
      double value, first, second;
    };

    /// Psi(x) = a/(2b) (exp(b x^2) - 1) and its derivatives in x.
    Scalar3
    exponential_term(const double x, const double a, const double b)
    {
      const double e = std::exp(b * x * x);
      return {0.5 * a / b * std::expm1(b * x * x),
              a * x * e,
              a * e * (1.0 + 2.0 * b * x * x)};
    }

    /// w(x) Psi(x) for a fibre or sheet term, w the tension switch @p w.
    Scalar3
    weighted_term(const double                 x,
                  const double                 a,
                  const double                 b,
                  const std::array<double, 3> &w)
    {
      if (w[0] == 0.0 && w[1] == 0.0 && w[2] == 0.0)
        return {0.0, 0.0, 0.0};
      const Scalar3 psi = exponential_term(x, a, b);
      return {w[0] * psi.value,
              w[1] * psi.value + w[0] * psi.first,
              w[2] * psi.value + 2.0 * w[1] * psi.first + w[0] * psi.second};
    }

    /// w(x) Psi(x) with the smootherstep of width delta.
    Scalar3
    switched_term(const double x,
                  const double a,
                  const double b,
                  const double delta)
    {
      return weighted_term(x, a, b, HolzapfelOgden::tension_switch(x, delta));
    }

  } // namespace


  std::array<double, 3>
  HolzapfelOgden::tension_switch(const double x, const double delta)
  {
    if (x <= 0.0)
      return {{0.0, 0.0, 0.0}};
    if (x >= delta) // also the hard switch delta = 0
      return {{1.0, 0.0, 0.0}};
    const double t = x / delta;
    return {{t * t * t * (10.0 + t * (-15.0 + 6.0 * t)),
             30.0 * t * t * (1.0 - t) * (1.0 - t) / delta,
             60.0 * t * (1.0 - t) * (1.0 - 2.0 * t) / (delta * delta)}};
  }


  std::array<double, 3>
  HolzapfelOgden::logistic_switch(const double x, const double k)
  {
    // With e = exp(-k |x|) <= 1 (no overflow, full relative accuracy on
    // both tails): w = 1/(1 + e) for x >= 0, e/(1 + e) for x < 0;
    // w (1 - w) = e/(1 + e)^2 and 1 - 2w = -+(1 - e)/(1 + e).
    const double e        = std::exp(-k * std::abs(x));
    const double w        = x >= 0.0 ? 1.0 / (1.0 + e) : e / (1.0 + e);
    const double v        = e / ((1.0 + e) * (1.0 + e));
    const double one_m_2w = (x >= 0.0 ? e - 1.0 : 1.0 - e) / (1.0 + e);
    return {{w, k * v, k * k * v * one_m_2w}};
  }


  std::array<double, 3>
  HolzapfelOgden::switched_exponential(const double x,
                                       const double a,
                                       const double b,
                                       const double delta)
  {
    const Scalar3 term = switched_term(x, a, b, delta);
    return {{term.value, term.first, term.second}};
  }


  const std::vector<LawEntry<HolzapfelOgdenParameters>> &
  HolzapfelOgdenParameters::entries()
  {
    using P = HolzapfelOgdenParameters;
    const std::string stiffness =
      " Units: kPa. Source: Holzapfel and Ogden 2009, Table 1 (default).";
    const std::string exponent = " Units: none. Source: Holzapfel and Ogden "
                                 "2009, Table 1 (default); must be > 0.";
    static const std::vector<LawEntry<P>> table = {
      {"a",
       &P::a,
       Range::positive,
       "Stiffness of the isotropic matrix term a/(2b) (exp(b (J^{-2/3} I1 - "
       "3)) - 1); must be > 0." +
         stiffness,
       "set e.g. 0.059 kPa (HO 2009 Table 1)"},
      {"b",
       &P::b,
       Range::positive,
       "Exponent of the isotropic matrix term (beware the widespread typo "
       "0.023)." +
         exponent,
       "set e.g. 8.023 (HO 2009 Table 1)"},
      {"a_f",
       &P::a_f,
       Range::non_negative,
       "Stiffness of the fibre term a_f/(2b_f) (exp(b_f (I4f - 1)^2) - 1), "
       "active in tension only; >= 0." +
         stiffness,
       "set e.g. 18.472 kPa (HO 2009 Table 1)"},
      {"b_f",
       &P::b_f,
       Range::positive,
       "Exponent of the fibre term." + exponent,
       "set e.g. 16.026 (HO 2009)"},
      {"a_s",
       &P::a_s,
       Range::non_negative,
       "Stiffness of the sheet term a_s/(2b_s) (exp(b_s (I4s - 1)^2) - 1), "
       "active in tension only; >= 0 (0, with a_fs = 0, gives the "
       "transversely isotropic law)." +
         stiffness,
       "set e.g. 2.481 kPa, or 0 for transverse isotropy"},
      {"b_s",
       &P::b_s,
       Range::positive,
       "Exponent of the sheet term." + exponent,
       "set e.g. 11.120 (HO 2009)"},
      {"a_fs",
       &P::a_fs,
       Range::non_negative,
       "Stiffness of the fibre-sheet coupling term a_fs/(2b_fs) (exp(b_fs "
       "I8fs^2) - 1); >= 0 (0, with a_s = 0, gives the transversely isotropic "
       "law)." +
         stiffness,
       "set e.g. 0.216 kPa, or 0 for transverse isotropy"},
      {"b_fs",
       &P::b_fs,
       Range::positive,
       "Exponent of the fibre-sheet coupling term." + exponent,
       "set e.g. 11.436 (HO 2009)"},
      {"Tension switch width",
       &P::switch_width,
       Range::non_negative,
       "Width delta in I4 - 1 of the C^2 blend that switches the fibre and "
       "sheet terms on in tension: off for I4 <= 1, the full 2009 law for "
       "I4 >= 1 + delta; 0 gives the hard switch of the paper (discontinuous "
       "tangent). Units: none. Range: 0-0.05; default 0.01 (a stretch of "
       "0.5 %). Only for Tension switch = smootherstep.",
       "set e.g. 0.01, or 0 for a hard switch"},
      {"Tension switch sharpness",
       &P::switch_sharpness,
       Range::positive,
       "Sharpness k of the logistic tension switch; must be > 0. Units: none. "
       "Source: Arostica et al. 2025 (k = 100, the default).",
       "set e.g. 100 (Arostica et al. 2025)"}};
    return table;
  }


  void
  HolzapfelOgdenParameters::declare_more(dealii::ParameterHandler &prm)
  {
    prm.declare_entry(
      "Tension switch",
      "smootherstep",
      dealii::Patterns::Selection("logistic|smootherstep"),
      "How the fibre and sheet terms switch off in compression: "
      "smootherstep, the C^2 blend of width 'Tension switch width' (exactly "
      "0 for I4 <= 1); logistic, the smooth Heaviside 1/(1 + exp(-k (I4 - "
      "1))) of the Arostica et al. 2025 benchmark, multiplying the term (1/2 "
      "at I4 = 1, never exactly 0), k = 'Tension switch sharpness'. Units: "
      "none.");
  }


  void
  HolzapfelOgdenParameters::parse_more(const dealii::ParameterHandler &prm,
                                       const std::vector<std::string> &path)
  {
    switch_form = prm.get(path, "Tension switch") == "logistic"
                    ? Switch::logistic
                    : Switch::smootherstep;
  }


  void
  HolzapfelOgden::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    using dealii::outer_product;
    using dealii::SymmetricTensor;

    // Isotropic term on Ibar1.
    const IsochoricInvariants inv =
      isochoric_invariants(in, InvariantSet::Ibar1);
    const SymmetricTensor<2, 3> &C = inv.C;
    const double e_iso             = std::exp(params.b * (inv.I1_bar - 3.0));
    const double psi_1             = 0.5 * params.a * e_iso;

    double psi =
      0.5 * params.a / params.b * std::expm1(params.b * (inv.I1_bar - 3.0));
    SymmetricTensor<2, 3> dpsi_dC = psi_1 * inv.dI1_bar;
    SymmetricTensor<4, 3> d2psi_dC2;
    namespace ops = SymmetricOps;
    if (in.with_tangent)
      {
        d2psi_dC2 = psi_1 * inv.d2I1_bar;
        ops::add_outer(d2psi_dC2, params.b * psi_1, inv.dI1_bar, inv.dI1_bar);
      }

    // Fibre and sheet terms on the full I4 = a0.C a0, dI4/dC = a0 x a0.
    const auto add_switched = [&](const dealii::Tensor<1, 3> &axis,
                                  const double                a_i,
                                  const double                b_i) {
      if (a_i == 0.0)
        return;
      const SymmetricTensor<2, 3> M =
        dealii::symmetrize(outer_product(axis, axis));
      const double  x = M * C - 1.0;
      const Scalar3 term =
        params.switch_form == Parameters::Switch::logistic
          ? weighted_term(x,
                          a_i,
                          b_i,
                          logistic_switch(x, params.switch_sharpness))
          : switched_term(x, a_i, b_i, params.switch_width);
      psi += term.value;
      dpsi_dC += term.first * M;
      if (in.with_tangent)
        ops::add_outer(d2psi_dC2, term.second, M, M);
    };
    add_switched(in.basis.f, params.a_f, params.b_f);
    add_switched(in.basis.s, params.a_s, params.b_s);

    // Fibre-sheet coupling on I8 = f0.C s0, dI8/dC = sym(f0 x s0).
    if (params.a_fs != 0.0)
      {
        const SymmetricTensor<2, 3> M =
          dealii::symmetrize(outer_product(in.basis.f, in.basis.s));
        const Scalar3 term = exponential_term(M * C, params.a_fs, params.b_fs);
        psi += term.value;
        dpsi_dC += term.first * M;
        if (in.with_tangent)
          ops::add_outer(d2psi_dC2, term.second, M, M);
      }

    // S = 2 dW/dC, dS/dE = 4 d2W/dC2.
    out.psi = psi;
    out.S   = 2.0 * dpsi_dC;
    if (in.with_tangent)
      out.dS_dE = 4.0 * d2psi_dC2;
  }


} // namespace systole::Materials
