#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/fung_isotropic.h"
#include "materials/passive_law_with_parameters.h"

#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / Fung anisotropic".
  struct FungAnisotropicParameters : LawParameters<FungAnisotropicParameters>
  {
    static constexpr const char *law_name = "Fung anisotropic";

    double mu    = 10.0;   ///< stress scale of the matrix @f$\mu@f$ [kPa], > 0
    double gamma = 1.0;    ///< exponent of the matrix @f$\gamma@f$ [-], > 0
    double k1    = 18.472; ///< fibre stiffness @f$k_1@f$ [kPa], >= 0
    double k2    = 16.026; ///< fibre exponent @f$k_2@f$ [-], > 0
    /// width @f$\delta@f$ of the tension switch in @f$I_4 - 1@f$ [-], >= 0
    double switch_width = 0.01;

    /// Entries "mu", "gamma", "k1", "k2" and "Tension switch width".
    static const std::vector<LawEntry<FungAnisotropicParameters>> &
    entries();
  };

  /// Transversely isotropic Fung-type law: the isochoric Fung isotropic
  /// matrix (FungIsotropic) plus the exponential fibre term of Holzapfel,
  /// Gasser and Ogden (2000, J. Elasticity 61:1, eq. 2.18, convex in
  /// @f$I_4@f$ for @f$I_4 \ge 1@f$), acting in tension only:
  /// @f[
  ///   W = \frac{\mu}{2}\left(e^{\gamma(\bar I_1 - 3)} - 1\right)
  ///     + w(I_{4f} - 1)\,\frac{k_1}{2k_2}
  ///       \left(e^{k_2 (I_{4f} - 1)^2} - 1\right),
  /// @f]
  /// W [kPa], @f$\bar I_1 = J^{-2/3}\,\mathrm{tr}\,C@f$ and the full fibre
  /// invariant @f$I_{4f} = f_0\cdot C f_0@f$ (not split, as in
  /// HolzapfelOgden and as Sansour 2008 and Helfenstein et al. 2010
  /// recommend: with the split invariant an anisotropic body under
  /// hydrostatic pressure would only change its volume).
  /// Small-strain shear modulus @f$\mu\gamma@f$ across the fibres; the fibre
  /// term adds nothing at F = I and stiffens a stretched fibre.
  ///
  /// Tension-only switch: w is the C^2 smootherstep of
  /// HolzapfelOgden::tension_switch with width @f$\delta@f$ ("Tension switch
  /// width"): w = 0 for @f$I_{4f} \le 1@f$ (a compressed fibre carries no
  /// stress: the term is off in compression), w = 1 for
  /// @f$I_{4f} \ge 1 + \delta@f$ (the HGO term exactly); @f$\delta = 0@f$ is
  /// the hard switch, whose tangent jumps by @f$4k_1@f$ at @f$I_{4f} = 1@f$.
  ///
  /// k1 = 0 gives FungIsotropic. With @f$a = \mu\gamma@f$, @f$b = \gamma@f$,
  /// @f$a_f = k_1@f$, @f$b_f = k_2@f$ and no sheet terms the law equals
  /// HolzapfelOgden (the unit tests check both). Requires det F > 0 (throws
  /// ExcNonPositiveVolumeRatio). Uses the fibre direction f0 of the basis.
  class FungAnisotropic
    : public PassiveLawWithParameters<FungAnisotropicParameters>
  {
  public:
    /// @param[in] parameters validated on construction.
    explicit FungAnisotropic(const Parameters &parameters);

    /// Energy [kPa], 2nd Piola-Kirchhoff stress [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;

  private:
    const FungIsotropic matrix; ///< the isotropic part (mu, gamma)
  };
} // namespace systole::Materials
