#pragma once

#include <deal.II/base/mpi.h>

#include <iosfwd>
#include <string>

namespace systole
{
  /// Number of transmural depth bins of the helix-angle profile.
  constexpr unsigned int n_helix_profile_bins = 10;

  /// What `systole-fibres FILE.prm` does: read the parameter file as
  /// `systole` does, build its mesh and fibre field (subsections Geometry and
  /// Fibres; every frame passes the validator), and write
  /// `<Output/Directory>/<run name>/results.h5` (+ fields.xdmf for ParaView):
  /// - /fields/step_000000: the unit vectors fibre, sheet, sheet_normal at the
  ///   vertices of every cell (each cell's own values: a discontinuous Q1
  ///   or P1 field), and, on LV and BiV meshes, transmural (phi), apicobasal
  ///   (psi) and helix_angle [degree];
  /// - /summary: the helix-angle profile through the wall, one row per bin of
  ///   the transmural coordinate phi (n_helix_profile_bins equal bins of
  ///   [0, 1]): depth_lower, depth_upper, depth (bin centre), helix_mean
  ///   (volume-weighted), helix_min, helix_max [degree], n_points (NaN
  ///   angles for an empty bin), sampled at the Gauss points of every cell
  ///   (5 x 5 x 5 on a hexahedron, QGaussSimplex(4) on a
  ///   tetrahedron);
  /// - /timeseries: one row (step, time, n_cells, n_points).
  ///
  /// The helix angle is measured in the wall frame of the rule-based
  /// generator's solves (Fibres::WallCoordinates, with the degree and
  /// apicobasal field of subsection Fibres / Rule-based), whatever the
  /// generator, as atan2(f . e_l, f . e_c) (folded into (-90, 90] for the dti
  /// generator, whose fibres have no sign), and the depth is its phi. That
  /// frame exists on every LV mesh (generated or gmsh) and for every
  /// generator, so profiles are comparable; on the generated ellipsoid it
  /// agrees with the analytic frame to hundredths of a degree away from the
  /// apex (tests/unit/fibres/rule_based_test.cc), but phi is the harmonic
  /// transmural coordinate, not the geometric t of the analytic rule (they
  /// differ by up to about 0.1). On BiV meshes (boundary parts
  /// lv_endocardium, rv_endocardium, epicardium and base) the frame and depth
  /// are those of Fibres::Biventricular::wall_frames (phi_epi, psi of
  /// subsection Fibres / Biventricular). Meshes without either set of parts (a
  /// box) get the fibre vectors only. Collective; throws one clear message on
  /// bad input.
  void
  inspect_fibres(const std::string &parameter_file,
                 const MPI_Comm     comm,
                 std::ostream      &out);
} // namespace systole
