#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria_base.h>

#include "base/archive_fwd.h"

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
  struct RunParameters;
  struct RunInputs;
  namespace IO
  {
    class CheckpointStore;
    class ResultsFile;
    class StateReader;
  } // namespace IO

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

  /// The results file of the run @p in: new, or (resuming from
  /// @p checkpoint) reopened with the rows of the checkpoint's small state,
  /// whose rest @p state_in then reads (the rows and the step, into
  /// @p resumed_step if given, come first in it, see
  /// RunCheckpointer::write()). Collective.
  std::unique_ptr<IO::ResultsFile>
  open_results(const std::string                &checkpoint,
               const RunInputs                  &in,
               std::unique_ptr<IO::StateReader> &state_in,
               unsigned int                     *resumed_step = nullptr);

  /// Whether the checkpoint of step @p step is due: every Output /
  /// Checkpoint interval steps, or Output / Checkpoint minutes after
  /// @p last (the latest rank decides). Collective when minutes are set.
  bool
  checkpoint_due(const RunParameters                         &run,
                 const unsigned int                           step,
                 const std::chrono::steady_clock::time_point &last,
                 const MPI_Comm                               comm);

  /// What a RunCheckpointer writes from and into: its constructor's
  /// argument and its members (kept by reference but the mesh file's name).
  struct RunCheckpointerParts
  {
    IO::CheckpointStore                                        &store;
    const IO::ResultsFile                                      &results;
    const dealii::parallel::DistributedTriangulationBase<3, 3> &tria;
    const std::string                                           mesh_file;
    const std::string                                          &all_entries;
    const RunParameters                                        &run;
    Logger                                                     &logger;
    const MPI_Comm                                              comm;
  };

  /// Writes the checkpoints of a run into @p store: the small state (the
  /// results file's rows, the step, then what the caller saves) through
  /// boost serialization, the parameters, and the mesh with its attached
  /// cell data (Triangulation::save into `<mesh_file>`); into a temporary
  /// folder renamed when complete. A write that fails stops every rank with
  /// one line naming the file, the reason, the intact previous checkpoint
  /// and the fix.
  class RunCheckpointer : private RunCheckpointerParts
  {
  public:
    /// Saves the run's state after the rows and the step; @p folder is the
    /// checkpoint's (for files of its own).
    using SaveState = std::function<void(boost::archive::text_oarchive &archive,
                                         const std::string &folder)>;

    explicit RunCheckpointer(const RunCheckpointerParts &parts);

    /// Writes the checkpoint of step @p step: @p save fills the small state
    /// (it may attach cell data to the mesh), @p after_mesh runs after the
    /// mesh's save (to release what @p save attached). Collective.
    void
    write(const unsigned int           step,
          const SaveState             &save,
          const std::function<void()> &after_mesh);

    /// The checkpoint folders, newest first.
    std::vector<std::string>
    list() const;

    /// The run's folder (for systole --resume).
    const std::string &
    output_directory() const;

    /// Checkpoints written and the seconds they took.
    unsigned int count   = 0;
    double       seconds = 0;

  private:
    /// Throw on every rank, naming the intact previous checkpoint, if rank
    /// @p failed_rank (< the number of ranks) has an @p error.
    void
    stop_if_failed(const std::string &error,
                   const unsigned int failed_rank,
                   const unsigned int step) const;

    /// Write the small state, the parameters and the parameter file's name
    /// into @p folder; returns "" or what failed (file and reason).
    std::string
    write_files(const std::string &folder,
                const std::string &data,
                const unsigned int step) const;
  };
} // namespace systole
