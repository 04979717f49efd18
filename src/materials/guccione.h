#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law_with_parameters.h"

#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / Guccione".
  /// Defaults: Land et al. 2015, problems 1 and 3.
  struct GuccioneParameters : LawParameters<GuccioneParameters>
  {
    static constexpr const char *law_name = "Guccione";

    double C    = 2.0; ///< overall stiffness [kPa], > 0
    double b_f  = 8.0; ///< fibre exponent weight [-], > 0
    double b_t  = 2.0; ///< cross-fibre (transverse) weight [-], > 0
    double b_fs = 4.0; ///< fibre-sheet/fibre-normal shear weight [-], > 0

    /// Entries "C", "b_f", "b_t", "b_fs" (all > 0).
    static const std::vector<LawEntry<GuccioneParameters>> &
    entries();
  };

  /// Transversely isotropic Fung-type law of Guccione et al.
  /// (J. Biomech. Eng. 113:42, 1991; form of Land et al. 2015,
  /// Proc. R. Soc. A 471:20150641, eq. 2.1):
  /// @f[
  ///   W = \frac{C}{2}\left(e^{Q} - 1\right),\quad
  ///   Q = b_f E_{ff}^2 + b_t\left(E_{ss}^2 + E_{nn}^2 + 2E_{sn}^2\right)
  ///     + 2 b_{fs}\left(E_{fs}^2 + E_{fn}^2\right),
  /// @f]
  /// with @f$E_{ab} = a\cdot E\,b@f$ the components of the full (not
  /// isochoric) Green-Lagrange strain @f$E = \frac12(F^TF - I)@f$ in the
  /// local frame (f, s, n) of PassiveInput::basis. W [kPa]; the law is stress
  /// free at F = I. Near-incompressibility is added by a VolumetricLaw.
  /// With @f$H = \sum_{a,b} B_{ab} E_{ab}\, a\otimes b@f$ (B the weights
  /// above) it gives @f$S = C e^Q H@f$ and
  /// @f$\partial S/\partial E = C e^Q (2 H\otimes H + \partial H/\partial
  /// E)@f$.
  class Guccione : public PassiveLawWithParameters<GuccioneParameters>
  {
  public:
    using PassiveLawWithParameters::PassiveLawWithParameters;

    /// Energy [kPa], 2nd Piola-Kirchhoff stress [kPa] and dS/dE [kPa].
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;
  };
} // namespace systole::Materials
