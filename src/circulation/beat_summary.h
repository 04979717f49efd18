#pragma once

#include "circulation/cycle_records.h"
#include "circulation/model_summary.h"

#include <array>
#include <string>
#include <vector>

namespace systole::Circulation
{
  /// Haemodynamic indices of one beat, in internal units (kPa, ms, mm^3).
  /// Values that a beat does not define (an end-systolic volume when the
  /// aortic valve did not open within the beat) are NaN.
  struct BeatSummary
  {
    unsigned int beat       = 0;
    double       start_time = 0; ///< [ms]
    double       end_time   = 0; ///< [ms]

    /// The mitral valve closed in this beat (there is an EDV).
    bool mitral_valve_closed = false;
    /// The aortic valve opened in this beat. If the mitral valve closed but
    /// the aortic did not open (weak contraction: transition 1 -> 0), the
    /// stroke volume is 0 and ESV = EDV.
    bool aortic_valve_opened = false;

    /// V at mitral closure [mm^3] (the last one of the beat).
    double end_diastolic_volume;
    /// V at aortic closure [mm^3].
    double end_systolic_volume;
    /// EDV - ESV [mm^3].
    double stroke_volume;
    /// SV / EDV [-].
    double ejection_fraction;
    /// p at mitral closure [kPa].
    double end_diastolic_pressure;
    /// Largest cavity pressure over the accepted steps [kPa].
    double peak_pressure;
    /// Largest and smallest dp/dt [kPa/ms], from differences of the cavity
    /// pressure over accepted steps.
    double dpdt_max;
    double dpdt_min;
    /// Time spent in each phase within the beat [ms], indexed by code(phase).
    std::array<double, n_phases> phase_duration = {{0, 0, 0, 0}};
    /// -\oint p dV by the trapezoidal rule over the accepted steps of the
    /// beat: the area of the PV loop [kPa mm^3].
    double stroke_work;
    /// Largest and smallest aortic root pressure in the beat [kPa].
    double aortic_systolic_pressure;
    double aortic_diastolic_pressure;
    /// |EDV - EDV of the previous beat| / EDV of the previous beat [-]; NaN
    /// for the first beat.
    double periodicity;

    /// Accepted integrator steps in the beat.
    unsigned int n_steps = 0;
    /// Calls of Ventricle::pressure() during the beat (the cost of a 3D
    /// model).
    unsigned long n_ventricle_calls = 0;
    /// Steps cut after a recoverable failure of the ventricle.
    unsigned int n_step_cuts = 0;
  };

  /// The summary as output columns, volumes in mL and pressures in mmHg
  /// (names with _mL/_mmHg suffixes), EF in %, dp/dt in mmHg/s, durations
  /// in ms; booleans as 0/1. The names and their order are the same for
  /// every beat.
  std::vector<SummaryColumn>
  summary_columns(const BeatSummary &summary);

  /// Collects the accepted steps and valve events of one beat and computes
  /// its BeatSummary.
  class BeatRecorder
  {
  public:
    /// @param[in] beat the beat number
    /// @param[in] start_time its start [ms]
    /// @param[in] anchor the last record of the previous beat (its state at
    ///   @p start_time), or nullptr for the first beat; differences, the loop
    ///   area and the phase durations start from it.
    BeatRecorder(const unsigned int beat,
                 const double       start_time,
                 const StepRecord  *anchor);

    void
    add_step(const StepRecord &record);

    void
    add_transition(const Transition &transition);

    /// The summary of the beat ending at @p end_time; @p previous_edv is the
    /// EDV of the previous beat [mm^3] (NaN if none).
    BeatSummary
    finish(const double        end_time,
           const double        previous_edv,
           const unsigned long n_ventricle_calls,
           const unsigned int  n_step_cuts) const;

  private:
    unsigned int            beat;
    double                  start_time;
    std::vector<StepRecord> records;
    std::vector<Transition> transitions;
  };
} // namespace systole::Circulation
