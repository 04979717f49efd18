#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "fibres/fibre_basis.h"

namespace systole::Materials
{
  /// The cross-fibre part of the active stress: the fractions of the fibre
  /// tension that act along the sheet and the sheet-normal directions
  /// (Sommer et al. 2015, Acta Biomater 24:172; Genet et al. 2014; the
  /// transversely isotropic eta of fenicsx-pulse is sheet = normal = eta).
  /// Each in [0, 1].
  struct CrossFibreFractions
  {
    double sheet  = 0.0; ///< eta_s [-]
    double normal = 0.0; ///< eta_n [-]
    bool
    any() const
    {
      return sheet != 0.0 || normal != 0.0;
    }
  };

  /// Adds the prescribed active stress
  /// @f[
  ///   S_a = T_a\,(f_0\otimes f_0 + \eta_s\, s_0\otimes s_0 + \eta_n\,
  ///   n_0\otimes n_0)
  /// @f]
  /// to the 2nd Piola-Kirchhoff stress @p S.
  ///
  /// Convention: @f$T_a@f$ is a 2nd Piola-Kirchhoff tension, i.e. per unit
  /// reference area and along the reference fibre @f$f_0@f$ (Land et al.
  /// 2015, Proc. R. Soc. A 471:20150641, problem 3; shared/reference/
  /// physiology.md). The Cauchy stress it produces along the current fibre
  /// is @f$T_a \lambda_f^2 / J@f$ with @f$\lambda_f = |F f_0|@f$. The
  /// cross-fibre part acts along the reference sheet and normal directions.
  /// Add it after any isochoric/volumetric split (it must not be projected
  /// away). @f$T_a@f$ is prescribed here (it does not depend on E), so the
  /// tangent dS/dE is unchanged; a stretch-dependent tension adds its own
  /// @f$\partial T_a/\partial E@f$ term (Mechanics: not major symmetric
  /// with a cross-fibre part).
  ///
  /// @param[in] Ta active tension @f$T_a@f$ [kPa] (positive contracts).
  /// @param[in] cross @f$\eta_s, \eta_n@f$ [-], each in [0, 1] (throws
  ///            ExcMessage otherwise); 0 gives the purely fibre-aligned form.
  /// @param[in] basis reference fibre frame (f0, s0, n0: orthonormal).
  /// @param[in,out] S 2nd Piola-Kirchhoff stress [kPa] to add to.
  void
  add_active_stress(const double                   Ta,
                    const CrossFibreFractions     &cross,
                    const Fibres::FibreBasis      &basis,
                    dealii::SymmetricTensor<2, 3> &S);

  /// The direction tensor of the active stress, S_a = T_a D:
  /// D = f0 x f0 + eta_s s0 x s0 + eta_n n0 x n0.
  dealii::SymmetricTensor<2, 3>
  active_stress_direction(const CrossFibreFractions &cross,
                          const Fibres::FibreBasis  &basis);
} // namespace systole::Materials
