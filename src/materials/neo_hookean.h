#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law_with_parameters.h"

#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / neo-Hookean".
  struct NeoHookeanParameters : LawParameters<NeoHookeanParameters>
  {
    static constexpr const char *law_name = "neo-Hookean";

    double mu = 10.0; ///< shear modulus @f$\mu@f$ [kPa], > 0

    /// Entry "mu" (> 0).
    static const std::vector<LawEntry<NeoHookeanParameters>> &
    entries();
  };

  /// Isotropic, isochoric neo-Hookean law (Treloar 1943; decoupled form of
  /// Simo and Taylor 1991, CMAME 85:273, and Holzapfel 2000, Nonlinear Solid
  /// Mechanics, eq. 6.147):
  /// @f[
  ///   W = \frac{\mu}{2}\left(\bar I_1 - 3\right),\qquad
  ///   \bar I_1 = J^{-2/3}\,\mathrm{tr}\,C,\quad J = \det F,
  /// @f]
  /// W [kPa]. Zero energy and stress at F = I and under any pure dilation;
  /// add a VolumetricLaw for the bulk response. Requires det F > 0 (throws
  /// ExcNonPositiveVolumeRatio). The fibre basis is not used.
  class NeoHookean : public PassiveLawWithParameters<NeoHookeanParameters>
  {
  public:
    using PassiveLawWithParameters::PassiveLawWithParameters;

    /// Energy [kPa], 2nd Piola-Kirchhoff stress
    /// @f$S = \mu J^{-2/3}(I - \frac{I_1}{3} C^{-1})@f$ [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;
  };
} // namespace systole::Materials
