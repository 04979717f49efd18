#pragma once

#include <deal.II/base/mpi.h>

#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace systole
{
  class Logger;
  struct RunParameters;
  namespace IO
  {
    class CheckpointStore;
  }

  /// Every entry of @p prm as deal.II's ShortPRM text: what a checkpoint
  /// records of the problem (the @p all_entries below).
  std::string
  checkpoint_entries(const dealii::ParameterHandler &prm);

  /// Resume: the newest valid checkpoint of the run in @p store, of this
  /// build's checkpoint format (IO::check_checkpoint_format) and written for
  /// the same problem (every entry outside subsection Output equal to
  /// @p all_entries, the ShortPRM text of the run's parameters); "" when the
  /// run does not resume. Throws with one line otherwise. Collective.
  std::string
  resume_checkpoint(const RunParameters &run,
                    IO::CheckpointStore &store,
                    const std::string   &all_entries,
                    Logger              &logger,
                    const MPI_Comm       comm);

  /// The files rank 0 writes into the checkpoint folder @p folder besides
  /// the meshes: the small state @p state (IO::checkpoint_state_file),
  /// `parameters.prm` (@p all_entries) and `parameter_file` (the file the
  /// run was started with, for `systole --resume`). Not collective.
  void
  write_checkpoint_files(const std::string   &folder,
                         const std::string   &state,
                         const std::string   &all_entries,
                         const RunParameters &run);
} // namespace systole
