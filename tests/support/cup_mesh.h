#pragma once

#include <deal.II/base/function.h>
#include <deal.II/base/types.h>

#include <mpi.h>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
} // namespace dealii

/// @file
/// A small cavity with a rim for the cavity-volume tests: a box with a hole
/// open at the top, and smooth displacements that tilt and warp the rim.

namespace test_support
{
  /// Boundary ids of the cup.
  constexpr dealii::types::boundary_id cup_wall   = 0; ///< outer faces
  constexpr dealii::types::boundary_id cup_base   = 1; ///< top faces, z = 2
  constexpr dealii::types::boundary_id cup_cavity = 2; ///< faces of the hole

  /// The cup into the empty @p tria (serial or distributed): the box
  /// [0, 3] x [0, 3] x [0, 2] mm of 3 x 3 x 2 hexahedra without its top
  /// centre cell [1, 2] x [1, 2] x [1, 2], refined @p refinements times. The
  /// hole (5 faces, boundary id cup_cavity) is the cavity; its rim is the
  /// square where it meets the top (cup_base).
  void
  make_cup(dealii::Triangulation<3, 3> &tria, const unsigned int refinements);

  /// The cup of make_cup(..., 0) as tetrahedra (serial,
  /// GridGenerator::convert_hypercube_to_simplex_mesh), refined
  /// @p refinements times.
  void
  make_tet_cup(dealii::Triangulation<3, 3> &tria,
               const unsigned int           refinements);

  /// A smooth displacement [mm] that grows with the height z and tilts and
  /// warps the top of the cup: on z = 2 the rim rises by 0.25 (x - 1.5) and
  /// by a warp of amplitude @p warp; @p phase varies the field.
  class WarpingDisplacement : public dealii::Function<3>
  {
  public:
    WarpingDisplacement(const double warp, const double phase);

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override;

  private:
    double warp, phase;
  };

  /// What fan_cavity_study() measures.
  struct FanCavityStudy
  {
    unsigned int n_rim_vertices;
    double       volume;     ///< [mm^3]
    double       derivative; ///< dV/du . d [mm^3/mm]
  };

  /// The rim-fan cavity of the cup (make_cup(@p refinements), distributed
  /// over @p comm, Q2 on MappingQ2) for u = WarpingDisplacement(0.15, 0.3):
  /// its volume and its derivative along d = WarpingDisplacement(0.3, 1.1).
  FanCavityStudy
  fan_cavity_study(const unsigned int refinements, const MPI_Comm comm);
} // namespace test_support
