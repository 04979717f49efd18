#pragma once

#include <deal.II/base/mpi.h>

#include <iosfwd>
#include <memory>
#include <string>

namespace systole
{
  /// One run of Systole, configured by a parameter file. Cheap to include
  /// (pimpl).
  class Simulation
  {
  public:
    /// Read and validate @p parameter_file (collective; throws one clear
    /// message on error).
    /// @p resume_directory: continue the run in that folder (results/<run>)
    /// from its newest valid checkpoint, as Output / Resume = true does.
    Simulation(const std::string &parameter_file,
               const MPI_Comm     comm,
               std::ostream      &out,
               const std::string &resume_directory = "");
    ~Simulation();

    /// The parameter file a run in @p run_directory was started with (as
    /// its newest checkpoint records it). Throws if there is none.
    static std::string
    parameter_file_of(const std::string &run_directory);

    /// Run the problem the file asks for, writing results/<run
    /// name>/results.h5.
    void
    run();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// "systole <version> (<git describe>)", as recorded in results files.
  std::string
  version();

  /// Write the full documented parameter set (defaults, or the values of @p
  /// file if not empty); @p json: deal.II's JSON form, which also gives every
  /// entry's pattern (scripts/bad_input_sweep.py mutates files by it).
  void
  print_parameters(std::ostream      &out,
                   const std::string &file = "",
                   const bool         json = false);
} // namespace systole
