#pragma once

#include <deal.II/base/mpi.h>

#include "base/archive_fwd.h"

#include <locale>
#include <memory>
#include <sstream>
#include <string>

namespace systole::IO
{
  /// The version of the checkpoint format this build writes and reads. A
  /// change to what a checkpoint holds or how (a component's state, the
  /// order in the state file, the files of the folder) increments it.
  ///
  /// History: 1: `state.bin`, a boost binary archive without a header (for
  /// the same build and machine type only); 2: `state.txt`, a header line
  /// and a boost text archive (portable, doubles exact); 3: the beat
  /// recorder's samples hold the cavities' phases.
  constexpr unsigned int checkpoint_format = 3;

  /// The file of a checkpoint folder that holds the small state.
  constexpr const char *checkpoint_state_file = "state.txt";

  /// The small state of a checkpoint being written: the header line
  /// `systole-checkpoint <format> <byte order> <code version>`, then a boost
  /// text archive. Doubles are written with 17 significant digits (they read
  /// back bit for bit), infinities and NaN as `inf` and `nan` (boost::math's
  /// non-finite facets), so the text is the same on every machine.
  class StateWriter
  {
  public:
    StateWriter();
    ~StateWriter();

    boost::archive::text_oarchive &
    archive();

    /// Close the archive and return the whole text.
    std::string
    finish();

  private:
    std::ostringstream                             stream;
    std::unique_ptr<boost::archive::text_oarchive> out;
  };

  /// The small state of a checkpoint being read, from the text a
  /// StateWriter wrote (the header is checked: see checkpoint_format_fault).
  class StateReader
  {
  public:
    /// @param[in] text the content of the state file
    /// @param[in] folder the checkpoint, named in error messages
    StateReader(const std::string &text, const std::string &folder);
    ~StateReader();

    boost::archive::text_iarchive &
    archive();

  private:
    std::istringstream                             stream;
    std::unique_ptr<boost::archive::text_iarchive> in;
  };

  /// Why the checkpoint @p folder cannot be read by this build ("" if it
  /// can): another format version (both named, and the code version that
  /// wrote it), the old binary format 1, another byte order (the meshes'
  /// data of deal.II and p4est are binary), or no Systole checkpoint. Not
  /// collective.
  std::string
  checkpoint_format_fault(const std::string &folder);

  /// Throws checkpoint_format_fault(@p folder) on every rank if it is not
  /// empty (read on rank 0). Collective.
  void
  check_checkpoint_format(const std::string &folder, const MPI_Comm comm);

  /// The state file of the checkpoint @p folder, read on rank 0, on every
  /// rank. Collective.
  std::string
  read_checkpoint_state(const std::string &folder, const MPI_Comm comm);
} // namespace systole::IO
