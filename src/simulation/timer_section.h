#pragma once

#include <deal.II/base/timer.h>

#include <memory>

namespace systole
{
  /// The section @p name of @p timer for the lifetime of the returned object
  /// (nothing without a timer).
  inline std::unique_ptr<dealii::TimerOutput::Scope>
  timer_section(dealii::TimerOutput *timer, const char *name)
  {
    return timer == nullptr
             ? nullptr
             : std::make_unique<dealii::TimerOutput::Scope>(*timer, name);
  }
} // namespace systole
