#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace systole
{
  /// Settings every run shares (Problem, Time, Output, Discretization).
  /// Components parse their own subsections.
  struct RunParameters
  {
    std::string problem;

    double start_time = 0.0; ///< [ms]
    double end_time   = 0.0; ///< [ms]
    double time_step  = 1.0; ///< [ms]

    /// Folder of the parameter file (absolute): relative input paths are
    /// taken from it.
    std::string parameter_directory;

    std::string  run_name;
    std::string  output_directory; ///< results/<run name>
    unsigned int field_output_interval = 1;
    /// Checkpoints every this many accepted steps (0: none by steps), and
    /// after this much wall time [min] (0: none by time).
    unsigned int checkpoint_interval = 0;
    double       checkpoint_minutes  = 0;
    /// Continue from the newest valid checkpoint in output_directory.
    bool resume = false;
    /// The parameter file (absolute path).
    std::string parameter_file;
    std::string progress   = "auto";
    std::string solver_log = "auto"; ///< auto, on or off
    /// Test-only hooks (Problem = heartbeat): SIGKILL after this accepted
    /// step, or halfway through writing the checkpoint of this step; -1:
    /// never.
    long test_kill_after_step = -1, test_kill_in_checkpoint = -1;
    /// Test-only: limit the file size before writing this step's checkpoint.
    long test_file_size_limit_in_checkpoint = -1;
    /// Test-only: limit the file size to the results file's after this step.
    long test_file_size_limit_after_step = -1;
    /// Test-only hook (Problem = heartbeat): end the run after this accepted
    /// step, as an interrupted run ends but without a checkpoint; -1: never.
    long test_stop_after_step = -1;

    unsigned int polynomial_degree = 1;
    unsigned int mapping_degree    = 2;

    /// @param[in] prm_file the parameter file (its stem is the default run
    /// name)
    static RunParameters
    parse(const dealii::ParameterHandler &prm, const std::string &prm_file);
  };

  /// Declare every entry of every component: a misspelt or unknown entry in a
  /// file is then an error naming the line.
  void
  declare_all_parameters(dealii::ParameterHandler &prm);

  /// Parse every component's subsection of @p prm (read from @p file) once, so
  /// that an invalid value or a missing input file is reported before anything
  /// runs. Throws one clear message.
  void
  validate_component_parameters(const dealii::ParameterHandler &prm,
                                const std::string              &file);

  /// Declare everything and read @p file. Throws one clear message on a bad
  /// file.
  void
  read_parameter_file(dealii::ParameterHandler &prm, const std::string &file);
} // namespace systole
