#pragma once

#include <string>

/// @file
/// Numbers as text for messages, logs and parameter defaults: one function,
/// so that the same value reads the same wherever it is printed.

namespace systole
{
  /// @p value with @p significant_digits significant digits (the default
  /// floating-point notation of a stream of that precision: "0.1", "1e-05").
  std::string
  format_number(const double value, const int significant_digits = 6);
} // namespace systole
