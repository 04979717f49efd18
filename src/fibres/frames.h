#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "fibres/fibre_basis.h"

#include <functional>
#include <string>
#include <vector>

/// @file
/// What every fibre generator shares: the field type, the validator of its
/// frames and the helix angle.

namespace systole::Fibres
{
  /// A fibre field: the frames at reference points of one locally owned cell
  /// (the points lie in that cell). Generators that need the mesh (the
  /// rule-based Laplace solves) use the cell; pointwise rules ignore it.
  using FibreField = std::function<
    void(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
         const std::vector<dealii::Point<3>>                     &points,
         std::vector<FibreBasis>                                 &bases)>;

  /// Throws ExcMessage naming @p where unless @p basis is orthonormal and
  /// right-handed (n = f x s) to @p tolerance and free of NaN. Every
  /// generator's output goes through this check.
  void
  validate(const FibreBasis  &basis,
           const std::string &where,
           const double       tolerance = 1e-8);

  /// A generator's frames at @p points: @p bases[i] = @p basis_at(i), each
  /// validated (an error names the point and the generator @p name).
  void
  validated_bases(const std::vector<dealii::Point<3>>           &points,
                  const std::string                             &name,
                  const std::function<FibreBasis(unsigned int)> &basis_at,
                  std::vector<FibreBasis>                       &bases);

  /// Helix angle of @p f [rad] in the local frame of the wall: the angle
  /// between f and the circumferential direction e_c, positive towards the
  /// apex-to-base direction e_l: atan2(f . e_l, f . e_c).
  double
  helix_angle(const dealii::Tensor<1, 3> &f,
              const dealii::Tensor<1, 3> &e_c,
              const dealii::Tensor<1, 3> &e_l);
} // namespace systole::Fibres
