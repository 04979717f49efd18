#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include "base/registry.h"

#include <memory>
#include <string>

/// @file
/// The run-type extension point: what `Problem = <name>` runs. Each problem
/// type is one entry of the table in problem_types.cc: its name, a sentence
/// for the help of "Problem", how to declare its own subsections and the
/// object that parses them and runs it. Simulation looks the name up; the
/// parameter declarations walk the table.
///
/// How to add a problem type: write simulation/<type>.{h,cc} with a run
/// function (and the declare/parse of its own subsection, if any), then add
/// one line to the table in problem_types.cc.

namespace systole
{
  class Logger;
  struct RunParameters;

  /// What every run gets: the parameters (declared and read), the settings
  /// every run shares, the text of the parameter file (written into the
  /// results), the rank-0 logger and the communicator.
  struct RunInputs
  {
    const dealii::ParameterHandler &prm;
    const RunParameters            &run;
    const std::string              &parameter_text;
    Logger                         &logger;
    MPI_Comm                        comm;
  };

  /// One problem type.
  class ProblemType
  {
  public:
    virtual ~ProblemType() = default;

    /// Parses and validates the problem's own subsections, so that a bad
    /// value is reported before anything runs (the components' subsections
    /// are checked by validate_component_parameters()).
    virtual void
    parse_parameters(const dealii::ParameterHandler &prm) const = 0;

    /// Runs it; results go to RunParameters::output_directory.
    virtual void
    run(const RunInputs &in) const = 0;
  };

  using ProblemTypeRegistry = Registry<std::unique_ptr<ProblemType>()>;

  /// The table of problem types (problem_types.cc).
  ProblemTypeRegistry &
  problem_types();
} // namespace systole
