#include "simulation/run_checkpoint.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria_base.h>

#include "base/errors.h"
#include "base/logger.h"
#include "io/checkpoint.h"
#include "io/checkpoint_format.h"
#include "io/results_file.h"
#include "simulation/parameters.h"
#include "simulation/problem_type.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/serialization/vector.hpp>
#include <sys/resource.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <sstream>

namespace systole
{
  /// Resume: the newest valid checkpoint of the run, written for the same
  /// problem (every entry outside subsection Output equal to
  /// @p all_entries); "" when the run does not resume.
  std::string
  checkpoint_entries(const dealii::ParameterHandler &prm)
  {
    std::ostringstream entries;
    prm.print_parameters(entries, dealii::ParameterHandler::ShortPRM);
    return entries.str();
  }

  std::string
  resume_checkpoint(const RunParameters &run,
                    IO::CheckpointStore &store,
                    const std::string   &all_entries,
                    Logger              &logger,
                    const MPI_Comm       comm)
  {
    if (!run.resume)
      return "";
    std::ostringstream faults;
    const std::string  checkpoint = store.newest_valid(faults);
    std::istringstream fault_lines(faults.str());
    for (std::string line; std::getline(fault_lines, line);)
      logger.line(line);
    AssertThrow(!checkpoint.empty(),
                dealii::ExcMessage(
                  "Output / Resume: there is no valid checkpoint in '" +
                  run.output_directory +
                  "' (set Output / Checkpoint interval when starting "
                  "the run)."));
    IO::check_checkpoint_format(checkpoint, comm);
    std::ifstream      in(checkpoint + "/parameters.prm");
    std::ostringstream saved;
    saved << in.rdbuf();
    const auto differences =
      IO::parameter_differences(saved.str(), all_entries, {"Output"});
    if (!differences.empty())
      {
        std::string message =
          "The checkpoint " + checkpoint +
          " was written for another problem: " + differences[0];
        if (differences.size() > 1)
          message += " (and " + std::to_string(differences.size() - 1) +
                     " more difference(s))";
        AssertThrow(false,
                    dealii::ExcMessage(
                      message +
                      ". Only subsection Output may change when a run "
                      "resumes."));
      }
    logger.line("Resuming from " + checkpoint);
    return checkpoint;
  }


  std::unique_ptr<IO::ResultsFile>
  open_results(const std::string                &checkpoint,
               const RunInputs                  &in,
               std::unique_ptr<IO::StateReader> &state_in,
               unsigned int                     *resumed_step)
  {
    if (checkpoint.empty())
      return std::make_unique<IO::ResultsFile>(in.run.output_directory,
                                               in.parameter_text,
                                               in.comm);
    state_in =
      std::make_unique<IO::StateReader>(IO::read_checkpoint_state(checkpoint,
                                                                  in.comm),
                                        checkpoint);
    IO::ResultsFile::Rows                  rows;
    unsigned int                           step = 0;
    state_in->archive() & rows.timeseries &rows.summary &rows.events &step;
    if (resumed_step != nullptr)
      *resumed_step = step;
    return std::make_unique<IO::ResultsFile>(in.run.output_directory,
                                             rows,
                                             step,
                                             in.comm);
  }


