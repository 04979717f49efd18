#pragma once

#include <deal.II/base/mpi.h>

#include <limits>
#include <vector>

namespace systole::Electrophysiology
{
  /// The activation time the field outputs write for a node that has not
  /// activated [ms] (as openCARP's LAT maps do): NaN would spread through
  /// DataOut's evaluation (0 x NaN) to every vertex of the node's cells.
  inline constexpr double not_activated_time = -1.0;

  /// Activation times of a set of points from a sampled potential: a point
  /// activates when its potential crosses the threshold upwards between two
  /// samples (v_old < threshold <= v_new); the crossing time is located by
  /// linear interpolation in time between the samples. Keeps the first
  /// activation (the activation map of the run) and the latest one (the
  /// current beat, for repeated stimulation). NaN marks "not (yet)
  /// activated".
  class ActivationTracker
  {
  public:
    /// @param[in] n_points number of points tracked
    /// @param[in] threshold upstroke threshold, in the units of the potential
    ActivationTracker(const unsigned int n_points, const double threshold);

    /// Record one sample interval: the potentials @p v_old at @p t_old and
    /// @p v_new at @p t_new > t_old, n_points() values each.
    void
    update(const double  t_old,
           const double *v_old,
           const double  t_new,
           const double *v_new);

    /// Time of the first upstroke of each point [ms]; NaN if none yet.
    const std::vector<double> &
    first() const;

    /// Time of the most recent upstroke of each point [ms]; NaN if none.
    const std::vector<double> &
    latest() const;

    unsigned int
    n_points() const;

    double
    threshold() const;

    /// Replace the recorded times (restoring a saved state).
    void
    set(const std::vector<double> &first, const std::vector<double> &latest);

  private:
    double              threshold_value;
    std::vector<double> first_times;
    std::vector<double> latest_times;
  };

  /// Summary of an activation map over the wall, every point weighted by
  /// its share of the volume (collective over @p comm).
  struct ActivationSummary
  {
    /// Fraction of the volume activated (first upstroke recorded) [-].
    double activated_fraction = 0;
    /// Earliest and latest activation time [ms] (NaN if none).
    double first = std::numeric_limits<double>::quiet_NaN();
    double last  = std::numeric_limits<double>::quiet_NaN();
    /// Total activation time last - first [ms] (NaN unless every point
    /// activated).
    double total = std::numeric_limits<double>::quiet_NaN();
    /// Time at which the given fraction (90 %) of the volume is active [ms]
    /// (NaN if it never is).
    double fraction_time = std::numeric_limits<double>::quiet_NaN();
  };

  /// Summarise activation times @p times (this rank's points, NaN for none)
  /// with volume weights @p weights (> 0); @p fraction in (0, 1] picks the
  /// quantile of fraction_time, located by bisection to 1e-9 ms. Collective.
  ActivationSummary
  summarize_activation(const std::vector<double> &times,
                       const std::vector<double> &weights,
                       const double               fraction,
                       const MPI_Comm             comm);
} // namespace systole::Electrophysiology
