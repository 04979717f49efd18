#include "simulation/simulation.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include "base/interrupt.h"
#include "base/logger.h"
#include "io/checkpoint.h"
#include "io/results_file.h"
#include "simulation/parameters.h"
#include "simulation/problem_type.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace systole
{
  struct Simulation::Impl
  {
    Impl(const MPI_Comm comm, std::ostream &out)
      : comm(comm)
      , logger(comm, out)
    {}

    MPI_Comm                 comm;
    Logger                   logger;
    dealii::ParameterHandler prm;
    std::string              text;
    RunParameters            run;
  };

  Simulation::Simulation(const std::string &parameter_file,
                         const MPI_Comm     comm,
                         std::ostream      &out,
                         const std::string &resume_directory)
    : impl(std::make_unique<Impl>(comm, out))
  {
    read_parameter_file(impl->prm, parameter_file);
    impl->run = RunParameters::parse(impl->prm, parameter_file);
    if (!resume_directory.empty())
      {
        impl->run.resume = true;
        impl->run.output_directory =
          std::filesystem::path(resume_directory).lexically_normal().string();
        while (impl->run.output_directory.size() > 1 &&
               impl->run.output_directory.back() == '/')
          impl->run.output_directory.pop_back();
      }
    AssertThrow(!impl->run.resume || impl->run.problem == "heartbeat" ||
                  impl->run.problem == "electrophysiology" ||
                  impl->run.problem == "elastodynamics",
                dealii::ExcMessage(
                  "Output / Resume: only Problem = heartbeat, "
                  "electrophysiology and elastodynamics write checkpoints "
                  "(Problem = " +
                  impl->run.problem + ")."));
    validate_component_parameters(impl->prm, parameter_file);

    // What ran: the file as given, then every entry with the value used.
    std::ifstream      in(parameter_file);
    std::ostringstream text;
    text << "# Parameter file '" << parameter_file << "' as given:\n"
         << in.rdbuf() << "\n# All entries with the values used:\n";
    impl->prm.print_parameters(text, dealii::ParameterHandler::ShortPRM);
    impl->text = text.str();
  }

  Simulation::~Simulation() = default;

  std::string
  Simulation::parameter_file_of(const std::string &run_directory)
  {
    for (const auto &folder :
         IO::CheckpointStore(run_directory, MPI_COMM_SELF).list())
      {
        std::ifstream in(folder + "/parameter_file");
        std::string   file;
        if (std::getline(in, file) && !file.empty())
          return file;
      }
    AssertThrow(false,
                dealii::ExcMessage("--resume " + run_directory +
                                   ": no checkpoint there (none written, or "
                                   "not a run folder)."));
    return "";
  }

  void
  Simulation::run()
  {
    install_interrupt_handlers();
    const auto start = std::chrono::steady_clock::now();
    impl->logger.set_details(
      impl->run.solver_log == "on" ||
      (impl->run.solver_log == "auto" && impl->run.problem != "heartbeat"));
    problem_types()
      .create(impl->run.problem)
      ->run({impl->prm, impl->run, impl->text, impl->logger, impl->comm});

    // Cost of the run, for benchmarks: wall time and peak resident memory.
    dealii::Utilities::System::MemoryStats memory;
    dealii::Utilities::System::get_memory_stats(memory);
    const double peak_mib = memory.VmHWM / 1024.0; // VmHWM is in kB
    const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
    std::ostringstream o;
    o << std::fixed << std::setprecision(2) << "Wall time " << wall
      << " s; peak memory " << std::setprecision(1)
      << dealii::Utilities::MPI::max(peak_mib, impl->comm)
      << " MiB per rank (max), "
      << dealii::Utilities::MPI::sum(peak_mib, impl->comm) << " MiB in total";
    impl->logger.line(o.str());
    IO::add_statistics(
      impl->run.output_directory + "/results.h5",
      {{"wall_time", "s", dealii::Utilities::MPI::max(wall, impl->comm)},
       {"peak_memory_per_rank",
        "MiB",
        dealii::Utilities::MPI::max(peak_mib, impl->comm)},
       {"peak_memory_total",
        "MiB",
        dealii::Utilities::MPI::sum(peak_mib, impl->comm)}},
      impl->comm);
  }

  std::string
  version()
  {
    return IO::code_version();
  }

  void
  print_parameters(std::ostream &out, const std::string &file, const bool json)
  {
    dealii::ParameterHandler prm;
    if (file.empty())
      declare_all_parameters(prm);
    else
      read_parameter_file(prm, file);
    prm.print_parameters(out,
                         json ? dealii::ParameterHandler::JSON
                              : dealii::ParameterHandler::PRM);
  }
} // namespace systole
