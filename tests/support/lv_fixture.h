#pragma once

#include "geometry/mesh.h"

#include <mpi.h>

/// @file
/// Small LV meshes for tests: the Land et al. 2015 ventricle, built as the app
/// builds it, and the parameters of the Arostica et al. 2025 ventricle.

namespace test_support
{
  /// Geometry / Type = arostica (LVShape::arostica()), refined
  /// @p refinements times.
  systole::Geometry::Parameters
  arostica_geometry(const unsigned int refinements);

  /// Exact volume of the cavity of the default (Land 2015) ventricle: the
  /// endocardial spheroid r_s = 7, r_l = 17 mm below the base plane z = 5 mm,
  /// in mm^3. V = pi r_s^2 / r_l^2 [r_l^2 z - z^3/3] from z = -r_l to z = 5.
  double
  land_cavity_volume();

  /// Cavity volume of the default ventricle (coarse 8 x 3 x 1 cells, refined
  /// @p refinements times) after the uniform stretch u = (lambda - 1)(X -
  /// x_base) about the centre of the base, computed with Q@p degree elements
  /// and a MappingQ@p mapping_degree on a distributed mesh over @p comm. Units:
  /// mm^3.
  double
  stretched_land_cavity_volume(const unsigned int refinements,
                               const double       lambda,
                               const unsigned int degree,
                               const unsigned int mapping_degree,
                               const MPI_Comm     comm);
} // namespace test_support
