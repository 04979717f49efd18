#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law.h"

#include <string>

namespace systole::Materials
{
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
  class NeoHookean : public PassiveLaw
  {
  public:
    /// Parameters of subsection "Material / neo-Hookean".
    struct Parameters
    {
      double mu = 10.0; ///< shear modulus @f$\mu@f$ [kPa], > 0

      /// Declares "mu" in the current subsection (the factory enters
      /// "Material / neo-Hookean" first).
      static void
      declare(dealii::ParameterHandler &prm);

      /// Reads "Material / neo-Hookean" with the path getters and validates.
      static Parameters
      parse(const dealii::ParameterHandler &prm);

      /// Throws ExcMessage naming "Material / neo-Hookean / mu" and the fix
      /// if mu is not > 0.
      void
      validate() const;
    };

    /// Name in the parameter file ("Material / Passive law").
    static constexpr const char *law_name = "neo-Hookean";

    /// @param[in] parameters validated on construction.
    explicit NeoHookean(const Parameters &parameters);

    /// Energy [kPa], 2nd Piola-Kirchhoff stress
    /// @f$S = \mu J^{-2/3}(I - \frac{I_1}{3} C^{-1})@f$ [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;

    /// Returns law_name.
    std::string
    name() const override;

    /// The parameters in use.
    const Parameters &
    parameters() const;

  private:
    const Parameters params;
  };
} // namespace systole::Materials
