#pragma once

#include <deal.II/base/tensor.h>

namespace systole::Fibres
{
  /// Orthonormal, right-handed material frame at one point of the reference
  /// configuration: fibre f0, sheet s0 and sheet-normal n0 = f0 x s0 (all unit
  /// vectors, dimensionless).
  struct FibreBasis
  {
    dealii::Tensor<1, 3> f; ///< fibre direction f0
    dealii::Tensor<1, 3> s; ///< sheet direction s0
    dealii::Tensor<1, 3> n; ///< sheet-normal direction n0

    /// The Cartesian frame (f, s, n) = (e_x, e_y, e_z).
    static FibreBasis
    cartesian()
    {
      FibreBasis b;
      b.f[0] = 1.0;
      b.s[1] = 1.0;
      b.n[2] = 1.0;
      return b;
    }
  };
} // namespace systole::Fibres
