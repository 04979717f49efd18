#include "electrophysiology/activation.h"

#include <deal.II/base/exceptions.h>

#include <cmath>

namespace systole::Electrophysiology
{
  ActivationTracker::ActivationTracker(const unsigned int n_points,
                                       const double       threshold)
    : threshold_value(threshold)
    , first_times(n_points, std::numeric_limits<double>::quiet_NaN())
    , latest_times(n_points, std::numeric_limits<double>::quiet_NaN())
  {}

  void
  ActivationTracker::update(const double  t_old,
                            const double *v_old,
                            const double  t_new,
                            const double *v_new)
  {
    Assert(t_new > t_old, dealii::ExcInternalError());
    const double dt = t_new - t_old;
    for (unsigned int i = 0; i < first_times.size(); ++i)
      if (v_old[i] < threshold_value && v_new[i] >= threshold_value)
        {
          // v_new > v_old here, so the fraction lies in (0, 1].
          const double t =
            t_old + dt * (threshold_value - v_old[i]) / (v_new[i] - v_old[i]);
          latest_times[i] = t;
          if (std::isnan(first_times[i]))
            first_times[i] = t;
        }
  }

  const std::vector<double> &
  ActivationTracker::first() const
  {
    return first_times;
  }

  const std::vector<double> &
  ActivationTracker::latest() const
  {
    return latest_times;
  }

  unsigned int
  ActivationTracker::n_points() const
  {
    return first_times.size();
  }

  double
  ActivationTracker::threshold() const
  {
    return threshold_value;
  }

  void
  ActivationTracker::set(const std::vector<double> &first,
                         const std::vector<double> &latest)
  {
    Assert(first.size() == first_times.size() &&
             latest.size() == latest_times.size(),
           dealii::ExcInternalError());
    first_times  = first;
    latest_times = latest;
  }


  ActivationSummary
  summarize_activation(const std::vector<double> &times,
                       const std::vector<double> &weights,
                       const double               fraction,
                       const MPI_Comm             comm)
  {
    Assert(times.size() == weights.size(), dealii::ExcInternalError());
    AssertThrow(fraction > 0 && fraction <= 1,
                dealii::ExcMessage("The activation fraction must lie in "
                                   "(0, 1]."));
    double total_weight = 0, active_weight = 0;
    double first = std::numeric_limits<double>::infinity();
    double last  = -std::numeric_limits<double>::infinity();
    for (unsigned int i = 0; i < times.size(); ++i)
      {
        total_weight += weights[i];
        if (!std::isnan(times[i]))
          {
            active_weight += weights[i];
            first = std::min(first, times[i]);
            last  = std::max(last, times[i]);
          }
      }
    const double sums[2] = {total_weight, active_weight};
    double       global_sums[2];
    dealii::Utilities::MPI::sum(dealii::ArrayView<const double>(sums, 2),
                                comm,
                                dealii::ArrayView<double>(global_sums, 2));
    first = dealii::Utilities::MPI::min(first, comm);
    last  = dealii::Utilities::MPI::max(last, comm);

    ActivationSummary s;
    if (!(global_sums[0] > 0))
      return s;
    s.activated_fraction = global_sums[1] / global_sums[0];
    if (!(global_sums[1] > 0))
      return s;
    s.first = first;
    s.last  = last;
    // Every point active (up to round-off in the weight sums).
    if (global_sums[1] >= global_sums[0] * (1 - 1e-12))
      s.total = last - first;
    if (global_sums[1] < fraction * global_sums[0] * (1 - 1e-12))
      return s;

    // Smallest T with (weight of points active by T) >= fraction * total:
    // the weight is a step function of T, so bisect on [first, last].
    const auto weight_by = [&](const double T) {
      double w = 0;
      for (unsigned int i = 0; i < times.size(); ++i)
        if (times[i] <= T) // false for NaN
          w += weights[i];
      return dealii::Utilities::MPI::sum(w, comm);
    };
    const double target = fraction * global_sums[0] * (1 - 1e-12);
    double       lower = first, upper = last;
    if (weight_by(lower) >= target)
      upper = lower;
    while (upper - lower > 1e-9)
      {
        const double middle = 0.5 * (lower + upper);
        if (weight_by(middle) >= target)
          upper = middle;
        else
          lower = middle;
      }
    s.fraction_time = upper;
    return s;
  }
} // namespace systole::Electrophysiology
