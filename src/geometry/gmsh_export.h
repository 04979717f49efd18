#pragma once

#include <deal.II/grid/tria.h>

#include "geometry/boundary_names.h"

#include <string>

namespace systole::Geometry
{
  /// Write the active cells of @p tria (serial or distributed: every rank
  /// sends its locally owned cells to rank 0, which writes) as an ASCII gmsh
  /// file, format 2.2, that read_gmsh() reads back with the same boundary
  /// parts: one node per vertex, one hexahedron (type 5) or tetrahedron
  /// (type 4) per cell (physical volume = the cell's material id + 1, named
  /// "myocardium" when it is the only one), one quadrangle (type 3) or
  /// triangle (type 2) per boundary face (physical surface = the boundary id
  /// + 1), and the physical names of @p names (tag 0 means "no physical
  /// group" to gmsh, hence the shift; the ids read back differ, the names do
  /// not). The geometry is the vertices only (trilinear or affine cells), as
  /// gmsh's first-order elements store it: curved manifolds are not written.
  /// Lengths in mm. Collective.
  void
  write_gmsh(const dealii::Triangulation<3, 3> &tria,
             const BoundaryNames               &names,
             const std::string                 &file);
} // namespace systole::Geometry
