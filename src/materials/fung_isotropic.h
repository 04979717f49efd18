#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law_with_parameters.h"

#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / Fung isotropic".
  struct FungIsotropicParameters : LawParameters<FungIsotropicParameters>
  {
    static constexpr const char *law_name = "Fung isotropic";

    double mu    = 10.0; ///< stress scale @f$\mu@f$ [kPa], > 0
    double gamma = 1.0;  ///< exponent @f$\gamma@f$ [-], > 0

    /// Entries "mu" and "gamma" (both > 0).
    static const std::vector<LawEntry<FungIsotropicParameters>> &
    entries();
  };

  /// Isotropic, isochoric Fung-type exponential law (Fung 1967, Am. J.
  /// Physiol. 213:1532; the isotropic exponential of Demiray 1972, J.
  /// Biomech. 5:309, in the decoupled form of Holzapfel 2000, Nonlinear Solid
  /// Mechanics, sec. 6.4):
  /// @f[
  ///   W = \frac{\mu}{2}\left(e^{\gamma(\bar I_1 - 3)} - 1\right),\qquad
  ///   \bar I_1 = J^{-2/3}\,\mathrm{tr}\,C,\quad J = \det F,
  /// @f]
  /// W [kPa], @f$\mu@f$ a stress scale [kPa], @f$\gamma@f$ the exponent [-].
  /// The small-strain shear modulus is @f$\mu\gamma@f$ (W ≈
  /// @f$\frac{\mu\gamma}{2}(\bar I_1 - 3)@f$, the neo-Hookean law).
  ///
  /// Why this form and not @f$\frac{\mu}{2} e^{\mathrm{tr}\,E}@f$: since
  /// @f$\mathrm{tr}\,E = (I_1 - 3)/2@f$, that form is this one with
  /// @f$\gamma = 1/2@f$, but (a) on the full @f$I_1@f$, which holds the
  /// volume change, so the law would carry its own (compression-softening)
  /// volumetric response beside the VolumetricLaw, and (b) without the
  /// @f$-1@f$, so W(I) = @f$\mu/2@f$ instead of 0. On @f$\bar I_1@f$ the bulk
  /// response is the VolumetricLaw's (or the pressure's) alone, the mixed
  /// formulations use the law unchanged (IsochoricPart is the identity for
  /// it), and @f$\gamma = 1/2@f$, @f$\mu = C@f$ matches the isotropic
  /// Guccione law @f$\frac{C}{2}(e^{E:E} - 1)@f$ in its small-strain shear
  /// modulus C/2 and, for an isochoric deformation, in the exponent to
  /// leading order (@f$\bar I_1 - 3 = 2 E:E + O(|E|^3)@f$).
  ///
  /// Zero energy and stress at F = I and under pure dilation; add a
  /// VolumetricLaw for the bulk response. Requires det F > 0 (throws
  /// ExcNonPositiveVolumeRatio). The fibre basis is not used.
  class FungIsotropic : public PassiveLawWithParameters<FungIsotropicParameters>
  {
  public:
    using PassiveLawWithParameters::PassiveLawWithParameters;

    /// Energy [kPa], 2nd Piola-Kirchhoff stress
    /// @f$S = \mu\gamma\, e^{\gamma(\bar I_1 - 3)}\, J^{-2/3}
    /// (I - \frac{I_1}{3} C^{-1})@f$ [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;
  };
} // namespace systole::Materials
