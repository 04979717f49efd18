#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace systole::Electrophysiology
{
  /// Calls @p step(t_next) with the end of every step from @p t0 to the last
  /// of @p breakpoints (ascending, after @p t0: the stimulus switching times
  /// and the end time): between two breakpoints the steps are equal and at
  /// most @p max_step long (up to 1e-9 of a step longer, so that a whole
  /// number of steps is not split by round-off), and the last ends on the
  /// breakpoint exactly. Monodomain::advance and SingleCell::advance step so.
  template <class Step>
  void
  for_each_step(const double               t0,
                const std::vector<double> &breakpoints,
                const double               max_step,
                const Step                &step)
  {
    double segment_start = t0;
    for (const double segment_end : breakpoints)
      {
        const double       span    = segment_end - segment_start;
        const unsigned int n_steps = static_cast<unsigned int>(
          std::max(1.0, std::ceil(span / max_step - 1e-9)));
        for (unsigned int k = 1; k <= n_steps; ++k)
          step(k == n_steps ? segment_end : segment_start + k * span / n_steps);
        segment_start = segment_end;
      }
  }
} // namespace systole::Electrophysiology
