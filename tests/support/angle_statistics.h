#pragma once

#include <cstddef>
#include <vector>

namespace test_support
{
  /// Samples of an error (e.g. an angle [degrees]): mean, signed mean, largest
  /// and percentiles of the absolute values.
  struct ErrorSamples
  {
    std::vector<double> values; ///< |e|
    double              signed_sum = 0;

    void
    add(const double e);
    std::size_t
    n() const
    {
      return values.size();
    }
    double
    mean() const;
    double
    signed_mean() const;
    double
    max() const;
    /// The value below which the fraction @p fraction of the samples lie.
    double
    percentile(const double fraction) const;
  };

  /// The difference a - b of two axis angles [degrees] (an axis and its
  /// opposite are one), in (-90, 90].
  double
  axis_difference(const double a, const double b);
} // namespace test_support
