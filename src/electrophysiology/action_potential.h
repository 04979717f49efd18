#pragma once

#include <vector>

namespace systole::Electrophysiology
{
  /// Measures of one beat of a paced cell.
  struct BeatSummary
  {
    double resting_potential_mV; ///< at the stimulus onset
    double peak_potential_mV;    ///< maximum over the beat
    /// Time spent above V_rest + 0.1 (V_peak - V_rest): from the upward to
    /// the first downward crossing after the peak, both interpolated
    /// linearly between samples; NaN if the beat has no such crossings.
    double APD90_ms;
    double peak_calcium_uM; ///< maximum over the beat; NaN without calcium
  };

  /// Collects the samples of one beat (time, potential and calcium, in time
  /// order, from the stimulus onset on) and measures it.
  class ActionPotentialRecorder
  {
  public:
    /// Start a beat whose stimulus begins at @p onset [ms] with the
    /// potential @p v_mV and calcium @p calcium_uM there.
    void
    start(const double onset, const double v_mV, const double calcium_uM);

    /// One sample after the previous one.
    void
    add(const double t, const double v_mV, const double calcium_uM);

    /// The measures of the samples since start().
    BeatSummary
    summary() const;

  private:
    std::vector<double> times, potentials;
    double              peak_calcium = 0;
  };
} // namespace systole::Electrophysiology
