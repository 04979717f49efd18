#pragma once

#include <deal.II/lac/vector.h>

#include "circulation/model.h"
#include "circulation/phase.h"

#include <boost/serialization/array.hpp>
#include <boost/serialization/vector.hpp>

#include <array>
#include <string>
#include <vector>

namespace systole::Circulation
{
  /// One column of the per-beat summary table of the results file.
  struct SummaryColumn
  {
    std::string name;
    std::string unit;
    double      value;
  };

  /// The phase of each cavity of a model, from its valves: ejection while
  /// the outlet valve is open, filling while the inlet valve is open,
  /// otherwise isovolumetric contraction after filling and isovolumetric
  /// relaxation after ejection.
  class CavityPhases
  {
  public:
    /// @param[in] valves_open the valve states at the start
    CavityPhases(const Model &model, const std::vector<bool> &valves_open);

    /// Update with the valve states after an event (or any time).
    void
    update(const std::vector<bool> &valves_open);

    /// Phase of cavity @p c.
    Phase
    phase(const unsigned int c) const
    {
      return phases[c];
    }

    /// Write or read the phases (boost serialization, for checkpoints).
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &phases;
    }

  private:
    const Model       &model;
    std::vector<Phase> phases;
  };

  /// Collects the samples of one beat of a 0D model (output times and valve
  /// events, in time order) and computes its summary row:
  /// - per cavity c: c_EDV_mL and c_EDP_mmHg, the volume and pressure at
  ///   the (last) closure of its inlet valve in the beat, c_ESV_mL the
  ///   volume at the closure of its outlet valve (the largest and smallest
  ///   volume of the beat if a valve did not close: with diode valves the
  ///   volume still changes by the leaks after a closure, by about 1e-5 mL
  ///   per beat), c_SV_mL, c_EF (%), c_peak_pressure_mmHg,
  ///   c_stroke_work_mmHg_mL (-oint p dV, trapezoidal), c_dpdt_max and
  ///   c_dpdt_min (mmHg/s: the largest difference quotient of the cavity
  ///   pressure between consecutive samples in isovolumetric contraction and
  ///   ejection, the smallest in isovolumetric relaxation and filling; NaN
  ///   in a beat without such an interval), and the time spent
  ///   in each phase of CavityPhases within the beat (ms):
  ///   c_filling_duration, c_isovolumetric_contraction_duration,
  ///   c_ejection_duration, c_isovolumetric_relaxation_duration. The phase
  ///   changes at the valve events (add_valve_event()); a beat starts in the
  ///   phase in which the previous one ended, the first one in the phase of
  ///   the valve states given to the constructor. The four durations add up
  ///   to end_time - start_time;
  /// - per pressure (states and outputs): name_max_mmHg, name_min_mmHg,
  ///   name_mean_mmHg (time average, trapezoidal);
  /// - total_blood_volume_mL at the beat's end, and its largest relative
  ///   change within the beat (total_blood_volume_drift);
  /// - EDV_change: the largest relative change of a cavity's EDV since the
  ///   previous beat (NaN in the first);
  /// - SV_difference: for cavities in series (Model::cavities_in_series(),
  ///   the closed loop's two ventricles), the spread of their stroke volumes
  ///   relative to their mean, (max SV - min SV) / mean SV: the blood moved
  ///   per beat between the parts of the loop, zero at a periodic state (NaN
  ///   for a single cavity or cavities not in series);
  /// - periodicity: what the periodic-state stop compares with its
  ///   tolerance: EDV_change, and, when two or more of the cavities in series
  ///   are external (both ventricles in 3D), the larger of EDV_change and the
  ///   relative stroke-volume spread of the external cavities (NaN in the
  ///   first beat). With one 3D ventricle (and a 0D one) it is EDV_change.
  /// Extremes are taken over the samples, so their accuracy is that of the
  /// output interval (valve events are samples too, so EDV and ESV, which
  /// lie at valve closures, are accurate to the tolerance).
  class ModelBeatRecorder
  {
  public:
    /// @param[in] valves_open the valve states at the start of the first
    ///   beat (the phase of each cavity there, see CavityPhases)
    ModelBeatRecorder(const Model &model, const std::vector<bool> &valves_open);

    /// Start beat @p beat at @p start_time; the last sample of the previous
    /// beat (its end) is the first one of this beat.
    void
    start(const unsigned int beat, const double start_time);

    /// A sample: time [ms], state, all cavity pressures [kPa] and outputs.
    void
    add(const double                  time,
        const dealii::Vector<double> &y,
        const dealii::Vector<double> &cavity_pressures,
        const dealii::Vector<double> &outputs);

    /// A sample at a valve event (add() it too, before or after): the
    /// closures of inlet and outlet valves mark EDV and ESV, and the cavity
    /// phases follow the new valve state (CavityPhases::update()).
    void
    add_valve_event(const unsigned int            valve,
                    const bool                    opens,
                    const double                  time,
                    const dealii::Vector<double> &y,
                    const dealii::Vector<double> &cavity_pressures);

    /// The summary row of the beat ending at @p end_time; stores the EDVs
    /// for the next beat's periodicity.
    std::vector<SummaryColumn>
    finish(const double end_time);

    /// The periodicity of the last finished beat (NaN for the first): the
    /// summary column "periodicity".
    double
    periodicity() const
    {
      return last_periodicity;
    }

    /// EDV of each cavity in the last finished beat [mm^3].
    const std::vector<double> &
    end_diastolic_volumes() const
    {
      return previous_edv;
    }

    /// Write or read everything collected so far (boost serialization, for
    /// checkpoints).
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &beat &start_time &samples &closures   &previous_edv;
      archive &last_periodicity &valves_open &phases &phase_durations;
      archive                                        &phase_time;
    }

  private:
    /// Adds the time from the last phase change (or the beat's start) to
    /// @p time to the durations of the current phases.
    void
    accumulate_phase_durations(const double time);

    /// The pressure-volume loop of one cavity over the beat (finish()).
    struct CavityBeat;

    /// The loop of cavity @p c: its extreme volumes (at the valve closures
    /// where the beat has them), pressures, work and dp/dt.
    CavityBeat
    cavity_beat(const unsigned int c) const;

    /// The summary columns of cavity @p c with the loop @p b.
    void
    append_cavity_columns(const unsigned int          c,
                          const CavityBeat           &b,
                          std::vector<SummaryColumn> &row) const;

    /// The spread of the @p stroke_volumes (of the 3D cavities only, if
    /// @p external_only) relative to their mean; NaN unless the cavities
    /// are in series.
    double
    stroke_volume_difference(const std::vector<double> &stroke_volumes,
                             const bool                 external_only) const;

    /// Max, min and time average of every pressure state and output.
    void
    append_pressure_columns(std::vector<SummaryColumn> &row) const;

    /// The total blood volume at the end of the beat and its largest
    /// relative drift from the start.
    void
    append_blood_volume_columns(std::vector<SummaryColumn> &row) const;

    struct Sample
    {
      double                 time;
      dealii::Vector<double> y, cavity_pressures, outputs;
      /// The phase code of each cavity up to the sample (add()).
      std::vector<int> phases;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int /*version*/)
      {
        archive &time &y &cavity_pressures &outputs &phases;
      }
    };

    struct Closure
    {
      unsigned int valve;
      Sample       sample;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int /*version*/)
      {
        archive &valve &sample;
      }
    };

    const Model         &model;
    unsigned int         beat       = 0;
    double               start_time = 0;
    std::vector<Sample>  samples;
    std::vector<Closure> closures;
    std::vector<double>  previous_edv;
    double               last_periodicity;
    /// The valve states after the last event, and the cavity phases.
    std::vector<bool> valves_open;
    CavityPhases      phases;
    /// Time [ms] in each phase within the beat, per cavity, up to
    /// phase_time.
    std::vector<std::array<double, n_phases>> phase_durations;
    double                                    phase_time = 0;
  };
} // namespace systole::Circulation
