#include "support/angle_statistics.h"

#include <algorithm>
#include <cmath>

namespace test_support
{
  void
  ErrorSamples::add(const double e)
  {
    values.push_back(std::abs(e));
    signed_sum += e;
  }

  double
  ErrorSamples::mean() const
  {
    double s = 0;
    for (const double v : values)
      s += v;
    return values.empty() ? 0.0 : s / values.size();
  }

  double
  ErrorSamples::signed_mean() const
  {
    return values.empty() ? 0.0 : signed_sum / values.size();
  }

  double
  ErrorSamples::max() const
  {
    return values.empty() ? 0.0
                          : *std::max_element(values.begin(), values.end());
  }

  double
  ErrorSamples::percentile(const double fraction) const
  {
    std::vector<double> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    return sorted.empty()
             ? 0.0
             : sorted[static_cast<std::size_t>(fraction * (sorted.size() - 1))];
  }

  double
  axis_difference(const double a, const double b)
  {
    double d = std::fmod(a - b, 180.0);
    if (d > 90)
      d -= 180;
    if (d <= -90)
      d += 180;
    return d;
  }
} // namespace test_support
