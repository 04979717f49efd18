#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law_with_parameters.h"

#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / Mooney-Rivlin".
  struct MooneyRivlinParameters : LawParameters<MooneyRivlinParameters>
  {
    static constexpr const char *law_name = "Mooney-Rivlin";

    double c1 = 4.0; ///< weight of @f$\bar I_1 - 3@f$ [kPa], >= 0
    double c2 = 1.0; ///< weight of @f$\bar I_2 - 3@f$ [kPa], >= 0

    /// Entries "c1" and "c2" (both >= 0; validate_more() asks c1 + c2 > 0).
    static const std::vector<LawEntry<MooneyRivlinParameters>> &
    entries();

    /// Requires c1 + c2 > 0 (some shear stiffness).
    void
    validate_more() const;
  };

  /// Isotropic, isochoric Mooney-Rivlin law (Mooney 1940, J. Appl. Phys.
  /// 11:582; Rivlin 1948; decoupled form of Holzapfel 2000, Nonlinear Solid
  /// Mechanics, eq. 6.148):
  /// @f[
  ///   W = c_1\left(\bar I_1 - 3\right) + c_2\left(\bar I_2 - 3\right),\quad
  ///   \bar I_1 = J^{-2/3} I_1,\quad \bar I_2 = J^{-4/3} I_2,
  /// @f]
  /// @f$I_1 = \mathrm{tr}\,C@f$, @f$I_2 = \frac12(I_1^2 - C:C)@f$, W [kPa];
  /// small-strain shear modulus @f$2(c_1 + c_2)@f$. Zero energy and stress at
  /// F = I and under pure dilation; add a VolumetricLaw for the bulk
  /// response. Requires det F > 0 (throws ExcNonPositiveVolumeRatio). The
  /// fibre basis is not used; c2 = 0 gives the neo-Hookean law with
  /// mu = 2 c1.
  class MooneyRivlin : public PassiveLawWithParameters<MooneyRivlinParameters>
  {
  public:
    using PassiveLawWithParameters::PassiveLawWithParameters;

    /// Energy [kPa], 2nd Piola-Kirchhoff stress [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;
  };
} // namespace systole::Materials
