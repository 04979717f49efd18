#pragma once

#include "electrophysiology/purkinje.h"
#include "io/results_file.h"

/// @file
/// The Purkinje network in the results, shared by Problem =
/// electrophysiology and Problem = heartbeat.

namespace systole
{
  /// Writes @p network (nothing if it is empty) to @p results as the tables
  /// /purkinje/nodes (x, y, z [mm], activation_time [ms], junction [-]: 1
  /// at a Purkinje-muscle junction) and /purkinje/edges (parent, child:
  /// node numbers from 0), and beside the results file purkinje.xdmf, the
  /// tree as a polyline with its activation time for ParaView (data inline:
  /// the file stands alone). Collective.
  void
  write_purkinje(IO::ResultsFile                          &results,
                 const Electrophysiology::PurkinjeNetwork &network,
                 const MPI_Comm                            comm);
} // namespace systole
