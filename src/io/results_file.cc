#include "io/results_file.h"

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace systole::IO
{

  namespace
  {
    /// A failed HDF5 call: what was being done, and the system's reason
    /// (errno, e.g. "No space left on device") when there is one.
    struct WriteFailure : std::runtime_error
    {
      explicit WriteFailure(const std::string &what)
        : std::runtime_error(
            what + (errno != 0 ? std::string(": ") + std::strerror(errno)
                               : std::string()))
      {}
    };

    void
    check(const herr_t status, const std::string &what)
    {
      if (status < 0)
        throw WriteFailure(what);
    }

    /// Whether the file at @p path can grow by @p bytes (a full disk, a
    /// quota or a file size limit says no, errno why): the space reserved
    /// past its end (posix_fallocate) and given back. Parallel HDF5 does not
    /// survive a write that fails on one rank only (the others wait at a
    /// barrier inside it), so the writes are checked before they start.
    bool
    can_grow(const std::string &path, const std::uintmax_t bytes)
    {
      const int fd = ::open(path.c_str(), O_WRONLY);
      if (fd < 0)
        return false;
      struct stat status;
      bool        ok = ::fstat(fd, &status) == 0;
      if (ok)
        {
          const int error =
            ::posix_fallocate(fd, status.st_size, static_cast<off_t>(bytes));
          ok = error == 0;
          if (!ok)
            errno = error;
          if (::ftruncate(fd, status.st_size) != 0 && ok)
            ok = false;
        }
      const int saved = errno;
      ::close(fd);
      errno = saved;
      return ok;
    }

    hid_t
    checked(const hid_t id, const std::string &what)
    {
      if (id < 0)
        throw WriteFailure(what);
      return id;
    }

    /// Creates the dataset @p name of @p type and dataspace @p space in
    /// @p location (creation properties @p properties); throws naming
    /// @p what.
    hid_t
    create_dataset(const hid_t        location,
                   const std::string &name,
                   const hid_t        type,
                   const hid_t        space,
                   const std::string &what,
                   const hid_t        properties = H5P_DEFAULT)
    {
      return checked(H5Dcreate2(location,
                                name.c_str(),
                                type,
                                space,
                                H5P_DEFAULT,
                                properties,
                                H5P_DEFAULT),
                     what);
    }

    /// Creates the group @p name in @p parent with its links' creation order
    /// tracked, so readers list the columns in the order written.
    hid_t
    create_ordered_group(const hid_t        parent,
                         const std::string &name,
                         const std::string &what)
    {
      const hid_t plist = checked(H5Pcreate(H5P_GROUP_CREATE), "group plist");
      check(H5Pset_link_creation_order(plist,
                                       H5P_CRT_ORDER_TRACKED |
                                         H5P_CRT_ORDER_INDEXED),
            "creation order");
      const hid_t group = checked(
        H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, plist, H5P_DEFAULT),
        what);
      H5Pclose(plist);
      return group;
    }

    void
    write_string_attribute(const hid_t        object,
                           const char        *name,
                           const std::string &value)
    {
      const hid_t type = checked(H5Tcopy(H5T_C_S1), "string type");
      check(H5Tset_size(type, std::max<std::size_t>(value.size(), 1)),
            "string size");
      const hid_t space = checked(H5Screate(H5S_SCALAR), "scalar space");
      const hid_t attr =
        checked(H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT),
                std::string("attribute ") + name);
      check(H5Awrite(attr, type, value.c_str()),
            std::string("attribute ") + name);
      H5Aclose(attr);
      H5Sclose(space);
      H5Tclose(type);
    }

    template <typename T>
    void
    write_scalar_attribute(const hid_t object,
                           const char *name,
                           const hid_t type,
                           const T     value)
    {
      const hid_t space = checked(H5Screate(H5S_SCALAR), "scalar space");
      const hid_t attr =
        checked(H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT),
                std::string("attribute ") + name);
      check(H5Awrite(attr, type, &value), std::string("attribute ") + name);
      H5Aclose(attr);
      H5Sclose(space);
    }

    /// A group of extendable 1-D float64 columns (the time series or the
    /// summary).
    struct Table
    {
      std::string              group_name;
      hid_t                    group = -1;
      std::vector<std::string> names;
      std::vector<hid_t>       datasets;
      hsize_t                  n_rows = 0;

      void
      append(const hid_t file, const std::vector<Column> &row, const bool root)
      {
        if (group < 0)
          {
            group =
              create_ordered_group(file, group_name, "group " + group_name);
            for (const auto &column : row)
              {
                const hsize_t initial = 0, maximum = H5S_UNLIMITED, chunk = 256;
                const hid_t   space =
                  checked(H5Screate_simple(1, &initial, &maximum), "space");
                const hid_t plist =
                  checked(H5Pcreate(H5P_DATASET_CREATE), "plist");
                check(H5Pset_chunk(plist, 1, &chunk), "chunk");
                // No fill values: parallel HDF5 would write them while
                // extending the column (H5Dset_extent), and a failed write
                // there leaves the other ranks at a barrier inside HDF5. The
                // row's own write, agreed on by guarded(), fails instead.
                check(H5Pset_fill_time(plist, H5D_FILL_TIME_NEVER),
                      "fill time");
                const hid_t dataset = create_dataset(group,
                                                     column.name,
                                                     H5T_NATIVE_DOUBLE,
                                                     space,
                                                     "column " + column.name,
                                                     plist);
                write_string_attribute(dataset, "unit", column.unit);
                H5Pclose(plist);
                H5Sclose(space);
                names.push_back(column.name);
                datasets.push_back(dataset);
              }
          }
        AssertThrow(row.size() == names.size(),
                    dealii::ExcMessage(
                      "Internal error: a row of " + group_name + " has " +
                      std::to_string(row.size()) + " columns, the first had " +
                      std::to_string(names.size()) + "."));

        for (unsigned int c = 0; c < row.size(); ++c)
          AssertThrow(row[c].name == names[c],
                      dealii::ExcMessage("Internal error: column " +
                                         row[c].name + " where " + names[c] +
                                         " was expected."));
        // Every rank makes the same collective calls even after one of
        // them failed on it (a write past a full disk fails on the rank
        // that writes only): the first failure is thrown at the end, and
        // guarded() stops every rank with it.
        std::string failure;
        int         failure_errno = 0;
        const auto  note = [&](const herr_t status, const std::string &what) {
          if (status < 0 && failure.empty())
            {
              failure       = what;
              failure_errno = errno;
            }
        };
        const hsize_t new_size = n_rows + 1;
        const hid_t   transfer =
          checked(H5Pcreate(H5P_DATASET_XFER), "transfer plist");
        check(H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE),
              "collective transfer");
        for (unsigned int c = 0; c < row.size(); ++c)
          {
            note(H5Dset_extent(datasets[c], &new_size), "extend " + names[c]);
            const hid_t file_space =
              checked(H5Dget_space(datasets[c]), "space");
            const hsize_t offset = n_rows, count = root ? 1 : 0;
            check(H5Sselect_hyperslab(file_space,
                                      H5S_SELECT_SET,
                                      &offset,
                                      nullptr,
                                      &count,
                                      nullptr),
                  "select");
            const hid_t memory_space =
              checked(H5Screate_simple(1, &count, nullptr), "space");
            if (!root)
              H5Sselect_none(memory_space);
            note(H5Dwrite(datasets[c],
                          H5T_NATIVE_DOUBLE,
                          memory_space,
                          file_space,
                          transfer,
                          &row[c].value),
                 "write " + names[c]);
            H5Sclose(memory_space);
            H5Sclose(file_space);
          }
        H5Pclose(transfer);
        if (!failure.empty())
          {
            errno = failure_errno;
            throw WriteFailure(failure);
          }
        n_rows = new_size;
      }

      void
      close()
      {
        for (const hid_t d : datasets)
          H5Dclose(d);
        datasets.clear();
        if (group >= 0)
          H5Gclose(group);
        group = -1;
      }
    };

    /// Write a 2-D dataset of global shape (n_global x width), this rank's rows
    /// at @p offset.
    void
    write_distributed(const hid_t        location,
                      const std::string &name,
                      const hid_t        memory_type,
                      const hid_t        file_type,
                      const void        *data,
                      const hsize_t      n_local,
                      const hsize_t      offset,
                      const hsize_t      n_global,
                      const hsize_t      width)
    {
      const hsize_t global_dims[2] = {n_global, width};
      const hid_t   file_space =
        checked(H5Screate_simple(2, global_dims, nullptr), "space");
      const hid_t   dataset  = create_dataset(location,
                                           name,
                                           file_type,
                                           file_space,
                                           "dataset " + name);
      const hsize_t start[2] = {offset, 0}, count[2] = {n_local, width};
      const hid_t   memory_space =
        checked(H5Screate_simple(2, count, nullptr), "space");
      if (n_local > 0)
        check(H5Sselect_hyperslab(file_space,
                                  H5S_SELECT_SET,
                                  start,
                                  nullptr,
                                  count,
                                  nullptr),
              "select");
      else
        {
          H5Sselect_none(file_space);
          H5Sselect_none(memory_space);
        }
      const hid_t transfer =
        checked(H5Pcreate(H5P_DATASET_XFER), "transfer plist");
      check(H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE),
            "collective transfer");
      check(H5Dwrite(dataset,
                     memory_type,
                     memory_space,
                     file_space,
                     transfer,
                     data),
            "write " + name);
      H5Pclose(transfer);
      H5Sclose(memory_space);
      H5Sclose(file_space);
      H5Dclose(dataset);
    }

    /// /statistics/<name> of every value and the texts as attributes of
    /// /statistics (created if missing). Every rank of a parallel file calls
    /// it with the same arguments.
    void
    write_statistics_to(
      const hid_t                                             file,
      const std::vector<Column>                              &values,
      const std::vector<std::pair<std::string, std::string>> &texts)
    {
      const hid_t group =
        H5Lexists(file, "statistics", H5P_DEFAULT) > 0
          ? checked(H5Gopen2(file, "statistics", H5P_DEFAULT), "/statistics")
          : checked(H5Gcreate2(file,
                               "statistics",
                               H5P_DEFAULT,
                               H5P_DEFAULT,
                               H5P_DEFAULT),
                    "/statistics");
      for (const auto &v : values)
        {
          std::string name = v.name;
          std::replace(name.begin(), name.end(), '/', ':');
          const hid_t space   = checked(H5Screate(H5S_SCALAR), "scalar space");
          const hid_t dataset = create_dataset(group,
                                               name,
                                               H5T_NATIVE_DOUBLE,
                                               space,
                                               "/statistics/" + name);
          check(H5Dwrite(dataset,
                         H5T_NATIVE_DOUBLE,
                         H5S_ALL,
                         H5S_ALL,
                         H5P_DEFAULT,
                         &v.value),
                "/statistics/" + name);
          write_string_attribute(dataset, "unit", v.unit);
          H5Dclose(dataset);
          H5Sclose(space);
        }
      for (const auto &[name, text] : texts)
        write_string_attribute(group, name.c_str(), text);
      H5Gclose(group);
    }

    struct FieldStep
    {
      unsigned int step;
      double       time;
      std::vector<std::pair<std::string, unsigned int>>
        sets; // name, components
      /// The mesh group of the step (another one after a resume on another
      /// number of ranks: the nodes of the output patches differ) and its
      /// size.
      std::string mesh           = "mesh";
      hsize_t     n_global_nodes = 0, n_global_cells = 0;
      /// 8 (hexahedra) or 4 (tetrahedra, linear output patches).
      hsize_t nodes_per_cell = 8;
    };

    /// The XDMF topology of cells with @p nodes_per_cell nodes.
    const char *
    xdmf_topology(const hsize_t nodes_per_cell)
    {
      return nodes_per_cell == 4 ? "Tetrahedron" : "Hexahedron";
    }
  } // namespace

  namespace
  {
    bool any_write_failed = false;
  } // namespace

  bool
  a_results_write_failed()
  {
    return any_write_failed;
  }

  namespace
  {
    /// Where this rank's part of a field output goes in the global node
    /// and cell arrays.
    struct FieldLayout
    {
      hsize_t n_local_nodes, n_local_cells;
      hsize_t node_offset = 0, cell_offset = 0;
      hsize_t n_global_nodes, n_global_cells;
    };

    FieldLayout
    field_layout(const dealii::DataOutBase::DataOutFilter &filter,
                 const MPI_Comm                            comm,
                 const bool                                root)
    {
      FieldLayout l;
      l.n_local_nodes = filter.n_nodes();
      l.n_local_cells = filter.n_cells();
      MPI_Exscan(&l.n_local_nodes,
                 &l.node_offset,
                 1,
                 MPI_UNSIGNED_LONG_LONG,
                 MPI_SUM,
                 comm);
      MPI_Exscan(&l.n_local_cells,
                 &l.cell_offset,
                 1,
                 MPI_UNSIGNED_LONG_LONG,
                 MPI_SUM,
                 comm);
      if (root)
        l.node_offset = l.cell_offset = 0;
      l.n_global_nodes = dealii::Utilities::MPI::sum(l.n_local_nodes, comm);
      l.n_global_cells = dealii::Utilities::MPI::sum(l.n_local_cells, comm);
      return l;
    }
  } // namespace

  struct ResultsFile::Impl
  {
    /// The file @p directory/results.h5, written on @p comm.
    Impl(const std::string &directory, const MPI_Comm comm)
      : comm(comm)
      , root(dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      , directory(directory)
      , file_path(directory + "/results.h5")
    {}

    MPI_Comm               comm;
    bool                   root;
    std::string            directory;
    std::string            file_path;
    hid_t                  file = -1;
    Table                  timeseries{"timeseries", -1, {}, {}, 0};
    Table                  summary{"summary", -1, {}, {}, 0};
    Table                  events{"events", -1, {}, {}, 0};
    hsize_t                n_global_nodes = 0, n_global_cells = 0;
    hsize_t                nodes_per_cell = 8;
    std::string            mesh_group = "mesh"; ///< of the next field output
    std::vector<FieldStep> field_steps;

    /// A write failed: nothing more is written.
    bool failed = false;
    /// An HDF5 write failed: the file is not closed (closing would write
    /// more of the failed operation; the rows of the last successful flush
    /// stay as they are), see a_results_write_failed().
    bool abandoned = false;

    void
    flush()
    {
      check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flush");
    }

    /// Appends @p row to @p table and flushes (guarded).
    void
    append(Table &table, const std::vector<Column> &row)
    {
      guarded([&]() {
        table.append(file, row, root);
        flush();
      });
    }

    /// Run @p write (one public write operation, ending in a flush) and
    /// agree on its success: a failure seen by one rank (rank 0 writes the
    /// HDF5 metadata) stops every rank with the same message, which names
    /// the file, what failed, why, and the fix. Before it, every rank
    /// agrees that the file is there and, on more than one rank, that it
    /// can grow by @p growth bytes: parallel HDF5 does not survive a write
    /// that fails on one rank only (the others wait at a barrier in it).
    template <class Write>
    void
    guarded(const Write &write, const std::uintmax_t growth = 1 << 20)
    {
      AssertThrow(!failed,
                  dealii::ExcMessage("The results file '" + file_path +
                                     "' is not written any more: a write "
                                     "failed before."));
      agree(attempt([&]() {
        // A file removed (or moved) during the run would take every later
        // row with it into an unlinked inode: stop instead.
        if (root && !std::filesystem::exists(file_path))
          throw WriteFailure(removed);
        if (root && dealii::Utilities::MPI::n_mpi_processes(comm) > 1 &&
            !can_grow(file_path, growth))
          throw WriteFailure("no room for " + std::to_string(growth >> 10) +
                             " KiB more");
      }));
      agree(attempt(write));
    }

    static inline const std::string removed = "removed during the run";

    /// Run @p f; its error in one line ("" if none).
    template <class F>
    static std::string
    attempt(const F &f)
    {
      errno = 0;
      try
        {
          f();
        }
      catch (const std::exception &e)
        {
          const std::string error = one_line_message(e);
          return error.empty() ? "unknown error" : error;
        }
      return "";
    }

    /// Every rank learns the first rank's @p error and stops with it (a
    /// collective no-op when no rank has one).
    void
    agree(std::string error)
    {
      const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
      const unsigned int first = dealii::Utilities::MPI::min(
        error.empty() ? dealii::Utilities::MPI::n_mpi_processes(comm) : rank,
        comm);
      if (first == dealii::Utilities::MPI::n_mpi_processes(comm))
        return;
      failed = true;
      error  = dealii::Utilities::MPI::broadcast(comm, error, first);
      // (A removed file is still open and healthy: it is closed as usual.)
      abandoned        = error.rfind(removed, 0) != 0;
      any_write_failed = any_write_failed || abandoned;
      AssertThrow(abandoned,
                  dealii::ExcMessage("The results file '" + file_path +
                                     "' was removed during the run: the run "
                                     "stops (the rows it held are lost). "
                                     "Leave a running run's files in place."));
      AssertThrow(false,
                  dealii::ExcMessage(
                    "Writing the results file '" + file_path + "' failed (" +
                    error +
                    "); the rows written before are kept. Free disk space "
                    "(or raise the quota or file size limit) or choose "
                    "another Output / Directory, and run again (a heartbeat "
                    "with checkpoints: systole --resume " +
                    directory + ")."));
    }

    /// The mesh group of a field output (/mesh, or /mesh_step_NNNNNN when
    /// the patches changed) with this rank's nodes and cells.
    void
    write_mesh(const dealii::DataOutBase::DataOutFilter &filter,
               const FieldLayout                        &layout,
               const unsigned int                        step);

    /// The fields of one step, /fields/step_NNNNNN; returns its record.
    FieldStep
    write_field_step(const dealii::DataOutBase::DataOutFilter &filter,
                     const FieldLayout                        &layout,
                     const unsigned int                        step,
                     const double                              time);

    void
    write_xdmf() const
    {
      if (!root)
        return;
      std::ostringstream x;
      const std::string  h5 = "results.h5";
      x << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
        << "<Xdmf Version=\"2.0\">\n  <Domain>\n"
        << "    <Grid Name=\"fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
      for (const FieldStep &s : field_steps)
        {
          char group[32];
          std::snprintf(group, sizeof(group), "step_%06u", s.step);
          x << "      <Grid Name=\"" << group << "\" GridType=\"Uniform\">\n"
            << "        <Time Value=\"" << std::setprecision(16) << s.time
            << "\"/>\n"
            << "        <Geometry GeometryType=\"XYZ\">\n"
            << "          <DataItem Dimensions=\"" << s.n_global_nodes
            << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
            << ":/" << s.mesh << "/nodes</DataItem>\n        </Geometry>\n"
            << "        <Topology TopologyType=\""
            << xdmf_topology(s.nodes_per_cell) << "\" NumberOfElements=\""
            << s.n_global_cells << "\">\n          <DataItem Dimensions=\""
            << s.n_global_cells << " " << s.nodes_per_cell
            << "\" NumberType=\"UInt\" Precision=\"4\" Format=\"HDF\">" << h5
            << ":/" << s.mesh << "/cells</DataItem>\n        </Topology>\n";
          for (const auto &[name, components] : s.sets)
            x << "        <Attribute Name=\"" << name << "\" AttributeType=\""
              << (components == 1 ? "Scalar" : "Vector")
              << "\" Center=\"Node\">\n"
              << "          <DataItem Dimensions=\"" << s.n_global_nodes << " "
              << components
              << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
              << ":/fields/" << group << "/" << name << "</DataItem>\n"
              << "        </Attribute>\n";
          x << "      </Grid>\n";
        }
      x << "    </Grid>\n  </Domain>\n</Xdmf>\n";

      // Write a new file and rename it over the old one: never a half-written
      // XDMF.
      const std::string final_path = directory + "/fields.xdmf";
      const std::string tmp_path   = final_path + ".tmp";
      {
        std::ofstream out(tmp_path);
        out << x.str();
        AssertThrow(out.good(),
                    dealii::ExcMessage("Cannot write " + tmp_path + "."));
      }
      std::filesystem::rename(tmp_path, final_path);
    }
  };

  ResultsFile::ResultsFile(const std::string &directory,
                           const std::string &parameter_text,
                           const MPI_Comm     comm)
    : impl(std::make_unique<Impl>(directory, comm))
  {
    // Create the folder on rank 0, then agree on success before anyone opens
    // the file.
    int         ok = 1;
    std::string error;
    if (impl->root)
      {
        std::error_code ec;
        std::filesystem::create_directories(directory, ec);
        if (ec || !std::filesystem::is_directory(directory))
          {
            ok    = 0;
            error = ec.message();
          }
      }
    ok = dealii::Utilities::MPI::min(ok, comm);
    AssertThrow(ok == 1,
                dealii::ExcMessage("Cannot create the output folder '" +
                                   directory + "'" +
                                   (error.empty() ? "" : ": " + error) +
                                   ". Check Output / Directory."));

    // Errors are reported through our exceptions, not HDF5's own stack dump.
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    const hid_t access =
      checked(H5Pcreate(H5P_FILE_ACCESS), "file access plist");
    check(H5Pset_fapl_mpio(access, comm, MPI_INFO_NULL), "MPI-IO driver");
    impl->file =
      H5Fcreate(impl->file_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access);
    H5Pclose(access);
    AssertThrow(impl->file >= 0,
                dealii::ExcMessage("Cannot create the results file '" +
                                   impl->file_path +
                                   "'. Is it open in another program?"));

    // /parameters: the full text, as a scalar fixed-length string (parallel
    // HDF5 cannot write variable-length strings). A failure here removes the
    // file: no half-made results file.
    try
      {
        const hid_t type = checked(H5Tcopy(H5T_C_S1), "string type");
        check(H5Tset_size(type,
                          std::max<std::size_t>(parameter_text.size(), 1)),
              "string size");
        check(H5Tset_cset(type, H5T_CSET_UTF8), "utf8");
        const hid_t space = checked(H5Screate(H5S_SCALAR), "space");
        const hid_t dataset =
          create_dataset(impl->file, "parameters", type, space, "/parameters");
        const std::string padded =
          parameter_text.empty() ? std::string(" ") : parameter_text;
        check(
          H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()),
          "/parameters");
        write_string_attribute(dataset, "code_version", code_version());
        write_scalar_attribute(
          dataset,
          "n_ranks",
          H5T_NATIVE_INT,
          static_cast<int>(dealii::Utilities::MPI::n_mpi_processes(comm)));
        H5Dclose(dataset);
        H5Sclose(space);
        H5Tclose(type);
        impl->flush();
      }
    catch (const std::exception &e)
      {
        H5Fclose(impl->file);
        impl->file = -1;
        MPI_Barrier(comm);
        if (impl->root)
          std::filesystem::remove(impl->file_path);
        AssertThrow(false,
                    dealii::ExcMessage(
                      "Writing the results file '" + impl->file_path +
                      "' failed (" + one_line_message(e) +
                      "). Free disk space (or raise the quota or file size "
                      "limit) or choose another Output / Directory."));
      }
  }

  namespace
  {
    /// The names of the links of @p group in creation order.
    std::vector<std::string>
    link_names(const hid_t group)
    {
      std::vector<std::string> names;
      const auto               collect =
        [](hid_t, const char *name, const H5L_info_t *, void *data) -> herr_t {
        static_cast<std::vector<std::string> *>(data)->push_back(name);
        return 0;
      };
      hsize_t index = 0;
      if (H5Literate(group,
                     H5_INDEX_CRT_ORDER,
                     H5_ITER_INC,
                     &index,
                     collect,
                     &names) < 0)
        {
          // Groups without creation order (the fields): by name.
          names.clear();
          index = 0;
          check(H5Literate(group,
                           H5_INDEX_NAME,
                           H5_ITER_INC,
                           &index,
                           collect,
                           &names),
                "list a group");
        }
      return names;
    }

    /// Reopen @p table in @p file and cut it to @p n_rows rows.
    void
    reopen(Table &table, const hid_t file, const hsize_t n_rows)
    {
      if (H5Lexists(file, table.group_name.c_str(), H5P_DEFAULT) <= 0)
        {
          AssertThrow(n_rows == 0,
                      dealii::ExcMessage("The results file has no /" +
                                         table.group_name +
                                         ", which the checkpoint expects."));
          return;
        }
      table.group =
        checked(H5Gopen2(file, table.group_name.c_str(), H5P_DEFAULT),
                "open /" + table.group_name);
      for (const auto &name : link_names(table.group))
        {
          const hid_t dataset =
            checked(H5Dopen2(table.group, name.c_str(), H5P_DEFAULT),
                    "open /" + table.group_name + "/" + name);
          const hid_t space = checked(H5Dget_space(dataset), "space");
          hsize_t     size  = 0;
          H5Sget_simple_extent_dims(space, &size, nullptr);
          H5Sclose(space);
          AssertThrow(size >= n_rows,
                      dealii::ExcMessage(
                        "The results file has " + std::to_string(size) +
                        " rows in /" + table.group_name + "/" + name +
                        ", fewer than the " + std::to_string(n_rows) +
                        " of the checkpoint: it is not the file the "
                        "checkpoint belongs to."));
          check(H5Dset_extent(dataset, &n_rows), "cut " + name);
          table.names.push_back(name);
          table.datasets.push_back(dataset);
        }
      table.n_rows = n_rows;
    }
  } // namespace


  ResultsFile::ResultsFile(const std::string &directory,
                           const Rows        &rows,
                           const unsigned int last_step,
                           const MPI_Comm     comm)
    : impl(std::make_unique<Impl>(directory, comm))
  {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    const hid_t access =
      checked(H5Pcreate(H5P_FILE_ACCESS), "file access plist");
    check(H5Pset_fapl_mpio(access, comm, MPI_INFO_NULL), "MPI-IO driver");
    impl->file = H5Fopen(impl->file_path.c_str(), H5F_ACC_RDWR, access);
    H5Pclose(access);
    AssertThrow(impl->file >= 0,
                dealii::ExcMessage("Cannot open the results file '" +
                                   impl->file_path + "' to continue the run."));
    reopen(impl->timeseries, impl->file, rows.timeseries);
    reopen(impl->summary, impl->file, rows.summary);
    reopen(impl->events, impl->file, rows.events);

    // The field outputs up to the checkpoint; later ones go.
    // The rows of a 2-D dataset.
    const auto n_rows_of = [&](const std::string &path) {
      const hid_t dataset =
        checked(H5Dopen2(impl->file, path.c_str(), H5P_DEFAULT), path);
      hsize_t     dims[2] = {0, 0};
      const hid_t space   = H5Dget_space(dataset);
      H5Sget_simple_extent_dims(space, dims, nullptr);
      H5Sclose(space);
      H5Dclose(dataset);
      return std::array<hsize_t, 2>{{dims[0], dims[1]}};
    };
    if (H5Lexists(impl->file, "fields", H5P_DEFAULT) > 0)
      {
        hsize_t dims[2] = {0, 0};

        const hid_t fields =
          checked(H5Gopen2(impl->file, "fields", H5P_DEFAULT), "/fields");
        for (const auto &name : link_names(fields))
          {
            const hid_t group =
              checked(H5Gopen2(fields, name.c_str(), H5P_DEFAULT), name);
            FieldStep   record{0, 0.0, {}};
            const hid_t step = H5Aopen(group, "step", H5P_DEFAULT);
            H5Aread(step, H5T_NATIVE_UINT, &record.step);
            H5Aclose(step);
            const hid_t time = H5Aopen(group, "time", H5P_DEFAULT);
            H5Aread(time, H5T_NATIVE_DOUBLE, &record.time);
            H5Aclose(time);
            if (H5Aexists(group, "mesh") > 0)
              {
                const hid_t mesh = H5Aopen(group, "mesh", H5P_DEFAULT);
                const hid_t type = H5Aget_type(mesh);
                std::string value(H5Tget_size(type), '\0');
                H5Aread(mesh, type, value.data());
                H5Tclose(type);
                H5Aclose(mesh);
                record.mesh = value.c_str();
              }
            record.n_global_nodes = n_rows_of(record.mesh + "/nodes")[0];
            const auto cells      = n_rows_of(record.mesh + "/cells");
            record.n_global_cells = cells[0];
            record.nodes_per_cell = cells[1];
            if (record.step <= last_step)
              for (const auto &set : link_names(group))
                {
                  const hid_t dataset =
                    checked(H5Dopen2(group, set.c_str(), H5P_DEFAULT), set);
                  const hid_t set_space = H5Dget_space(dataset);
                  H5Sget_simple_extent_dims(set_space, dims, nullptr);
                  H5Sclose(set_space);
                  H5Dclose(dataset);
                  record.sets.emplace_back(set,
                                           static_cast<unsigned int>(dims[1]));
                }
            H5Gclose(group);
            if (record.step <= last_step)
              impl->field_steps.push_back(record);
            else
              check(H5Ldelete(fields, name.c_str(), H5P_DEFAULT),
                    "remove /fields/" + name);
          }
        H5Gclose(fields);
        // The statistics of the earlier run (the resumed run writes its
        // own at its end).
        if (H5Lexists(impl->file, "statistics", H5P_DEFAULT) > 0)
          check(H5Ldelete(impl->file, "statistics", H5P_DEFAULT),
                "remove /statistics");
        // Meshes of removed steps.
        for (const auto &name : link_names(impl->file))
          if (name.rfind("mesh_step_", 0) == 0 &&
              std::stoul(name.substr(10)) > last_step)
            check(H5Ldelete(impl->file, name.c_str(), H5P_DEFAULT),
                  "remove /" + name);
        std::sort(impl->field_steps.begin(),
                  impl->field_steps.end(),
                  [](const FieldStep &a, const FieldStep &b) {
                    return a.step < b.step;
                  });
        if (!impl->field_steps.empty())
          {
            impl->mesh_group     = impl->field_steps.back().mesh;
            impl->n_global_nodes = impl->field_steps.back().n_global_nodes;
            impl->n_global_cells = impl->field_steps.back().n_global_cells;
            impl->nodes_per_cell = impl->field_steps.back().nodes_per_cell;
          }
        impl->write_xdmf();
      }
    impl->flush();
  }


  ResultsFile::Rows
  ResultsFile::rows() const
  {
    return {impl->timeseries.n_rows, impl->summary.n_rows, impl->events.n_rows};
  }


  ResultsFile::~ResultsFile()
  {
    // After a failed write the file stays open (see a_results_write_failed()).
    if (impl->abandoned)
      return;
    impl->timeseries.close();
    impl->summary.close();
    impl->events.close();
    if (impl->file >= 0)
      H5Fclose(impl->file);
  }

  const std::string &
  ResultsFile::path() const
  {
    return impl->file_path;
  }

  void
  ResultsFile::append_timeseries(const std::vector<Column> &row)
  {
    impl->append(impl->timeseries, row);
  }

  void
  ResultsFile::append_event(const std::vector<Column> &row)
  {
    impl->append(impl->events, row);
  }

  void
  ResultsFile::append_summary(const std::vector<Column> &row)
  {
    impl->append(impl->summary, row);
  }

  void
  ResultsFile::write_statistics(
    const std::vector<Column>                              &values,
    const std::vector<std::pair<std::string, std::string>> &texts)
  {
    impl->guarded([&]() {
      write_statistics_to(impl->file, values, texts);
      impl->flush();
    });
  }

  void
  ResultsFile::write_table(const std::string              &path,
                           const std::vector<TableColumn> &columns)
  {
    impl->guarded([&]() { write_table_now(path, columns); });
  }

  void
  ResultsFile::write_table_now(const std::string              &path,
                               const std::vector<TableColumn> &columns)
  {
    // Open or create every group on the path (creation order tracked, so
    // readers list the columns in the order written). Collective: every rank
    // makes the same calls and writes the same values.
    std::vector<hid_t> groups = {impl->file};
    std::string        so_far;
    for (const auto &part : dealii::Utilities::split_string_list(path, '/'))
      {
        if (part.empty())
          continue;
        so_far += "/" + part;
        const hid_t parent = groups.back();
        if (H5Lexists(parent, part.c_str(), H5P_DEFAULT) > 0)
          groups.push_back(checked(H5Gopen2(parent, part.c_str(), H5P_DEFAULT),
                                   "group " + so_far));
        else
          groups.push_back(
            create_ordered_group(parent, part, "group " + so_far));
      }
    const hid_t group = groups.back();
    for (const auto &column : columns)
      {
        const bool    is_text = !column.text.empty();
        const hsize_t n = is_text ? column.text.size() : column.values.size();
        const hid_t   space =
          checked(H5Screate_simple(1, &n, nullptr), "space " + column.name);
        hid_t       type = H5T_NATIVE_DOUBLE;
        std::string buffer;
        if (is_text)
          {
            std::size_t width = 1;
            for (const auto &s : column.text)
              width = std::max(width, s.size());
            type = checked(H5Tcopy(H5T_C_S1), "string type");
            check(H5Tset_size(type, width), "string size");
            check(H5Tset_strpad(type, H5T_STR_NULLPAD), "string padding");
            check(H5Tset_cset(type, H5T_CSET_UTF8), "utf8");
            buffer.assign(width * n, '\0');
            for (hsize_t i = 0; i < n; ++i)
              buffer.replace(i * width, column.text[i].size(), column.text[i]);
          }
        const hid_t dataset = create_dataset(group,
                                             column.name,
                                             type,
                                             space,
                                             so_far + "/" + column.name);
        if (n > 0)
          check(H5Dwrite(dataset,
                         type,
                         H5S_ALL,
                         H5S_ALL,
                         H5P_DEFAULT,
                         is_text ? static_cast<const void *>(buffer.data())
                                 : column.values.data()),
                so_far + "/" + column.name);
        if (!is_text)
          write_string_attribute(dataset, "unit", column.unit);
        H5Dclose(dataset);
        if (is_text)
          H5Tclose(type);
        H5Sclose(space);
      }
    for (std::size_t g = groups.size() - 1; g > 0; --g)
      H5Gclose(groups[g]);
    impl->flush();
  }

  void
  add_statistics(const std::string         &path,
                 const std::vector<Column> &values,
                 const MPI_Comm             comm)
  {
    int ok = 1;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0 &&
        std::filesystem::is_regular_file(path))
      {
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
        const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
        ok               = file >= 0;
        if (ok)
          {
            write_statistics_to(file, values, {});
            H5Fclose(file);
          }
      }
    ok = dealii::Utilities::MPI::min(ok, comm);
    AssertThrow(ok == 1,
                dealii::ExcMessage("Cannot reopen the results file '" + path +
                                   "' to add the run's statistics."));
  }

  void
  ResultsFile::Impl::write_mesh(
    const dealii::DataOutBase::DataOutFilter &filter,
    const FieldLayout                        &layout,
    const unsigned int                        step)
  {
    const bool first_mesh = H5Lexists(file, "mesh", H5P_DEFAULT) <= 0;
    char       step_mesh_name[32];
    std::snprintf(step_mesh_name,
                  sizeof(step_mesh_name),
                  "mesh_step_%06u",
                  step);
    mesh_group = first_mesh ? "mesh" : step_mesh_name;
    std::vector<double> nodes;
    filter.fill_node_data(nodes);
    std::vector<unsigned int> cells;
    filter.fill_cell_data(layout.node_offset, cells);
    // Hexahedra (8 nodes) or linear tetrahedra (4): the same on every
    // rank (a rank without cells has none to say).
    nodes_per_cell =
      dealii::Utilities::MPI::max(layout.n_local_cells > 0
                                    ? cells.size() / layout.n_local_cells
                                    : 0,
                                  comm);
    AssertThrow(nodes_per_cell == 8 || nodes_per_cell == 4,
                dealii::ExcMessage(
                  "Field output: cells of " + std::to_string(nodes_per_cell) +
                  " nodes (the results file takes hexahedra and linear "
                  "tetrahedra)."));
    const hid_t group = checked(H5Gcreate2(file,
                                           mesh_group.c_str(),
                                           H5P_DEFAULT,
                                           H5P_DEFAULT,
                                           H5P_DEFAULT),
                                "/" + mesh_group);
    write_distributed(group,
                      "nodes",
                      H5T_NATIVE_DOUBLE,
                      H5T_IEEE_F64LE,
                      nodes.data(),
                      layout.n_local_nodes,
                      layout.node_offset,
                      layout.n_global_nodes,
                      3);
    write_distributed(group,
                      "cells",
                      H5T_NATIVE_UINT,
                      H5T_STD_U32LE,
                      cells.data(),
                      layout.n_local_cells,
                      layout.cell_offset,
                      layout.n_global_cells,
                      nodes_per_cell);
    H5Gclose(group);
    n_global_nodes = layout.n_global_nodes;
    n_global_cells = layout.n_global_cells;
  }

  FieldStep
  ResultsFile::Impl::write_field_step(
    const dealii::DataOutBase::DataOutFilter &filter,
    const FieldLayout                        &layout,
    const unsigned int                        step,
    const double                              time)
  {
    hid_t fields = -1;
    if (H5Lexists(file, "fields", H5P_DEFAULT) <= 0)
      fields = checked(
        H5Gcreate2(file, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
        "/fields");
    else
      fields = checked(H5Gopen2(file, "fields", H5P_DEFAULT), "/fields");
    char name[32];
    std::snprintf(name, sizeof(name), "step_%06u", step);
    const hid_t group =
      checked(H5Gcreate2(fields, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              std::string("/fields/") + name +
                " (a field step written twice?)");
    write_scalar_attribute(group, "time", H5T_NATIVE_DOUBLE, time);
    write_scalar_attribute(group, "step", H5T_NATIVE_UINT, step);
    write_string_attribute(group, "mesh", mesh_group);

    FieldStep record{step,
                     time,
                     {},
                     mesh_group,
                     n_global_nodes,
                     n_global_cells,
                     nodes_per_cell};
    for (unsigned int i = 0; i < filter.n_data_sets(); ++i)
      {
        const std::string  set_name   = filter.get_data_set_name(i);
        const unsigned int components = filter.get_data_set_dim(i);
        write_distributed(group,
                          set_name,
                          H5T_NATIVE_DOUBLE,
                          H5T_IEEE_F64LE,
                          filter.get_data_set(i),
                          layout.n_local_nodes,
                          layout.node_offset,
                          layout.n_global_nodes,
                          components);
        record.sets.emplace_back(set_name, components);
      }
    H5Gclose(group);
    H5Gclose(fields);
    return record;
  }

  void
  ResultsFile::write_fields(const dealii::DataOut<3, 3> &data_out,
                            const unsigned int           step,
                            const double                 time)
  {
    dealii::DataOutBase::DataOutFilter filter(
      dealii::DataOutBase::DataOutFilterFlags(
        /*filter_duplicate_vertices=*/true,
        /*xdmf_hdf5_output=*/true));
    data_out.write_filtered_data(filter);
    const FieldLayout layout = field_layout(filter, impl->comm, impl->root);

    // What the step adds at most: a mesh (coordinates, cells) and every
    // field's values at every node, in doubles, and the metadata.
    std::uintmax_t values = 3;
    for (unsigned int i = 0; i < filter.n_data_sets(); ++i)
      values += filter.get_data_set_dim(i);
    const std::uintmax_t growth =
      8 * (values * layout.n_global_nodes + 8 * layout.n_global_cells) +
      (1 << 20);
    impl->guarded(
      [&]() {
        // The first output, or the first after a resume on another number of
        // ranks (other patches): a mesh group of its own.
        if (H5Lexists(impl->file, "mesh", H5P_DEFAULT) <= 0 ||
            layout.n_global_nodes != impl->n_global_nodes ||
            layout.n_global_cells != impl->n_global_cells)
          impl->write_mesh(filter, layout, step);
        const FieldStep record =
          impl->write_field_step(filter, layout, step, time);
        impl->flush();
        impl->field_steps.push_back(record);
        impl->write_xdmf();
      },
      growth);
  }
} // namespace systole::IO
