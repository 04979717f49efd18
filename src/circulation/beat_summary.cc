#include "circulation/beat_summary.h"

#include "base/units.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace systole::Circulation
{
  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  } // namespace

  BeatRecorder::BeatRecorder(const unsigned int beat,
                             const double       start_time,
                             const StepRecord  *anchor)
    : beat(beat)
    , start_time(start_time)
  {
    if (anchor != nullptr)
      records.push_back(*anchor);
  }

  void
  BeatRecorder::add_step(const StepRecord &record)
  {
    records.push_back(record);
  }

  void
  BeatRecorder::add_transition(const Transition &transition)
  {
    transitions.push_back(transition);
  }

  BeatSummary
  BeatRecorder::finish(const double        end_time,
                       const double        previous_edv,
                       const unsigned long n_ventricle_calls,
                       const unsigned int  n_step_cuts) const
  {
    BeatSummary s;
    s.beat              = beat;
    s.start_time        = start_time;
    s.end_time          = end_time;
    s.n_ventricle_calls = n_ventricle_calls;
    s.n_step_cuts       = n_step_cuts;
    s.n_steps           = std::count_if(records.begin(),
                              records.end(),
                              [this](const StepRecord &r) {
                                return r.beat == beat && r.step_size > 0;
                              });

    s.end_diastolic_volume   = nan;
    s.end_diastolic_pressure = nan;
    s.end_systolic_volume    = nan;
    for (const auto &t : transitions)
      {
        if (t.from == Phase::filling &&
            t.to == Phase::isovolumetric_contraction)
          {
            s.mitral_valve_closed    = true;
            s.end_diastolic_volume   = t.volume;
            s.end_diastolic_pressure = t.pressure;
          }
        else if (t.to == Phase::ejection)
          s.aortic_valve_opened = true;
        else if (t.from == Phase::ejection)
          s.end_systolic_volume = t.volume;
      }
    if (s.mitral_valve_closed && !s.aortic_valve_opened)
      s.end_systolic_volume = s.end_diastolic_volume;
    s.stroke_volume     = s.end_diastolic_volume - s.end_systolic_volume;
    s.ejection_fraction = s.stroke_volume / s.end_diastolic_volume;
    s.periodicity =
      std::abs(s.end_diastolic_volume - previous_edv) / previous_edv;

    const double inf            = std::numeric_limits<double>::infinity();
    s.peak_pressure             = -inf;
    s.aortic_systolic_pressure  = -inf;
    s.aortic_diastolic_pressure = inf;
    s.dpdt_max                  = -inf;
    s.dpdt_min                  = inf;
    s.stroke_work               = 0;
    for (std::size_t i = 0; i < records.size(); ++i)
      {
        const auto &r   = records[i];
        s.peak_pressure = std::max(s.peak_pressure, r.pressure);
        s.aortic_systolic_pressure =
          std::max(s.aortic_systolic_pressure, r.aortic_pressure);
        s.aortic_diastolic_pressure =
          std::min(s.aortic_diastolic_pressure, r.aortic_pressure);
        if (i == 0)
          continue;
        const auto  &q  = records[i - 1];
        const double dt = r.time - q.time;
        if (dt <= 0)
          continue;
        const double dpdt = (r.pressure - q.pressure) / dt;
        s.dpdt_max        = std::max(s.dpdt_max, dpdt);
        s.dpdt_min        = std::min(s.dpdt_min, dpdt);
        s.phase_duration[code(r.phase)] += dt;
        // The loop runs counter-clockwise in the (V, p) plane, so the
        // work done on the blood, -(closed integral of p dV), is positive.
        s.stroke_work -=
          0.5 * (r.pressure + q.pressure) * (r.volume - q.volume);
      }
    if (records.empty())
      s.peak_pressure               = s.aortic_systolic_pressure =
        s.aortic_diastolic_pressure = nan;
    if (s.dpdt_max == -inf)
      s.dpdt_max = s.dpdt_min = nan;
    return s;
  }

  std::vector<SummaryColumn>
  summary_columns(const BeatSummary &s)
  {
    // kPa/ms -> mmHg/s
    const double dpdt = Units::second / Units::mmHg;
    const auto   mL   = [](const double v) { return Units::mm3_to_mL(v); };
    const auto   mmHg = [](const double p) { return Units::kPa_to_mmHg(p); };
    return {
      {"beat", "-", static_cast<double>(s.beat)},
      {"start_time", "ms", s.start_time},
      {"EDV_mL", "mL", mL(s.end_diastolic_volume)},
      {"ESV_mL", "mL", mL(s.end_systolic_volume)},
      {"SV_mL", "mL", mL(s.stroke_volume)},
      {"EF", "%", 100.0 * s.ejection_fraction},
      {"EDP_mmHg", "mmHg", mmHg(s.end_diastolic_pressure)},
      {"peak_pressure_mmHg", "mmHg", mmHg(s.peak_pressure)},
      {"dpdt_max", "mmHg/s", dpdt * s.dpdt_max},
      {"dpdt_min", "mmHg/s", dpdt * s.dpdt_min},
      {"aortic_systolic_mmHg", "mmHg", mmHg(s.aortic_systolic_pressure)},
      {"aortic_diastolic_mmHg", "mmHg", mmHg(s.aortic_diastolic_pressure)},
      {"stroke_work_mmHg_mL",
       "mmHg mL",
       s.stroke_work / (Units::mmHg * Units::mL)},
      {"filling_duration", "ms", s.phase_duration[code(Phase::filling)]},
      {"isovolumetric_contraction_duration",
       "ms",
       s.phase_duration[code(Phase::isovolumetric_contraction)]},
      {"ejection_duration", "ms", s.phase_duration[code(Phase::ejection)]},
      {"isovolumetric_relaxation_duration",
       "ms",
       s.phase_duration[code(Phase::isovolumetric_relaxation)]},
      {"aortic_valve_opened", "-", s.aortic_valve_opened ? 1.0 : 0.0},
      {"periodicity", "-", s.periodicity},
      {"steps", "-", static_cast<double>(s.n_steps)},
      {"ventricle_calls", "-", static_cast<double>(s.n_ventricle_calls)},
      {"step_cuts", "-", static_cast<double>(s.n_step_cuts)},
    };
  }
} // namespace systole::Circulation
