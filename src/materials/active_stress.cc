#include "materials/active_stress.h"

#include <cmath>
#include <string>

namespace systole::Materials
{
  void
  add_active_stress(const double                   Ta,
                    const double                   transverse_fraction,
                    const Fibres::FibreBasis      &basis,
                    dealii::SymmetricTensor<2, 3> &S)
  {
    AssertThrow(std::isfinite(Ta),
                dealii::ExcMessage("The active tension is not finite."));
    AssertThrow(transverse_fraction >= 0.0 && transverse_fraction <= 1.0,
                dealii::ExcMessage(
                  "The transverse fraction of the active stress (" +
                  std::to_string(transverse_fraction) +
                  ") must lie in [0, 1]."));

    const dealii::SymmetricTensor<2, 3> ff =
      dealii::symmetrize(dealii::outer_product(basis.f, basis.f));
    S += Ta * ff +
         (transverse_fraction * Ta) * (dealii::unit_symmetric_tensor<3>() - ff);
  }
} // namespace systole::Materials
