#include "circulation/model_summary.h"

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

  CavityPhases::CavityPhases(const Model             &model,
                             const std::vector<bool> &valves_open)
    : model(model)
    , phases(model.n_cavities(), Phase::isovolumetric_relaxation)
  {
    update(valves_open);
  }

  void
  CavityPhases::update(const std::vector<bool> &valves_open)
  {
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      {
        const auto &cavity = model.cavities()[c];
        Phase      &phase  = phases[c];
        if (valves_open[cavity.outlet_valve])
          phase = Phase::ejection;
        else if (valves_open[cavity.inlet_valve])
          phase = Phase::filling;
        else if (phase == Phase::filling)
          phase = Phase::isovolumetric_contraction;
        else if (phase == Phase::ejection)
          phase = Phase::isovolumetric_relaxation;
      }
  }

  ModelBeatRecorder::ModelBeatRecorder(const Model             &model,
                                       const std::vector<bool> &valves_open)
    : model(model)
    , previous_edv(model.n_cavities(), nan)
    , last_periodicity(nan)
    , valves_open(valves_open)
    , phases(model, valves_open)
    , phase_durations(model.n_cavities(), {{0, 0, 0, 0}})
  {}

  void
  ModelBeatRecorder::start(const unsigned int beat, const double start_time)
  {
    this->beat       = beat;
    this->start_time = start_time;
    if (!samples.empty())
      samples.erase(samples.begin(), samples.end() - 1);
    closures.clear();
    // The phases carry over from the end of the previous beat.
    for (auto &d : phase_durations)
      d = {{0, 0, 0, 0}};
    phase_time = start_time;
  }

  void
  ModelBeatRecorder::accumulate_phase_durations(const double time)
  {
    if (time <= phase_time)
      return;
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      phase_durations[c][code(phases.phase(c))] += time - phase_time;
    phase_time = time;
  }

  void
  ModelBeatRecorder::add_valve_event(
    const unsigned int            valve,
    const bool                    opens,
    const double                  time,
    const dealii::Vector<double> &y,
    const dealii::Vector<double> &cavity_pressures)
  {
    if (!opens)
      closures.push_back({valve, {time, y, cavity_pressures, {}, {}}});
    accumulate_phase_durations(time);
    valves_open[valve] = opens;
    phases.update(valves_open);
  }

  void
  ModelBeatRecorder::add(const double                  time,
                         const dealii::Vector<double> &y,
                         const dealii::Vector<double> &cavity_pressures,
                         const dealii::Vector<double> &outputs)
  {
    std::vector<int> codes(model.n_cavities());
    for (unsigned int c = 0; c < codes.size(); ++c)
      codes[c] = code(phases.phase(c));
    samples.push_back({time, y, cavity_pressures, outputs, codes});
  }

  /// The pressure-volume loop of one cavity over the beat.
  struct ModelBeatRecorder::CavityBeat
  {
    double edv, esv;           ///< end-diastolic, end-systolic volume [mm³]
    double edp, peak;          ///< end-diastolic, peak pressure [kPa]
    double work;               ///< -oint p dV [kPa mm³]
    double dpdt_max, dpdt_min; ///< [kPa/ms]
  };

  ModelBeatRecorder::CavityBeat
  ModelBeatRecorder::cavity_beat(const unsigned int c) const
  {
    const auto        &cavity = model.cavities()[c];
    const unsigned int iv     = cavity.volume_state;
    const double       inf    = std::numeric_limits<double>::infinity();
    double             v_max = -inf, v_min = inf, p_peak = -inf;
    double             p_ed     = nan;
    double             work     = 0;
    double             dpdt_max = -inf, dpdt_min = inf;
    for (std::size_t i = 0; i < samples.size(); ++i)
      {
        const auto  &s = samples[i];
        const double v = s.y[iv], p = s.cavity_pressures[c];
        if (v > v_max)
          {
            v_max = v;
            p_ed  = p;
          }
        v_min  = std::min(v_min, v);
        p_peak = std::max(p_peak, p);
        if (i > 0)
          {
            // The loop runs counter-clockwise in (V, p): the work done
            // on the blood, -oint p dV, is positive.
            const auto &q = samples[i - 1];
            work -= 0.5 * (p + q.cavity_pressures[c]) * (v - q.y[iv]);
            // An event sample can share its time with an output sample.
            const double dt = s.time - q.time;
            if (dt > 0)
              {
                // The clinical indices: dp/dt max while the cavity
                // contracts (isovolumetric contraction, ejection), dp/dt
                // min while it relaxes or fills (a sample's phase is that
                // of the interval up to it: its events come after it). So
                // a jump of the load right after the inlet valve's closure
                // (the supports re-referred to end-diastole: 1.5 mmHg at
                // once) is neither.
                const double dpdt  = (p - q.cavity_pressures[c]) / dt;
                const int    phase = s.phases[c];
                if (phase == code(Phase::isovolumetric_contraction) ||
                    phase == code(Phase::ejection))
                  dpdt_max = std::max(dpdt_max, dpdt);
                else
                  dpdt_min = std::min(dpdt_min, dpdt);
              }
          }
      }
    if (samples.empty())
      v_max = v_min = p_peak = nan;
    if (dpdt_max == -inf)
      dpdt_max = nan;
    if (dpdt_min == inf)
      dpdt_min = nan;
    // The valve closures, where the beat has them.
    for (const auto &closure : closures)
      if (closure.valve == cavity.inlet_valve)
        {
          v_max = closure.sample.y[iv];
          p_ed  = closure.sample.cavity_pressures[c];
        }
      else if (closure.valve == cavity.outlet_valve)
        v_min = closure.sample.y[iv];
    return {v_max, v_min, p_ed, p_peak, work, dpdt_max, dpdt_min};
  }

  void
  ModelBeatRecorder::append_cavity_columns(
    const unsigned int          c,
    const CavityBeat           &b,
    std::vector<SummaryColumn> &row) const
  {
    const auto mL   = [](const double v) { return Units::mm3_to_mL(v); };
    const auto mmHg = [](const double p) { return Units::kPa_to_mmHg(p); };
    // kPa/ms -> mmHg/s
    const double      mmHg_per_s = Units::second / Units::mmHg;
    const double      sv         = b.edv - b.esv;
    const std::string n          = model.cavities()[c].name + "_";
    row.push_back({n + "EDV_mL", "mL", mL(b.edv)});
    row.push_back({n + "ESV_mL", "mL", mL(b.esv)});
    row.push_back({n + "SV_mL", "mL", mL(sv)});
    row.push_back({n + "EF", "%", 100.0 * sv / b.edv});
    row.push_back({n + "EDP_mmHg", "mmHg", mmHg(b.edp)});
    row.push_back({n + "peak_pressure_mmHg", "mmHg", mmHg(b.peak)});
    row.push_back({n + "stroke_work_mmHg_mL",
                   "mmHg mL",
                   b.work / (Units::mmHg * Units::mL)});
    row.push_back({n + "dpdt_max", "mmHg/s", mmHg_per_s * b.dpdt_max});
    row.push_back({n + "dpdt_min", "mmHg/s", mmHg_per_s * b.dpdt_min});
    for (const Phase phase : {Phase::filling,
                              Phase::isovolumetric_contraction,
                              Phase::ejection,
                              Phase::isovolumetric_relaxation})
      row.push_back(
        {n + name(phase) + "_duration", "ms", phase_durations[c][code(phase)]});
  }

  double
  ModelBeatRecorder::stroke_volume_difference(
    const std::vector<double> &stroke_volumes,
    const bool                 external_only) const
  {
    // Cavities in series eject the same volume at a periodic state; the
    // difference is the blood moved per beat from one part of the loop to
    // the other (e.g. from the pulmonary to the systemic pool).
    double       sv_max = -std::numeric_limits<double>::infinity();
    double       sv_min = -sv_max, sv_sum = 0;
    unsigned int n = 0;
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      if (!external_only || model.cavities()[c].kind == CavityKind::external)
        {
          sv_max = std::max(sv_max, stroke_volumes[c]);
          sv_min = std::min(sv_min, stroke_volumes[c]);
          sv_sum += stroke_volumes[c];
          ++n;
        }
    if (!model.cavities_in_series() || n < 2 || samples.empty())
      return nan;
    return (sv_max - sv_min) / (sv_sum / n);
  }

  void
  ModelBeatRecorder::append_pressure_columns(
    std::vector<SummaryColumn> &row) const
  {
    // Every pressure: max, min, time average.
    const auto pressure_statistics = [&](const std::string &name,
                                         const auto        &value_of) {
      double max = -std::numeric_limits<double>::infinity(), min = -max;
      double integral = 0;
      for (std::size_t i = 0; i < samples.size(); ++i)
        {
          const double p = value_of(samples[i]);
          max            = std::max(max, p);
          min            = std::min(min, p);
          if (i > 0)
            integral += 0.5 * (p + value_of(samples[i - 1])) *
                        (samples[i].time - samples[i - 1].time);
        }
      const double duration =
        samples.empty() ? 0.0 : samples.back().time - samples.front().time;
      row.push_back({name + "_max_mmHg", "mmHg", Units::kPa_to_mmHg(max)});
      row.push_back({name + "_min_mmHg", "mmHg", Units::kPa_to_mmHg(min)});
      row.push_back(
        {name + "_mean_mmHg",
         "mmHg",
         duration > 0 ? Units::kPa_to_mmHg(integral / duration) : nan});
    };
    for (unsigned int i = 0; i < model.n_states(); ++i)
      if (model.states()[i].quantity == Quantity::pressure)
        pressure_statistics(model.states()[i].name,
                            [i](const Sample &s) { return s.y[i]; });
    for (unsigned int i = 0; i < model.outputs().size(); ++i)
      if (model.outputs()[i].quantity == Quantity::pressure)
        pressure_statistics(model.outputs()[i].name,
                            [i](const Sample &s) { return s.outputs[i]; });
  }

  void
  ModelBeatRecorder::append_blood_volume_columns(
    std::vector<SummaryColumn> &row) const
  {
    double v_end = nan, drift = nan;
    if (!samples.empty())
      {
        const double v0 = model.total_blood_volume(samples.front().y);
        v_end           = model.total_blood_volume(samples.back().y);
        drift           = 0;
        for (const auto &s : samples)
          drift = std::max(drift,
                           std::abs(model.total_blood_volume(s.y) - v0) /
                             std::abs(v0));
      }
    row.push_back({"total_blood_volume_mL", "mL", Units::mm3_to_mL(v_end)});
    row.push_back({"total_blood_volume_drift", "-", drift});
  }

  std::vector<SummaryColumn>
  ModelBeatRecorder::finish(const double end_time)
  {
    accumulate_phase_durations(end_time);
    std::vector<SummaryColumn> row = {{"beat", "-", static_cast<double>(beat)},
                                      {"start_time", "ms", start_time},
                                      {"end_time", "ms", end_time}};

    std::vector<double> edv(model.n_cavities(), nan);
    std::vector<double> stroke_volumes(model.n_cavities(), nan);
    double              edv_change = samples.empty() ? nan : 0.0;
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      {
        const CavityBeat b = cavity_beat(c);
        edv[c]             = b.edv;
        stroke_volumes[c]  = b.edv - b.esv;
        edv_change =
          std::max(edv_change,
                   std::abs(b.edv - previous_edv[c]) / previous_edv[c]);
        append_cavity_columns(c, b, row);
      }
    // std::max ignores a NaN second argument only; the first beat has no
    // previous EDV.
    if (std::isnan(previous_edv.empty() ? nan : previous_edv[0]))
      edv_change = nan;

    const double sv_difference_all =
      stroke_volume_difference(stroke_volumes, false);
    // The periodicity: every cavity's EDV and, with two or more 3D
    // (external) cavities in series, their stroke volumes. The EDVs alone
    // settle long before the stroke volumes of a closed-loop BiV agree (the
    // pools are compliant: docs/verification.md); with one 3D ventricle the
    // stop stays on the EDVs, as it was.
    const double sv_difference_3d =
      stroke_volume_difference(stroke_volumes, true);
    const double periodicity =
      std::isnan(sv_difference_3d) || std::isnan(edv_change)
        ? edv_change
        : std::max(edv_change, sv_difference_3d);

    append_pressure_columns(row);
    append_blood_volume_columns(row);
    row.push_back({"EDV_change", "-", edv_change});
    row.push_back({"SV_difference", "-", sv_difference_all});
    row.push_back({"periodicity", "-", periodicity});
    row.push_back({"samples", "-", static_cast<double>(samples.size())});

    previous_edv     = edv;
    last_periodicity = periodicity;
    return row;
  }
} // namespace systole::Circulation
