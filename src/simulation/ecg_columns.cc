#include "simulation/ecg_columns.h"

#include <algorithm>
#include <limits>

namespace systole
{
  void
  append_ecg_columns(const std::array<double, 12> &leads,
                     std::vector<IO::Column>      &row)
  {
    const auto &names = Electrophysiology::lead_names();
    for (unsigned int l = 0; l < 12; ++l)
      row.push_back({"ecg_" + names[l], "mV", leads[l]});
  }


  void
  EcgBeat::add(const double time, const std::array<double, 12> &values)
  {
    if (!times.empty() && time <= times.back())
      return;
    times.push_back(time);
    leads.push_back(values);
  }


  void
  EcgBeat::append_biomarkers(const double             start,
                             const double             end,
                             const double             threshold,
                             std::vector<IO::Column> &row) const
  {
    std::vector<double>                 t;
    std::vector<std::array<double, 12>> v;
    const double                        tolerance = 1e-9 * (1 + std::abs(end));
    for (unsigned int k = 0; k < times.size(); ++k)
      if (times[k] >= start - tolerance && times[k] <= end + tolerance)
        {
          t.push_back(times[k] - start);
          v.push_back(leads[k]);
        }
    Electrophysiology::EcgBiomarkers b;
    if (t.size() >= 3)
      b = Electrophysiology::ecg_biomarkers(t, v, threshold);
    else
      {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        b.qrs_onset = b.qrs_duration = b.t_end = b.qt_interval = nan;
        b.r_amplitude.fill(nan);
      }
    row.push_back({"ecg_QRS_onset", "ms", b.qrs_onset});
    row.push_back({"ecg_QRS_duration", "ms", b.qrs_duration});
    row.push_back({"ecg_T_end", "ms", b.t_end});
    row.push_back({"ecg_QT_interval", "ms", b.qt_interval});
    const auto &names = Electrophysiology::lead_names();
    for (unsigned int l = 0; l < 12; ++l)
      row.push_back({"ecg_R_amplitude_" + names[l], "mV", b.r_amplitude[l]});
  }


  void
  EcgBeat::forget_before(const double time)
  {
    unsigned int k = 0;
    while (k < times.size() && times[k] < time)
      ++k;
    times.erase(times.begin(), times.begin() + k);
    leads.erase(leads.begin(), leads.begin() + k);
  }


  std::array<double, 12>
  EcgBeat::at(const double time) const
  {
    AssertThrow(!times.empty(), dealii::ExcInternalError());
    const auto upper = std::lower_bound(times.begin(), times.end(), time);
    if (upper == times.begin())
      return leads.front();
    if (upper == times.end())
      return leads.back();
    const unsigned int k = upper - times.begin();
    const double       s = (time - times[k - 1]) / (times[k] - times[k - 1]);
    std::array<double, 12> out;
    for (unsigned int l = 0; l < 12; ++l)
      out[l] = (1 - s) * leads[k - 1][l] + s * leads[k][l];
    return out;
  }
} // namespace systole
