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
  /// recorder's samples hold the cavities' phases; 4: a third saved
  /// displacement and the heartbeat's times of the saved states (the
  /// quadratic predictor); 5: the heartbeat's valve indicators of the
  /// accepted state before the last and at the end of a crossing's bracket
  /// (the event location), the release of the supports referred to
  /// end-diastole (its start and end positions and time).
  constexpr unsigned int checkpoint_format = 5;

  /// The file of a checkpoint folder that holds the small state.
  constexpr const char *checkpoint_state_file = "state.txt";

  /// What StateWriter and StateReader share: a boost text archive of type
  /// @p Archive on the string stream @p Stream, opened after the header line
  /// with the stream in the classic locale plus boost::math's non-finite
  /// facets (the standard streams fail to read inf and nan back).
  template <class Stream, class Archive>
  class TextState
  {
  public:
    Archive &
    archive()
    {
      return *text_archive;
    }

  protected:
    ~TextState();

    /// Puts the locale on the stream and opens the archive on it.
    void
    open_archive();

    Stream                   stream;
    std::unique_ptr<Archive> text_archive;
  };

  // Instantiated in checkpoint_format.cc, where the archives are complete.
  extern template class TextState<std::ostringstream,
                                  boost::archive::text_oarchive>;
  extern template class TextState<std::istringstream,
                                  boost::archive::text_iarchive>;

  /// The small state of a checkpoint being written: the header line
  /// `systole-checkpoint <format> <byte order> <code version>`, then a boost
  /// text archive. Doubles are written with 17 significant digits (they read
  /// back bit for bit), infinities and NaN as `inf` and `nan` (boost::math's
  /// non-finite facets), so the text is the same on every machine.
  class StateWriter
    : public TextState<std::ostringstream, boost::archive::text_oarchive>
  {
  public:
    StateWriter();

    /// Close the archive and return the whole text.
    std::string
    finish();
  };

  /// The small state of a checkpoint being read, from the text a
  /// StateWriter wrote (the header is checked: see checkpoint_format_fault).
  class StateReader
    : public TextState<std::istringstream, boost::archive::text_iarchive>
  {
  public:
    /// @param[in] text the content of the state file
    /// @param[in] folder the checkpoint, named in error messages
    StateReader(const std::string &text, const std::string &folder);
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
