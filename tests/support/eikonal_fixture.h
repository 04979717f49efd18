#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include "electrophysiology/eikonal.h"

#include <mpi.h>

#include <array>
#include <string>
#include <vector>

/// @file
/// Eikonal solves on boxes for the tests: a point source in a homogeneous
/// anisotropic block against the ellipsoidal arrival times.
namespace test_support
{
  struct EikonalBlock
  {
    dealii::Point<3>            upper{4, 3, 2}; ///< lower corner at 0 [mm]
    std::array<unsigned int, 3> cells      = {{8, 6, 4}};
    bool                        tetrahedra = false;
    /// The fibre frame (rotated against the axes) and velocities [mm/ms].
    double           v_f = 0.6, v_s = 0.25, v_n = 0.15;
    dealii::Point<3> source{1.3, 1.1, 0.7};
    double           start = 2; ///< source time [ms]
    /// Nodes within this distance (max norm) of the source get the exact
    /// time [mm]; 0: one cell size.
    double exact_radius = 0;
    /// Instead of the point source: a plane front with this normal
    /// (not zero), the exact times given at every boundary node.
    dealii::Tensor<1, 3> plane_normal;
    /// A fast layer along a boundary part (EikonalSettings); empty: none.
    std::string layer_part;
    double      layer_thickness = 0, layer_velocity = 0;
  };

  struct EikonalBlockResult
  {
    /// Activation time of every node [ms], by global index (gathered on
    /// every rank), and the exact times.
    std::vector<double> times, exact;
    double              max_error = 0, mean_error = 0; ///< over the nodes [ms]
    unsigned int        rounds  = 0;
    unsigned long       n_nodes = 0;
  };

  /// The rotated fibre frame of EikonalBlock.
  systole::Fibres::FibreBasis
  eikonal_block_frame();

  /// Solve the point source of @p block on @p comm.
  EikonalBlockResult
  run_eikonal_block(const EikonalBlock &block, const MPI_Comm comm);
} // namespace test_support
