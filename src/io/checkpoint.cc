#include "io/checkpoint.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <boost/crc.hpp>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace systole::IO
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr const char *prefix = "checkpoint_";

    /// CRC-32 and size of a file.
    std::pair<std::uintmax_t, unsigned int>
    checksum(const fs::path &file)
    {
      std::ifstream      in(file, std::ios::binary);
      boost::crc_32_type crc;
      std::vector<char>  buffer(1 << 20);
      std::uintmax_t     size = 0;
      while (in)
        {
          in.read(buffer.data(), buffer.size());
          const auto n = in.gcount();
          crc.process_bytes(buffer.data(), n);
          size += n;
        }
      return {size, crc.checksum()};
    }

    /// Flush a file or folder to the disk.
    void
    sync(const fs::path &path)
    {
      const int fd = ::open(path.c_str(), O_RDONLY);
      if (fd >= 0)
        {
          ::fsync(fd);
          ::close(fd);
        }
    }

    /// Run @p f on rank 0; every rank throws its error message if it failed.
    template <class Function>
    void
    on_root(const MPI_Comm comm, const Function &f)
    {
      std::string error;
      if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
        try
          {
            f();
          }
        catch (const std::exception &e)
          {
            error = e.what();
            if (error.empty())
              error = "unknown error";
          }
      error = dealii::Utilities::MPI::broadcast(comm, error, 0);
      AssertThrow(error.empty(), dealii::ExcMessage(error));
    }
  } // namespace


  CheckpointStore::CheckpointStore(const std::string &run_directory,
                                   const MPI_Comm     comm,
                                   const unsigned int keep)
    : directory(run_directory)
    , comm(comm)
    , keep(std::max(keep, 1u))
  {}


  std::string
  CheckpointStore::begin(const unsigned int step)
  {
    pending      = (fs::path(directory) / "checkpoint.tmp").string();
    pending_step = step;
    on_root(comm, [&]() {
      fs::remove_all(pending);
      fs::create_directories(pending);
    });
    return pending + "/";
  }


  std::string
  CheckpointStore::commit()
  {
    AssertThrow(!pending.empty(),
                dealii::ExcMessage("CheckpointStore::commit before begin()."));
    char name[32];
    std::snprintf(name, sizeof(name), "%s%06u", prefix, pending_step);
    const fs::path final_path = fs::path(directory) / name;
    // Every rank has closed its files before the manifest sums them.
    MPI_Barrier(comm);
    on_root(comm, [&]() {
      std::vector<fs::path> files;
      for (const auto &entry : fs::directory_iterator(pending))
        if (entry.is_regular_file())
          files.push_back(entry.path());
      std::sort(files.begin(), files.end());
      std::ostringstream manifest;
      for (const auto &file : files)
        {
          sync(file);
          const auto [size, crc] = checksum(file);
          manifest << size << ' ' << std::hex << crc << std::dec << ' '
                   << file.filename().string() << '\n';
        }
      {
        std::ofstream out(fs::path(pending) / "MANIFEST");
        out << manifest.str();
        AssertThrow(out.good(),
                    dealii::ExcMessage("Cannot write the manifest of " +
                                       pending + "."));
      }
      sync(fs::path(pending) / "MANIFEST");
      sync(pending);
      fs::remove_all(final_path);
      fs::rename(pending, final_path);
      sync(directory);
      // Keep the newest ones.
      std::vector<std::string> all;
      for (const auto &entry : fs::directory_iterator(directory))
        if (entry.is_directory() &&
            entry.path().filename().string().rfind(prefix, 0) == 0)
          all.push_back(entry.path().string());
      std::sort(all.rbegin(), all.rend());
      for (std::size_t i = keep; i < all.size(); ++i)
        fs::remove_all(all[i]);
    });
    pending.clear();
    return final_path.string();
  }


  std::vector<std::string>
  CheckpointStore::list() const
  {
    std::vector<std::string> all;
    if (fs::is_directory(directory))
      for (const auto &entry : fs::directory_iterator(directory))
        if (entry.is_directory() &&
            entry.path().filename().string().rfind(prefix, 0) == 0)
          all.push_back(entry.path().string());
    std::sort(all.rbegin(), all.rend());
    return all;
  }


  std::string
  CheckpointStore::fault(const std::string &folder)
  {
    const fs::path manifest_path = fs::path(folder) / "MANIFEST";
    std::ifstream  manifest(manifest_path);
    if (!manifest)
      return manifest_path.string() + " is missing (an unfinished write)";
    std::string  line;
    unsigned int n_files = 0;
    while (std::getline(manifest, line))
      {
        std::istringstream in(line);
        std::uintmax_t     size = 0;
        unsigned int       crc  = 0;
        std::string        name;
        in >> size >> std::hex >> crc >> std::dec >> name;
        if (!in || name.empty())
          return manifest_path.string() + " is corrupt";
        const fs::path file = fs::path(folder) / name;
        if (!fs::is_regular_file(file))
          return file.string() + " is missing";
        const auto [actual_size, actual_crc] = checksum(file);
        if (actual_size != size)
          return file.string() + " is truncated or corrupt (" +
                 std::to_string(actual_size) + " bytes, the manifest says " +
                 std::to_string(size) + ")";
        if (actual_crc != crc)
          return file.string() + " is corrupt (checksum mismatch)";
        ++n_files;
      }
    if (n_files == 0)
      return manifest_path.string() + " lists no files";
    return "";
  }


  std::string
  CheckpointStore::newest_valid(std::ostream &log) const
  {
    std::string chosen;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        const auto all = list();
        for (unsigned int i = 0; i < all.size(); ++i)
          {
            const std::string why = fault(all[i]);
            if (why.empty())
              {
                chosen = all[i];
                break;
              }
            log << "Checkpoint fault: " << why << "; "
                << (i + 1 < all.size() ? "falling back to " + all[i + 1]
                                       : std::string("no older checkpoint"))
                << std::endl;
          }
      }
    return dealii::Utilities::MPI::broadcast(comm, chosen, 0);
  }


  namespace
  {
    /// Entry path ("A / B / name") -> value of a ShortPRM text.
    std::map<std::string, std::string>
    parse_short_prm(const std::string &text)
    {
      std::map<std::string, std::string> entries;
      std::vector<std::string>           path;
      std::istringstream                 in(text);
      std::string                        line;
      const auto                         trim = [](const std::string &s) {
        const auto begin = s.find_first_not_of(" \t");
        if (begin == std::string::npos)
          return std::string();
        const auto end = s.find_last_not_of(" \t\r");
        return s.substr(begin, end - begin + 1);
      };
      while (std::getline(in, line))
        {
          line = trim(line);
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(trim(line.substr(11)));
          else if (line == "end")
            {
              if (!path.empty())
                path.pop_back();
            }
          else if (line.rfind("set ", 0) == 0)
            {
              const auto  equal = line.find('=');
              std::string key;
              for (const auto &section : path)
                key += section + " / ";
              key += trim(line.substr(4, equal - 4));
              entries[key] =
                equal == std::string::npos ? "" : trim(line.substr(equal + 1));
            }
        }
      return entries;
    }
  } // namespace


  std::vector<std::string>
  parameter_differences(const std::string              &saved,
                        const std::string              &current,
                        const std::vector<std::string> &ignored)
  {
    const auto a = parse_short_prm(saved), b = parse_short_prm(current);
    const auto is_ignored = [&](const std::string &key) {
      for (const auto &section : ignored)
        if (key.rfind(section + " / ", 0) == 0)
          return true;
      return false;
    };
    std::vector<std::string> differences;
    for (const auto &[key, value] : a)
      {
        if (is_ignored(key))
          continue;
        const auto it = b.find(key);
        if (it == b.end())
          differences.push_back(key + ": '" + value +
                                "' in the checkpoint, not declared now");
        else if (it->second != value)
          differences.push_back(key + ": '" + value + "' in the checkpoint, '" +
                                it->second + "' now");
      }
    for (const auto &[key, value] : b)
      if (!is_ignored(key) && a.find(key) == a.end())
        differences.push_back(key + ": not in the checkpoint, '" + value +
                              "' now");
    return differences;
  }
} // namespace systole::IO
