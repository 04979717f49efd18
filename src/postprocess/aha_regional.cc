#include "postprocess/aha_regional.h"

#include <deal.II/base/mpi.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace systole::Postprocess
{
  Needs
  AhaRegional::needs() const
  {
    Needs n;
    n.cardiac_frame = n.segments = true;
    return n;
  }

  AhaRegional::SegmentValues
  AhaRegional::segment_means(const StepData &data)
  {
    return segment_means(data, [&](const unsigned int c, const unsigned int q) {
      const auto &pq = (*data.quantities)[c][q];
      return std::array<double, 3>{
        {pq.strain_circumferential, pq.strain_longitudinal, pq.strain_radial}};
    });
  }

  AhaRegional::SegmentValues
  AhaRegional::segment_means(const StepData &data, const PointValues &value)
  {
    // Per segment: the three weighted sums and the volume.
    std::vector<double> sums(17 * 4, 0.0);
    for (unsigned int c = 0; c < data.points->size(); ++c)
      {
        if (!data.in_wall(c))
          continue;
        const auto &points = (*data.points)[c];
        for (unsigned int q = 0; q < points.size(); ++q)
          {
            const unsigned int s = (*data.point_segments)[c][q] - 1;
            const auto         v = value(c, q);
            const double       w = points[q].JxW;
            for (unsigned int k = 0; k < 3; ++k)
              sums[4 * s + k] += v[k] * w;
            sums[4 * s + 3] += w;
          }
      }
    dealii::Utilities::MPI::sum(sums, data.comm, sums);
    SegmentValues means;
    for (unsigned int s = 0; s < 17; ++s)
      for (unsigned int k = 0; k < 3; ++k)
        means[s][k] = sums[4 * s + 3] > 0
                        ? sums[4 * s + k] / sums[4 * s + 3]
                        : std::numeric_limits<double>::quiet_NaN();
    return means;
  }

  std::string
  AhaRegional::column_prefix(const unsigned int segment)
  {
    char prefix[16];
    std::snprintf(prefix, sizeof(prefix), "aha_%02u_", segment);
    return prefix;
  }

  void
  update_peak(double &peak, const double value)
  {
    if (!std::isfinite(peak) || std::abs(value) > std::abs(peak))
      peak = value;
  }

  void
  update_peaks(AhaRegional::SegmentValues       &peaks,
               const AhaRegional::SegmentValues &values)
  {
    for (unsigned int s = 0; s < 17; ++s)
      for (unsigned int k = 0; k < 3; ++k)
        update_peak(peaks[s][k], values[s][k]);
  }

  void
  AhaRegional::step(const StepData &data, std::vector<IO::Column> &row)
  {
    (void)row;
    update_peaks(peaks, segment_means(data));
  }

  void
  AhaRegional::end_beat(
    const StepData                         &data,
    const std::vector<std::vector<double>> *activation_times,
    std::vector<IO::Column>                &row)
  {
    std::vector<double> sums(17 * 2, 0.0);
    if (activation_times != nullptr)
      for (unsigned int c = 0; c < data.points->size(); ++c)
        {
          const auto &points = (*data.points)[c];
          if (points.empty() || !data.in_wall(c))
            continue;
          for (unsigned int q = 0; q < points.size(); ++q)
            {
              const unsigned int s = (*data.point_segments)[c][q] - 1;
              const double       t = (*activation_times)[c][q];
              if (!std::isfinite(t))
                continue;
              sums[2 * s] += t * points[q].JxW;
              sums[2 * s + 1] += points[q].JxW;
            }
        }
    dealii::Utilities::MPI::sum(sums, data.comm, sums);
    static const char *components[3] = {"circumferential",
                                        "longitudinal",
                                        "radial"};
    for (unsigned int s = 0; s < 17; ++s)
      {
        const std::string prefix = column_prefix(s + 1);
        for (unsigned int k = 0; k < 3; ++k)
          row.push_back(
            {prefix + "peak_strain_" + components[k], "-", peaks[s][k]});
        row.push_back({prefix + "activation_time",
                       "ms",
                       sums[2 * s + 1] > 0
                         ? sums[2 * s] / sums[2 * s + 1]
                         : std::numeric_limits<double>::quiet_NaN()});
      }
    reset();
  }

  void
  AhaRegional::reset()
  {
    for (auto &p : peaks)
      p.fill(std::numeric_limits<double>::quiet_NaN());
  }

  AhaRegional::AhaRegional()
  {
    reset();
  }

  std::vector<double>
  AhaRegional::state() const
  {
    std::vector<double> values;
    for (const auto &segment : peaks)
      values.insert(values.end(), segment.begin(), segment.end());
    return values;
  }


  void
  AhaRegional::set_state(const std::vector<double> &values)
  {
    AssertThrow(values.size() == 17 * 3,
                dealii::ExcMessage("AhaRegional: a state of 51 numbers "
                                   "expected."));
    for (unsigned int s = 0; s < 17; ++s)
      for (unsigned int k = 0; k < 3; ++k)
        peaks[s][k] = values[3 * s + k];
  }
} // namespace systole::Postprocess
