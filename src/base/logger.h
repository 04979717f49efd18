#pragma once

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>

#include <chrono>
#include <iosfwd>
#include <string>

namespace systole
{
  /// Console output of a run: everything goes through rank 0. Passed by
  /// reference, never global.
  class Logger
  {
  public:
    /// @param[in] comm communicator of the run; only its rank 0 prints.
    /// @param[in] out  stream to print to (std::cout in the app).
    Logger(const MPI_Comm comm, std::ostream &out);

    /// Stream that prints on rank 0 only.
    dealii::ConditionalOStream &
    stream();

    /// Stream for solver details (Newton residual histories): prints on
    /// rank 0 while details are enabled (the default).
    dealii::ConditionalOStream &
    detail();

    /// Enable or silence detail().
    void
    set_details(const bool enabled);

    /// Print one line on rank 0.
    void
    line(const std::string &text);

    bool
    is_root() const;

  private:
    dealii::ConditionalOStream out;
    dealii::ConditionalOStream details;
  };

  /// A progress line for long runs: step, simulated time, current activity,
  /// elapsed time, ETA. Printed on rank 0 at most every @p min_interval
  /// seconds; silent when disabled (the default in CI, where the environment
  /// variable CI is set, or when stdout is not a terminal).
  class Progress
  {
  public:
    enum class Mode
    {
      automatic,
      on,
      off
    };

    Progress(Logger      &logger,
             const Mode   mode,
             const double start_time,
             const double end_time,
             const double min_interval_seconds = 2.0);

    /// Report that step @p step reached simulated time @p time [ms] and is now
    /// doing @p activity.
    void
    update(const unsigned int step,
           const double       time,
           const std::string &activity);

    /// Seconds since construction.
    double
    elapsed() const;

    /// Whether progress lines are printed.
    bool
    enabled() const;

    /// Parse "auto", "on" or "off".
    static Mode
    parse_mode(const std::string &text);

  private:
    Logger                               &logger;
    bool                                  active;
    double                                start_time;
    double                                end_time;
    double                                min_interval;
    std::chrono::steady_clock::time_point started;
    double                                last_print = -1e300;
  };
} // namespace systole
