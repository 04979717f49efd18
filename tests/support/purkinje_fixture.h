#pragma once

#include "electrophysiology/purkinje.h"

#include <mpi.h>

#include <array>
#include <vector>

/// @file
/// A Purkinje tree on the endocardium of the small (Land 2015) ventricle
/// and the eikonal activation of the wall through it, for the tests.

namespace test_support
{
  /// Tree parameters scaled to the small ventricle (endocardium r_s = 7,
  /// r_l = 17 mm): the His point on the base's rim at +x, towards the apex.
  systole::Electrophysiology::PurkinjeParameters
  small_purkinje_parameters();

  struct PurkinjeRun
  {
    /// The endocardial triangles (the same on every rank).
    std::vector<std::array<dealii::Point<3>, 3>> triangles;
    systole::Electrophysiology::PurkinjeNetwork  network;
    /// With a right bundle: the nodes of the left tree (numbered first).
    unsigned int n_left = 0;
    /// Per junction: the position of the mesh node nearest to it and that
    /// node's myocardial eikonal time [ms] (on every rank).
    std::vector<dealii::Point<3>> junction_node;
    std::vector<double>           junction_node_time;
    double                        h = 0; ///< largest cell edge [mm]
    /// Mesh nodes the myocardial eikonal did not reach (all ranks).
    unsigned long n_unreached = 0;
    double        velocity    = 0.6; ///< myocardial (isotropic) speed [mm/ms]
  };

  /// Grow the tree of @p params on the endocardium of the Land ventricle
  /// (and a right bundle, if @p params has one, on its surface)
  /// (coarse 8 x 3 x 1 cells refined @p refinements times, distributed
  /// over @p comm), activate it from 0 ms and, if @p eikonal, solve the
  /// myocardial eikonal from its junctions.
  PurkinjeRun
  run_purkinje_lv(const systole::Electrophysiology::PurkinjeParameters &params,
                  const unsigned int refinements,
                  const bool         eikonal,
                  const MPI_Comm     comm);

  /// Distance from @p p to the triangle @p t computed without
  /// closest_point_on_triangle(): the plane's distance if the foot lies
  /// inside (barycentric coordinates), else the nearest of the three edges.
  double
  distance_to_triangle(const dealii::Point<3>                &p,
                       const std::array<dealii::Point<3>, 3> &t);
} // namespace test_support
