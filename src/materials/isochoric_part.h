#pragma once

#include "materials/passive_law.h"

#include <string>

namespace systole::Materials
{
  /// The isochoric part of a passive law: @f$\Psi(C) = \bar\psi(\bar C)@f$
  /// with @f$\bar C = J^{-2/3} C@f$, the law evaluated at
  /// @f$\bar F = J^{-1/3} F@f$. The mixed formulations use it, so that the
  /// volume change is governed by the pressure alone (a law written in E,
  /// such as Guccione's, otherwise softens under compression at the points
  /// where the weakly imposed J = 1 is not met). For J = 1 it is the law
  /// itself; for an already isochoric law (neo-Hookean, Mooney-Rivlin,
  /// Holzapfel-Ogden) it changes nothing.
  ///
  /// Stress and tangent (Holzapfel 2000, Nonlinear Solid Mechanics, eqs.
  /// 6.84, 6.88, 6.168): @f$S = J^{-2/3} \mathbb P : \bar S@f$,
  /// @f$\mathbb C = \mathbb P : \bar{\mathbb C} : \mathbb P^T + \frac23
  /// (J^{-2/3} \bar S : C)\tilde{\mathbb P} - \frac23 (C^{-1}\otimes S +
  /// S\otimes C^{-1})@f$ with @f$\mathbb P = \mathbb I - \frac13
  /// C^{-1}\otimes C@f$, @f$\bar{\mathbb C} = J^{-4/3}\,d\bar S/d\bar E@f$,
  /// @f$\tilde{\mathbb P} = C^{-1}\odot C^{-1} - \frac13 C^{-1}\otimes
  /// C^{-1}@f$ (@f$\bar S, d\bar S/d\bar E@f$ the law's at @f$\bar F@f$).
  class IsochoricPart : public PassiveLaw
  {
  public:
    /// @param[in] law the full law (kept by reference; must outlive this)
    explicit IsochoricPart(const PassiveLaw &law);

    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;

    std::string
    name() const override;

  private:
    const PassiveLaw &law;
  };
} // namespace systole::Materials
