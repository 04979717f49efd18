#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include "simulation/heartbeat_stepper.h"

#include <array>
#include <chrono>
#include <functional>
#include <limits>
#include <vector>

namespace systole
{
  class ElectricalActivation;
  class Logger;
  class MechanicsVentricles;
  class Progress;
  struct RunParameters;
  namespace IO
  {
    class ResultsFile;
    struct Column;
  } // namespace IO
  namespace Mechanics
  {
    class Problem;
  }
  namespace Postprocess
  {
    class Manager;
  }

  /// What a HeartbeatWriter writes from and to: its constructor's argument
  /// and its members (kept by reference; they must outlive it).
  struct HeartbeatWriterParts
  {
    const Circulation::Model &model;
    IO::ResultsFile          &results;
    MechanicsVentricles      &ventricles;
    Mechanics::Problem       &problem;
    ElectricalActivation     *ep; ///< null without electrophysiology
    const RunParameters      &run;
    Logger                   &logger;
    Progress                 &progress;
    Postprocess::Manager     &postprocess;
    const double              period;
    MPI_Comm                  comm;
  };

  /// Writes what the heartbeat stepper computes: one /timeseries row per
  /// accepted step, one /events row per valve event, one /summary row per
  /// beat, fields every Output / Field output interval steps, the log, and
  /// the checkpoints when they are due.
  class HeartbeatWriter : public HeartbeatStepper::Observer,
                          private HeartbeatWriterParts
  {
  public:
    explicit HeartbeatWriter(const HeartbeatWriterParts &parts);

    void
    on_step(const HeartbeatStepper::Step &s) override;

    void
    on_event(const unsigned int            valve,
             const bool                    opens,
             const HeartbeatStepper::Step &s) override;

    void
    on_failure(const double       t_from,
               const double       t_to,
               const std::string &why) override;

    void
    on_beat(const unsigned int                             beat,
            const std::vector<Circulation::SummaryColumn> &summary) override;

    /// Checkpoints: every Output / Checkpoint interval steps, after Output /
    /// Checkpoint wall time interval minutes, and on SIGTERM or SIGINT (then
    /// the run stops).
    void
    on_step_complete(const unsigned int step_index) override;

    bool
    stop_requested() override;

    /// Writes a checkpoint of the step with the given index.
    std::function<void(unsigned int)> checkpoint;
    /// The heartbeat's sections (none: not timed).
    dealii::TimerOutput *timer = nullptr;
    /// Mechanics / Inertia: a kinetic_energy column [µJ].
    bool inertia = false;

    /// The counters of the rows written (save() and load() of a
    /// checkpoint).
    template <class Archive>
    void
    serialize(Archive &archive)
    {
      archive &rows.total_iterations &rows.total_solves &rows.total_rejected;
      archive &rows.steps_in_beat &rows.ep_steps_written &rows
        .ep_steps_in_beats;
      archive &rows.last_time &rows.last_step &rows.last_field_step;
    }

    /// The wall times of the current beat so far [s] (they are columns of
    /// its summary row; a resumed run adds its own).
    std::array<double, 5>
    beat_seconds() const;

    void
    set_beat_seconds(const std::array<double, 5> &so_far);

    /// The fields of the last step, unless written already. Collective.
    void
    finish();

  private:
    /// Total wall times [s]: mechanics, assembly, linear solver, cavity
    /// volume, electrophysiology.
    std::array<double, 5>
    seconds() const;

    /// The EP and postprocessor columns of a step's row.
    void
    append_ep_columns(const HeartbeatStepper::Step &s,
                      std::vector<IO::Column>      &row);

    /// The EP columns of a beat's summary row, and the text for its log.
    std::string
    append_beat_ep_columns(
      const std::vector<Circulation::SummaryColumn> &summary,
      std::vector<IO::Column>                       &row);

    void
    write_fields(const unsigned int step);

    std::vector<unsigned int> external;
    /// The counters of the rows written (saved in checkpoints but
    /// seconds_written).
    struct RowCounters
    {
      unsigned int  total_iterations = 0, total_solves = 0, total_rejected = 0;
      unsigned int  steps_in_beat    = 0;
      unsigned long ep_steps_written = 0, ep_steps_in_beats = 0;
      /// Totals at the last summary row: mechanics, assembly, linear
      /// solver, cavity volume, electrophysiology [s].
      std::array<double, 5> seconds_written = {{0, 0, 0, 0, 0}};
      double                last_time       = 0;
      unsigned int          last_step       = 0;
      /// Step of the last field output (none: the largest value).
      unsigned int last_field_step = std::numeric_limits<unsigned int>::max();
    } rows;
    bool                                  stop = false;
    std::chrono::steady_clock::time_point last_checkpoint =
      std::chrono::steady_clock::now();
  };
} // namespace systole
