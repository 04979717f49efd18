#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law_with_parameters.h"

#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / St Venant-Kirchhoff".
  struct StVenantKirchhoffParameters
    : LawParameters<StVenantKirchhoffParameters>
  {
    static constexpr const char *law_name = "St Venant-Kirchhoff";

    double lambda = 40.0; ///< first Lame parameter @f$\lambda@f$ [kPa], >= 0
    double mu     = 10.0; ///< shear modulus @f$\mu@f$ [kPa], > 0

    /// Entries "lambda" (>= 0) and "mu" (> 0).
    static const std::vector<LawEntry<StVenantKirchhoffParameters>> &
    entries();
  };

  /// Isotropic St Venant-Kirchhoff law (Holzapfel 2000, Nonlinear Solid
  /// Mechanics, eq. 6.151):
  /// @f[
  ///   W = \frac{\lambda}{2}(\mathrm{tr}\,E)^2 + \mu\, E:E,\qquad
  ///   S = \lambda\,(\mathrm{tr}\,E)\, I + 2\mu E,\qquad
  ///   \frac{\partial S}{\partial E} = \lambda\, I\otimes I + 2\mu\,\mathbb{I},
  /// @f]
  /// E the full Green-Lagrange strain, W [kPa]. Compressible on its own (no
  /// VolumetricLaw needed); unstable in strong compression, so meant for
  /// verification and small strains only. The fibre basis is not used.
  class StVenantKirchhoff
    : public PassiveLawWithParameters<StVenantKirchhoffParameters>
  {
  public:
    using PassiveLawWithParameters::PassiveLawWithParameters;

    /// Energy [kPa], 2nd Piola-Kirchhoff stress [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;
  };
} // namespace systole::Materials
