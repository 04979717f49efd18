#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "fibres/fibre_basis.h"

namespace systole::Materials
{
  /// Adds the prescribed active stress
  /// @f[
  ///   S_a = T_a\, f_0\otimes f_0 + \eta\, T_a\,(I - f_0\otimes f_0)
  /// @f]
  /// to the 2nd Piola-Kirchhoff stress @p S.
  ///
  /// Convention: @f$T_a@f$ is a 2nd Piola-Kirchhoff tension, i.e. per unit
  /// reference area and along the reference fibre @f$f_0@f$ (Land et al.
  /// 2015, Proc. R. Soc. A 471:20150641, problem 3; shared/reference/
  /// physiology.md). The Cauchy stress it produces along the current fibre
  /// is @f$T_a \lambda_f^2 / J@f$ with @f$\lambda_f = |F f_0|@f$. The
  /// optional transverse part (physiology.md, "Active tension") acts in the
  /// reference plane orthogonal to @f$f_0@f$. Add it after any
  /// isochoric/volumetric split (it must not be projected away).
  /// @f$T_a@f$ is prescribed (it does not depend on E), so the tangent
  /// dS/dE is unchanged; a stretch-dependent tension must add its own
  /// @f$\partial T_a/\partial E@f$ term.
  ///
  /// @param[in] Ta active tension @f$T_a@f$ [kPa] (positive contracts).
  /// @param[in] transverse_fraction @f$\eta@f$ [-], in [0, 1] (throws
  ///            ExcMessage otherwise); 0 gives the purely fibre-aligned form.
  /// @param[in] basis reference fibre frame; only @f$f_0@f$ (unit) is used.
  /// @param[in,out] S 2nd Piola-Kirchhoff stress [kPa] to add to.
  void
  add_active_stress(const double                   Ta,
                    const double                   transverse_fraction,
                    const Fibres::FibreBasis      &basis,
                    dealii::SymmetricTensor<2, 3> &S);
} // namespace systole::Materials
