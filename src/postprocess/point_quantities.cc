#include "postprocess/point_quantities.h"

#include <array>
#include <cmath>
#include <limits>

namespace systole::Postprocess
{
  PointQuantities
  point_quantities(const dealii::Tensor<2, 3>          &F,
                   const Fibres::FibreBasis            &basis,
                   const dealii::SymmetricTensor<2, 3> &sigma,
                   const double                         tension,
                   const CardiacFrame                  *frame)
  {
    PointQuantities            q;
    const dealii::Tensor<1, 3> f     = F * basis.f;
    q.fibre_stretch                  = f.norm();
    q.active_tension                 = tension;
    q.J                              = dealii::determinant(F);
    const dealii::Tensor<1, 3> fibre = f / q.fibre_stretch;
    q.fibre_stress                   = fibre * (sigma * fibre);
    bool finite                      = true;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        finite = finite && std::isfinite(sigma[i][j]);
    q.first_principal_stress = finite
                                 ? dealii::eigenvalues(sigma)[0]
                                 : std::numeric_limits<double>::quiet_NaN();
    if (frame == nullptr)
      {
        q.strain_circumferential = q.strain_longitudinal = q.strain_radial =
          std::numeric_limits<double>::quiet_NaN();
        return q;
      }
    // e . E e = (|F e|^2 - 1) / 2 for a unit e.
    const auto strain = [&](const dealii::Tensor<1, 3> &e) {
      return 0.5 * ((F * e).norm_square() - 1.0);
    };
    q.strain_circumferential = strain(frame->circumferential);
    q.strain_longitudinal    = strain(frame->longitudinal);
    q.strain_radial          = strain(frame->radial);
    return q;
  }
} // namespace systole::Postprocess
