#pragma once

#include "materials/holzapfel_ogden.h"

/// @file
/// Parameter sets of the passive laws shared by several tests.

namespace test_support
{
  /// Holzapfel-Ogden with the default parameters but no sheet and no
  /// fibre-sheet terms (a_s = a_fs = 0): the transversely isotropic law.
  systole::Materials::HolzapfelOgden::Parameters
  transversely_isotropic_holzapfel_ogden();
} // namespace test_support
