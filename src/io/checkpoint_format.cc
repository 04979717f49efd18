#include "io/checkpoint_format.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include "io/results_file.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/math/special_functions/nonfinite_num_facets.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace systole::IO
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr const char *magic = "systole-checkpoint";

    std::string
    byte_order()
    {
      const std::uint16_t one = 1;
      unsigned char       first;
      std::memcpy(&first, &one, 1);
      return first == 1 ? "little-endian" : "big-endian";
    }

    /// The classic locale with boost::math's facets that write and read
    /// inf and nan (the standard streams fail to read them back).
    std::locale
    portable_locale()
    {
      const std::locale with_put(std::locale::classic(),
                                 new boost::math::nonfinite_num_put<char>);
      return std::locale(with_put, new boost::math::nonfinite_num_get<char>);
    }

    struct Header
    {
      bool         valid = false;
      unsigned int format;
      std::string  byte_order, code_version;
    };

    Header
    parse_header(const std::string &line)
    {
      Header             h;
      std::istringstream in(line);
      std::string        word;
      if (!(in >> word) || word != magic || !(in >> h.format >> h.byte_order))
        return h;
      std::getline(in >> std::ws, h.code_version);
      h.valid = true;
      return h;
    }

    std::string
    this_build()
    {
      return "this build (" + code_version() + ") reads format " +
             std::to_string(checkpoint_format);
    }
  } // namespace


  template <class Stream, class Archive>
  TextState<Stream, Archive>::~TextState() = default;


  template <class Stream, class Archive>
  void
  TextState<Stream, Archive>::open_archive()
  {
    stream.imbue(portable_locale());
    text_archive =
      std::make_unique<Archive>(stream, boost::archive::no_codecvt);
  }


  template class TextState<std::ostringstream, boost::archive::text_oarchive>;
  template class TextState<std::istringstream, boost::archive::text_iarchive>;


  StateWriter::StateWriter()
  {
    stream << magic << ' ' << checkpoint_format << ' ' << byte_order() << ' '
           << code_version() << '\n';
    open_archive();
  }


  std::string
  StateWriter::finish()
  {
    text_archive.reset();
    return stream.str();
  }


  StateReader::StateReader(const std::string &text, const std::string &folder)
  {
    stream.str(text);
    std::string line;
    std::getline(stream, line);
    const Header h = parse_header(line);
    AssertThrow(h.valid && h.format == checkpoint_format,
                dealii::ExcMessage("The state of the checkpoint " + folder +
                                   " is not in checkpoint format " +
                                   std::to_string(checkpoint_format) + "."));
    open_archive();
  }


  std::string
  checkpoint_format_fault(const std::string &folder)
  {
    const fs::path state = fs::path(folder) / checkpoint_state_file;
    if (!fs::is_regular_file(state))
      {
        if (fs::is_regular_file(fs::path(folder) / "state.bin"))
          return "The checkpoint " + folder +
                 " is in checkpoint format 1 (a binary state.bin, written by "
                 "Systole before checkpoints had a format version); " +
                 this_build() +
                 ": finish the run with the build that wrote it, or start it "
                 "again.";
        return "The checkpoint " + folder + " has no " + checkpoint_state_file +
               ": not a Systole checkpoint of format " +
               std::to_string(checkpoint_format) + ".";
      }
    std::ifstream in(state);
    std::string   line;
    std::getline(in, line);
    const Header h = parse_header(line);
    if (!h.valid)
      return "The checkpoint " + folder + " is in an unknown format (" +
             state.string() + " does not begin with '" + magic +
             " <format>'); " + this_build() + ".";
    if (h.format != checkpoint_format)
      return "The checkpoint " + folder + " is in checkpoint format " +
             std::to_string(h.format) + " (written by " + h.code_version +
             "); " + this_build() + ": resume it with a build of format " +
             std::to_string(h.format) + ", or start the run again.";
    if (h.byte_order != byte_order())
      return "The checkpoint " + folder + " was written on a " + h.byte_order +
             " machine and this one is " + byte_order() +
             ": its meshes' data (deal.II, p4est) are binary; resume it on a " +
             h.byte_order + " machine.";
    return "";
  }


  void
  check_checkpoint_format(const std::string &folder, const MPI_Comm comm)
  {
    std::string fault;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      fault = checkpoint_format_fault(folder);
    fault = dealii::Utilities::MPI::broadcast(comm, fault, 0);
    AssertThrow(fault.empty(), dealii::ExcMessage(fault));
  }


  std::string
  read_checkpoint_state(const std::string &folder, const MPI_Comm comm)
  {
    std::string bytes;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::ifstream      in(fs::path(folder) / checkpoint_state_file);
        std::ostringstream o;
        o << in.rdbuf();
        bytes = o.str();
      }
    return dealii::Utilities::MPI::broadcast(comm, bytes, 0);
  }
} // namespace systole::IO