  bool
  checkpoint_due(const RunParameters                         &run,
                 const unsigned int                           step,
                 const std::chrono::steady_clock::time_point &last,
                 const MPI_Comm                               comm)
  {
    if (run.checkpoint_interval > 0 && step % run.checkpoint_interval == 0)
      return true;
    if (run.checkpoint_minutes <= 0)
      return false;
    const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last)
        .count() /
      60.0;
    return dealii::Utilities::MPI::max(minutes, comm) >= run.checkpoint_minutes;
  }


  RunCheckpointer::RunCheckpointer(const RunCheckpointerParts &parts)
    : RunCheckpointerParts(parts)
  {}


  std::vector<std::string>
  RunCheckpointer::list() const
  {
    return store.list();
  }


  const std::string &
  RunCheckpointer::output_directory() const
  {
    return run.output_directory;
  }


  void
  RunCheckpointer::write(const unsigned int           step,
                         const SaveState             &save,
                         const std::function<void()> &after_mesh)
  {
    const auto        begin  = std::chrono::steady_clock::now();
    const std::string folder = store.begin(step);
    IO::StateWriter   writer;
    {
      auto      &archive = writer.archive();
      const auto rows    = results.rows();
      archive &rows.timeseries &rows.summary &rows.events &step;
      save(archive, folder);
    }
    // Test hook (Output / Test file size limit in checkpoint): from here on,
    // writes that grow a file beyond 1 kB fail as on a full disk.
    if (run.test_file_size_limit_in_checkpoint == static_cast<long>(step))
      {
        std::signal(SIGXFSZ, SIG_IGN);
        const rlimit limit{1024, 1024};
        setrlimit(RLIMIT_FSIZE, &limit);
      }
    // The small state first: the largest file, whose failure (a full disk)
    // is reported here, before the mesh's save (p4est aborts on a failed
    // write).
    const std::string text = writer.finish();
    std::string       error;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      error = write_files(folder, text, step);
    stop_if_failed(error, 0, step);
    // The mesh with its data (MPI-IO): a rank whose write failed tells the
    // others, which would otherwise wait for it in the commit.
    error.clear();
    try
      {
        tria.save(folder + mesh_file);
      }
    catch (const std::exception &e)
      {
        error = one_line_message(e);
      }
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    stop_if_failed(error,
                   dealii::Utilities::MPI::min(
                     error.empty()
                       ? n_ranks
                       : dealii::Utilities::MPI::this_mpi_process(comm),
                     comm),
                   step);
    if (after_mesh)
      after_mesh();
    const std::string path = store.commit();
    seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin)
        .count();
    ++count;
    logger.detail() << "  checkpoint " << path << std::endl;
  }


  void
  RunCheckpointer::stop_if_failed(const std::string &error,
                                  const unsigned int failed_rank,
                                  const unsigned int step) const
  {
    if (failed_rank >= dealii::Utilities::MPI::n_mpi_processes(comm))
      return;
    const std::string message =
      dealii::Utilities::MPI::broadcast(comm, error, failed_rank);
    if (message.empty())
      return;
    const auto        previous = store.list();
    const std::string previous_note =
      previous.empty() ? std::string("none was written before")
                       : "the last one, " + previous.front() + ", is intact";
    AssertThrow(false,
                dealii::ExcMessage(
                  "Writing the checkpoint of step " + std::to_string(step) +
                  " failed (" + message + "); " + previous_note +
                  ". Free disk space (or raise the quota or file size limit), "
                  "then continue with systole --resume " +
                  run.output_directory + "."));
  }


  std::string
  RunCheckpointer::write_files(const std::string &folder,
                               const std::string &data,
                               const unsigned int step) const
  {
    const auto write = [](const std::string &file,
                          const std::string &text,
                          const std::size_t  n) -> std::string {
      errno = 0;
      std::ofstream out(file, std::ios::binary);
      out.write(text.data(), n);
      out.close();
      if (out.fail())
        return file + ": " +
               (errno != 0 ? std::strerror(errno) : "write error");
      return "";
    };
    // Test hook (Output / Test kill in checkpoint): die by SIGKILL halfway
    // through the state of the checkpoint of this step.
    if (run.test_kill_in_checkpoint == static_cast<long>(step))
      {
        std::ofstream state_file(folder + IO::checkpoint_state_file,
                                 std::ios::binary);
        state_file.write(data.data(), data.size() / 2);
        state_file.flush();
        std::raise(SIGKILL);
      }
    std::string error =
      write(folder + IO::checkpoint_state_file, data, data.size());
    if (error.empty())
      error = write(folder + "parameters.prm", all_entries, all_entries.size());
    if (error.empty())
      error = write(folder + "parameter_file",
                    run.parameter_file,
                    run.parameter_file.size());
    return error;
  }
} // namespace systole
