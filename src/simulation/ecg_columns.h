#pragma once

#include "electrophysiology/ecg.h"
#include "io/results_file.h"

#include <array>
#include <string>
#include <vector>

/// @file
/// The result columns of the pseudo-ECG, shared by Problem =
/// electrophysiology and Problem = heartbeat.

namespace systole
{
  /// Appends ecg_<lead> [mV] for the 12 leads (Electrophysiology::
  /// lead_names()) to the /timeseries row @p row.
  void
  append_ecg_columns(const std::array<double, 12> &leads,
                     std::vector<IO::Column>      &row);

  /// The samples of the 12 leads of one beat, and their biomarkers.
  struct EcgBeat
  {
    std::vector<double>                 times; ///< [ms], ascending
    std::vector<std::array<double, 12>> leads; ///< [mV]

    /// Add a sample at @p time [ms] (ignored unless after the last one).
    void
    add(const double time, const std::array<double, 12> &values);

    /// Appends to the /summary row @p row the biomarkers (Electrophysiology::
    /// ecg_biomarkers()) of the samples in [@p start, @p end] [ms], with
    /// times from @p start: ecg_QRS_onset, ecg_QRS_duration, ecg_T_end,
    /// ecg_QT_interval [ms], ecg_R_amplitude_<lead> [mV] (NaN with fewer
    /// than three samples).
    void
    append_biomarkers(const double             start,
                      const double             end,
                      const double             threshold,
                      std::vector<IO::Column> &row) const;

    /// Drop the samples before @p time [ms].
    void
    forget_before(const double time);

    /// The leads at @p time [ms], linear between the samples around it
    /// (the nearest one outside them).
    std::array<double, 12>
    at(const double time) const;
  };
} // namespace systole
