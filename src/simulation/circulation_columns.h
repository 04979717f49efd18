#pragma once

#include <deal.II/lac/vector.h>

#include "circulation/model.h"
#include "circulation/model_summary.h"
#include "circulation/phase.h"
#include "io/results_file.h"

#include <string>
#include <vector>

/// @file
/// The result rows of a 0D circulation model, shared by Problem =
/// circulation and Problem = heartbeat (in the units of the results file).

namespace systole
{
  /// Appends to @p row: every state and output of @p model at @p a named
  /// after it with its unit suffix ("lv_volume_mL",
  /// "systemic_arterial_pressure_mmHg", "aortic_valve_flow_mL_per_s", ...),
  /// the phase code of every cavity ("lv_phase", Circulation::code()) and
  /// total_blood_volume_mL.
  void
  append_model_columns(const Circulation::Model              &model,
                       const Circulation::Arguments          &a,
                       const std::vector<Circulation::Phase> &phases,
                       std::vector<IO::Column>               &row);

  /// A valve event as the /events row records it. Callers pass it braced:
  /// valve_event_columns(model, {time, beat, valve, opens, y, p}).
  struct ValveEventRow
  {
    double                        time; ///< [ms]
    unsigned int                  beat;
    unsigned int                  valve; ///< index into Model::valves()
    bool                          opens; ///< else it closes
    const dealii::Vector<double> &y;     ///< the state of the model there
    /// The pressure of every cavity there [kPa].
    const dealii::Vector<double> &cavity_pressures;
  };

  /// The /events row of the valve event @p e: time, beat, valve, opens (1
  /// or 0), and the volume and pressure of every cavity there.
  std::vector<IO::Column>
  valve_event_columns(const Circulation::Model &model, const ValveEventRow &e);

  /// "Beat k: lv EDV .. mL, ESV .. mL, EF .. %, peak .. mmHg; EDV change
  /// .. %[, stroke volumes .. % apart]" from a summary row of
  /// Circulation::ModelBeatRecorder (the stroke volumes for cavities in
  /// series); with several cavities, each after the first and the EDV change
  /// on an indented line of its own (lines under 100 columns).
  std::string
  beat_log_line(const Circulation::Model                      &model,
                const unsigned int                             beat,
                const std::vector<Circulation::SummaryColumn> &summary);

  /// The value of column @p name in @p row (NaN if absent).
  double
  summary_value(const std::vector<Circulation::SummaryColumn> &row,
                const std::string                             &name);
} // namespace systole
