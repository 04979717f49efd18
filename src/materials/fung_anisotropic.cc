#include "materials/fung_anisotropic.h"

#include "materials/holzapfel_ogden.h"
#include "materials/volumetric_law.h"

#include <array>
#include <cmath>

namespace systole::Materials
{
  namespace
  {
    FungIsotropic::Parameters
    matrix_parameters(const FungAnisotropic::Parameters &p)
    {
      FungIsotropic::Parameters matrix;
      matrix.mu    = p.mu;
      matrix.gamma = p.gamma;
      return matrix;
    }
  } // namespace


  const std::vector<LawEntry<FungAnisotropicParameters>> &
  FungAnisotropicParameters::entries()
  {
    using P                                     = FungAnisotropicParameters;
    static const std::vector<LawEntry<P>> table = {
      {"mu",
       &P::mu,
       Range::positive,
       "Stress scale mu of the isotropic matrix term mu/2 (exp(gamma "
       "(J^{-2/3} I1 - 3)) - 1), as in Fung isotropic; the small-strain shear "
       "modulus across the fibres is mu gamma. Units: kPa. Range: illustrative "
       "default 10 kPa; must be > 0.",
       "set e.g. 10 kPa"},
      {"gamma",
       &P::gamma,
       Range::positive,
       "Exponent gamma of the isotropic matrix term. Units: none. Range: "
       "illustrative default 1; must be > 0.",
       "set e.g. 1"},
      {"k1",
       &P::k1,
       Range::non_negative,
       "Stiffness k1 of the fibre term k1/(2 k2) (exp(k2 (I4f - 1)^2) - 1) "
       "(Holzapfel, Gasser and Ogden 2000), I4f = f0.C f0, active in tension "
       "only. Units: kPa. Source: the fibre term a_f of Holzapfel and Ogden "
       "2009, Table 1 (default); >= 0 (0 gives Fung isotropic).",
       "set e.g. 18.472 kPa, or 0 for Fung isotropic"},
      {"k2",
       &P::k2,
       Range::positive,
       "Exponent k2 of the fibre term. Units: none. Source: b_f of Holzapfel "
       "and Ogden 2009, Table 1 (default); must be > 0.",
       "set e.g. 16.026"},
      {"Tension switch width",
       &P::switch_width,
       Range::non_negative,
       "Width delta in I4f - 1 of the C^2 blend that switches the fibre term "
       "on in tension (as in Holzapfel-Ogden): off for I4f <= 1, the full term "
       "for I4f >= 1 + delta; 0 gives a hard switch (discontinuous tangent). "
       "Units: none. Range: 0-0.05; default 0.01 (a stretch of 0.5 %).",
       "set e.g. 0.01, or 0 for a hard switch"}};
    return table;
  }


  FungAnisotropic::FungAnisotropic(const Parameters &parameters)
    // The base validates first, so that a bad mu or gamma is reported under
    // this law's name rather than by the matrix's constructor.
    : PassiveLawWithParameters(parameters)
    , matrix(matrix_parameters(parameters))
  {}


  void
  FungAnisotropic::evaluate(const PassiveInput &in, PassiveOutput &out) const
  {
    using dealii::outer_product;
    using dealii::SymmetricTensor;

    // The isotropic matrix (also checks det F > 0; honours in.with_tangent).
    matrix.evaluate(in, out);
    if (params.k1 == 0.0)
      return;

    // Fibre term w(x) k1/(2 k2) (e^{k2 x^2} - 1), x = I4f - 1 = f0.C f0 - 1,
    // as Holzapfel-Ogden's fibre term; dI4/dC = M = f0 x f0.
    const dealii::Tensor<1, 3>  Ff = in.F * in.basis.f;
    const double                x  = Ff * Ff - 1.0;
    const std::array<double, 3> term =
      HolzapfelOgden::switched_exponential(x,
                                           params.k1,
                                           params.k2,
                                           params.switch_width);
    if (term[0] == 0.0 && term[1] == 0.0 && term[2] == 0.0)
      return;

    const SymmetricTensor<2, 3> M =
      dealii::symmetrize(outer_product(in.basis.f, in.basis.f));
    // S = 2 dW/dC, dS/dE = 4 d2W/dC2.
    out.psi += term[0];
    out.S += (2.0 * term[1]) * M;
    if (in.with_tangent)
      out.dS_dE += (4.0 * term[2]) * outer_product(M, M);
  }


} // namespace systole::Materials
