#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/numerics/data_out.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace systole::IO
{
  /// One value of a time-series row: column name, unit, value.
  struct Column
  {
    std::string name;
    std::string unit;
    double      value;
  };

  /// One column of a small table written at once (ResultsFile::write_table()):
  /// numbers (float64, with a unit) or, when @p text is not empty, strings.
  struct TableColumn
  {
    std::string              name;
    std::string              unit;
    std::vector<double>      values;
    std::vector<std::string> text;
  };

  /// The results file of a run, `<directory>/results.h5` (HDF5, written
  /// collectively by all ranks through MPI-IO), with an XDMF companion
  /// `fields.xdmf` that ParaView opens:
  /// - `/parameters`: the full parameter text (attributes `code_version`,
  /// `n_ranks`);
  /// - `/timeseries/<column>`: one float64 entry per completed step (attribute
  /// `unit`);
  /// - `/summary/<column>`: one row per beat (written by later components);
  /// - `/events/<column>`: one row per discrete event (valve events);
  /// - `/mesh/nodes`, `/mesh/cells`: reference mesh of the field output
  /// (hexahedra);
  /// - `/fields/step_NNNNNN/<name>`: nodal fields every k steps (group
  /// attributes time, step). The file is flushed after every row and every
  /// field output, so a run killed midway leaves a readable file with every
  /// completed step. All calls are collective; values passed in must be equal
  /// on all ranks (only rank 0's are written). A failed write (disk full, a
  /// file size limit, the file removed) throws on every rank one line naming
  /// the file, what failed and why, and the fix; the file is then left as
  /// its last flush wrote it (the earlier rows stay readable) and nothing
  /// more is written to it.
  class ResultsFile
  {
  public:
    /// Create (truncate) the file. Creates @p directory if needed.
    ResultsFile(const std::string &directory,
                const std::string &parameter_text,
                const MPI_Comm     comm);
    /// The number of rows of each table (a checkpoint records them).
    struct Rows
    {
      unsigned long timeseries = 0, summary = 0, events = 0;
    };

    /// Open the existing file in @p directory to continue a run from a
    /// checkpoint: every table is cut back to @p rows and the field outputs
    /// of steps after @p last_step are removed (they were written after the
    /// checkpoint), the XDMF file rewritten. Throws if the file has fewer
    /// rows than @p rows.
    ResultsFile(const std::string &directory,
                const Rows        &rows,
                const unsigned int last_step,
                const MPI_Comm     comm);

    ~ResultsFile();

    /// The rows written so far.
    Rows
    rows() const;

    ResultsFile(const ResultsFile &) = delete;
    ResultsFile &
    operator=(const ResultsFile &) = delete;

    /// Append one row to /timeseries. The first row fixes the columns and their
    /// order; later rows must carry the same columns in the same order.
    void
    append_timeseries(const std::vector<Column> &row);

    /// Append one row to /summary (same rules as the time series, separate
    /// columns).
    void
    append_summary(const std::vector<Column> &row);

    /// Append one row to /events (valve events and other discrete events of
    /// the run; same rules as the time series, separate columns).
    void
    append_event(const std::vector<Column> &row);

    /// Write the fields of @p data_out (patches already built) as
    /// /fields/step_NNNNNN and update the XDMF file. The first call also writes
    /// /mesh.
    void
    write_fields(const dealii::DataOut<3, 3> &data_out,
                 const unsigned int           step,
                 const double                 time);

    /// Write /statistics/<name> for every value (a float64 scalar with
    /// attribute unit) and one string attribute of /statistics per text: the
    /// cost of the run (timer sections, solver counts, sizes), which
    /// scripts/bench reads. A '/' in a name becomes ':'. Each name once.
    void
    write_statistics(
      const std::vector<Column>                              &values,
      const std::vector<std::pair<std::string, std::string>> &texts = {});

    /// Write the table /@p path/<column> once: every column a 1-D dataset of
    /// its rows, float64 with attribute unit, or fixed-length strings (for
    /// names); the groups of @p path (e.g. "calibration/parameters") are
    /// created as needed, the columns in creation order. For results written
    /// once at the end of a run (a calibration's parameters); the
    /// time-series, summary and event tables are not touched.
    void
    write_table(const std::string              &path,
                const std::vector<TableColumn> &columns);

    /// Path of the HDF5 file.
    const std::string &
    path() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;

    /// write_table() without the agreement on success.
    void
    write_table_now(const std::string              &path,
                    const std::vector<TableColumn> &columns);
  };

  /// Whether a write of a ResultsFile failed in this process. Its HDF5 file
  /// is then left open on purpose (closing would write more of the failed
  /// operation, and HDF5 1.10's MPI-IO driver crashes when it closes such a
  /// file, also at MPI_Finalize): the app ends the process without
  /// finalizing after reporting the error.
  bool
  a_results_write_failed();

  /// ResultsFile::write_statistics() on the closed results file @p path
  /// (rank 0 reopens it; nothing happens if it does not exist): what the app
  /// measures after the problem ran (wall time, peak memory). Collective.
  void
  add_statistics(const std::string         &path,
                 const std::vector<Column> &values,
                 const MPI_Comm             comm);

  /// The version string recorded in results files: "<semver> (<git describe>)".
  std::string
  code_version();
} // namespace systole::IO
