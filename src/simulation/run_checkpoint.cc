#include "simulation/run_checkpoint.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include "base/logger.h"
#include "io/checkpoint.h"
#include "io/checkpoint_format.h"
#include "simulation/parameters.h"

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


  void
  write_checkpoint_files(const std::string   &folder,
                         const std::string   &state,
                         const std::string   &all_entries,
                         const RunParameters &run)
  {
    std::ofstream state_file(folder + "/" + IO::checkpoint_state_file,
                             std::ios::binary);
    state_file << state;
    std::ofstream(folder + "/parameters.prm") << all_entries;
    std::ofstream(folder + "/parameter_file") << run.parameter_file;
    AssertThrow(state_file.good(),
                dealii::ExcMessage("Cannot write " + folder + "/" +
                                   IO::checkpoint_state_file + "."));
  }
} // namespace systole
