#pragma once

#include <deal.II/base/tensor.h>

#include "fibres/fibre_basis.h"
#include "materials/passive_law.h"

#include <random>

/// @file
/// Deterministic random kinematics for unit tests (std::mt19937 from a seed).

namespace test_support
{
  /// A uniformly distributed rotation (det = +1) drawn from @p rng
  /// (normalised Gaussian quaternion).
  dealii::Tensor<2, 3>
  random_rotation(std::mt19937 &rng);

  /// As above, from a fixed @p seed.
  dealii::Tensor<2, 3>
  random_rotation(const unsigned int seed);

  /// F = Q (I + strain G): Q a random rotation and G a random matrix with
  /// entries uniform in [-1, 1], so @p strain [-] sets the size of the
  /// stretch and shear (0.15: stretches of roughly 0.7-1.3). Redrawn until
  /// det F > 0.2. Deterministic in @p seed.
  dealii::Tensor<2, 3>
  random_deformation_gradient(const unsigned int seed, const double strain);

  /// A random orthonormal right-handed frame: f, s and n = f x s.
  systole::Fibres::FibreBasis
  random_fibre_basis(const unsigned int seed);

  /// random_deformation_gradient(seed, strain) with
  /// random_fibre_basis(seed + 1000).
  systole::Materials::PassiveInput
  random_passive_input(const unsigned int seed, const double strain);

  /// F = I with a random fibre frame (the laws must not care).
  systole::Materials::PassiveInput
  identity_input(const unsigned int seed = 1);

  /// F = I + (stretch - 1) a0 x a0: uniaxial stretch along the unit vector
  /// @p axis, all other directions unchanged.
  dealii::Tensor<2, 3>
  uniaxial_stretch(const dealii::Tensor<1, 3> &axis, const double stretch);
} // namespace test_support
