#pragma once

#include <deal.II/base/point.h>

namespace systole::Geometry
{
  /// Exact (bitwise, lexicographic) order of points, for maps keyed by
  /// vertices: a vertex shared by cells of different ranks carries the same
  /// coordinates on every rank (the same computations made it, or moved it).
  struct PointLess
  {
    bool
    operator()(const dealii::Point<3> &a, const dealii::Point<3> &b) const
    {
      for (unsigned int d = 0; d < 3; ++d)
        if (a[d] != b[d])
          return a[d] < b[d];
      return false;
    }
  };
} // namespace systole::Geometry
