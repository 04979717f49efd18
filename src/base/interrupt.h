#pragma once

#include <deal.II/base/mpi.h>

namespace systole
{
  /// Catch SIGINT and SIGTERM so a run stops after the current step with a
  /// complete results file instead of dying mid-write. Call once at start-up.
  void
  install_interrupt_handlers();

  /// Whether any rank received SIGINT/SIGTERM (collective over @p comm).
  bool
  interrupted(const MPI_Comm comm);
} // namespace systole
