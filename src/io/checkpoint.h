#pragma once

#include <deal.II/base/mpi.h>

#include <ostream>
#include <string>
#include <vector>

namespace systole::IO
{
  /// The checkpoints of a run: folders `<run>/checkpoint_NNNNNN` (NNNNNN the
  /// index of the last accepted step), each holding the files the components
  /// write (the meshes with their cell data, the small state) and a
  /// `MANIFEST` with the size and CRC-32 of every file.
  ///
  /// Writing is atomic: the files go to `<run>/checkpoint.tmp`, the manifest
  /// is written last, and the folder is then renamed to its final name
  /// (rename(2) of a folder is atomic), so a run killed while writing leaves
  /// the previous checkpoints intact and an unfinished `checkpoint.tmp` that
  /// is never read. After a commit only the newest `keep` checkpoints remain.
  /// All functions are collective; the file system work is done on rank 0.
  class CheckpointStore
  {
  public:
    CheckpointStore(const std::string &run_directory,
                    const MPI_Comm     comm,
                    const unsigned int keep = 2);

    /// Create an empty temporary folder for the checkpoint of step @p step
    /// and return its path (with a trailing '/').
    std::string
    begin(const unsigned int step);

    /// Write the manifest of the temporary folder, rename it to its final
    /// name and remove the oldest checkpoints beyond `keep`. Returns the
    /// final path.
    std::string
    commit();

    /// The checkpoint folders, newest first.
    std::vector<std::string>
    list() const;

    /// The newest checkpoint whose files match its manifest ("" if none).
    /// Each one skipped is reported on @p log (rank 0) by one line naming the
    /// file and the fault.
    std::string
    newest_valid(std::ostream &log) const;

    /// Why @p folder is not a valid checkpoint ("" if it is): the first file
    /// missing, of the wrong size or with the wrong checksum, or a missing
    /// manifest. Not collective.
    static std::string
    fault(const std::string &folder);

  private:
    std::string  directory;
    MPI_Comm     comm;
    unsigned int keep;
    std::string  pending;
    unsigned int pending_step = 0;
  };

  /// The entries of two parameter texts in deal.II's ShortPRM format
  /// (`subsection`, `set name = value`, `end`) that differ, as "Section /
  /// Entry: 'saved value' in the checkpoint, 'current value' now", ignoring
  /// the top-level subsections in @p ignored.
  std::vector<std::string>
  parameter_differences(const std::string              &saved,
                        const std::string              &current,
                        const std::vector<std::string> &ignored);
} // namespace systole::IO
