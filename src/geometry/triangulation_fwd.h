#pragma once

/// @file
/// The forward declaration of dealii::Triangulation, for the headers that
/// only take a triangulation by reference (so they need not include
/// deal.II/grid/tria.h).

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
} // namespace dealii
