#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law_with_parameters.h"

#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / Veronda-Westman".
  struct VerondaWestmanParameters : LawParameters<VerondaWestmanParameters>
  {
    static constexpr const char *law_name = "Veronda-Westman";

    double c1    = 10.0; ///< stress scale @f$c_1@f$ [kPa], > 0
    double gamma = 1.0;  ///< exponent @f$\gamma@f$ [-], > 0

    /// Entries "c1" and "gamma" (both > 0).
    static const std::vector<LawEntry<VerondaWestmanParameters>> &
    entries();
  };

  /// Isotropic, isochoric Veronda-Westman law (Veronda and Westman 1970, J.
  /// Biomech. 3:111, for skin; the decoupled form of FEBio's
  /// "Veronda-Westman" material):
  /// @f[
  ///   W = c_1\left(e^{\gamma(\bar I_1 - 3)} - 1\right)
  ///     - \frac{c_1\gamma}{2}\left(\bar I_2 - 3\right),\quad
  ///   \bar I_1 = J^{-2/3} I_1,\quad \bar I_2 = J^{-4/3} I_2,
  /// @f]
  /// @f$I_1 = \mathrm{tr}\,C@f$, @f$I_2 = \frac12(I_1^2 - C:C)@f$, W [kPa].
  /// The weight of @f$\bar I_2@f$ is tied to c1 and gamma, so the law has two
  /// parameters; its small-strain shear modulus is
  /// @f$2(W_1 + W_2) = c_1\gamma@f$ (@f$W_i = \partial W/\partial\bar I_i@f$
  /// at F = I). Zero energy and stress at F = I and under pure dilation; add
  /// a VolumetricLaw for the bulk response. Requires det F > 0 (throws
  /// ExcNonPositiveVolumeRatio). The fibre basis is not used.
  class VerondaWestman
    : public PassiveLawWithParameters<VerondaWestmanParameters>
  {
  public:
    using PassiveLawWithParameters::PassiveLawWithParameters;

    /// Energy [kPa], 2nd Piola-Kirchhoff stress [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;
  };
} // namespace systole::Materials
