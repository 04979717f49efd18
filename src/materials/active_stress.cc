#include "materials/active_stress.h"

#include <cmath>
#include <string>

namespace systole::Materials
{
  dealii::SymmetricTensor<2, 3>
  active_stress_direction(const CrossFibreFractions &cross,
                          const Fibres::FibreBasis  &basis)
  {
    for (const double eta : {cross.sheet, cross.normal})
      AssertThrow(eta >= 0.0 && eta <= 1.0,
                  dealii::ExcMessage(
                    "The cross-fibre fractions of the active stress (sheet " +
                    std::to_string(cross.sheet) + ", normal " +
                    std::to_string(cross.normal) + ") must lie in [0, 1]."));
    const auto outer = [](const dealii::Tensor<1, 3> &a) {
      return dealii::symmetrize(dealii::outer_product(a, a));
    };
    dealii::SymmetricTensor<2, 3> D = outer(basis.f);
    if (cross.sheet != 0.0)
      D += cross.sheet * outer(basis.s);
    if (cross.normal != 0.0)
      D += cross.normal * outer(basis.n);
    return D;
  }

  void
  add_active_stress(const double                   Ta,
                    const CrossFibreFractions     &cross,
                    const Fibres::FibreBasis      &basis,
                    dealii::SymmetricTensor<2, 3> &S)
  {
    AssertThrow(std::isfinite(Ta),
                dealii::ExcMessage("The active tension is not finite."));
    S += Ta * active_stress_direction(cross, basis);
  }
} // namespace systole::Materials
