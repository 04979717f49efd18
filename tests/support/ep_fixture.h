#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include "electrophysiology/monodomain.h"

#include <mpi.h>

#include <array>
#include <functional>
#include <vector>

/// @file
/// Small monodomain runs on boxes for the electrophysiology tests.

namespace test_support
{
  /// A box of hexahedra (or tetrahedra) with a uniform fibre direction.
  struct EPBox
  {
    dealii::Point<3>            lower;
    dealii::Point<3>            upper;
    std::array<unsigned int, 3> cells = {{1, 1, 1}};
    dealii::Tensor<1, 3>        fibre; ///< unit fibre direction
    /// Each hexahedron split into tetrahedra (Cell shape = tetrahedra:
    /// 24 per cube, P1).
    bool tetrahedra = false;
  };

  /// What a run produced.
  struct EPResult
  {
    /// Potential and activation times at the probes at the end.
    systole::Electrophysiology::PointValues       probes;
    systole::Electrophysiology::ActivationSummary summary;
    systole::Electrophysiology::Statistics        statistics;
    unsigned long long                            n_dofs = 0;
  };

  /// Run the monodomain model of @p params on @p box (distributed over
  /// @p comm) from 0 to @p end_time [ms], advancing in intervals of
  /// @p interval [ms], and evaluate at @p probes. @p after_interval, if
  /// given, is called with the model at the start and after every interval.
  EPResult
  run_ep_box(
    const systole::Electrophysiology::Parameters &params,
    const EPBox                                  &box,
    const double                                  end_time,
    const double                                  interval,
    const std::vector<dealii::Point<3>>          &probes,
    const MPI_Comm                                comm,
    const std::function<void(const systole::Electrophysiology::Monodomain &)>
      &after_interval = {});

  /// Fibre direction e_x, e_y or e_z.
  dealii::Tensor<1, 3>
  unit_vector(const unsigned int direction);
} // namespace test_support
