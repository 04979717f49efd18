#include "circulation/elastance_ventricle.h"

#include <deal.II/base/exceptions.h>

#include <cmath>

namespace systole::Circulation
{
  ElastanceVentricle::ElastanceVentricle(const Parameters &parameters)
    : params(parameters)
  {
    const auto &p = params;
    AssertThrow(p.minimum_elastance > 0 &&
                  p.maximum_elastance >= p.minimum_elastance,
                dealii::ExcMessage("ElastanceVentricle: need 0 < E_min <= "
                                   "E_max."));
    AssertThrow(p.period > 0 && p.contraction_duration > 0 &&
                  p.relaxation_duration > 0 && p.contraction_onset >= 0 &&
                  p.contraction_onset + p.contraction_duration +
                      p.relaxation_duration <=
                    p.period,
                dealii::ExcMessage(
                  "ElastanceVentricle: need positive durations and onset + "
                  "contraction + relaxation within one period."));
  }

  double
  ElastanceVentricle::activation(const double t) const
  {
    const auto  &p   = params;
    const double tau = std::fmod(t, p.period) - p.contraction_onset;
    if (tau <= 0)
      return 0.0;
    if (tau < p.contraction_duration)
      return 0.5 * (1.0 - std::cos(M_PI * tau / p.contraction_duration));
    const double tau_r = tau - p.contraction_duration;
    if (tau_r < p.relaxation_duration)
      return 0.5 * (1.0 + std::cos(M_PI * tau_r / p.relaxation_duration));
    return 0.0;
  }

  double
  ElastanceVentricle::elastance(const double t) const
  {
    return params.minimum_elastance +
           (params.maximum_elastance - params.minimum_elastance) *
             activation(t);
  }

  double
  ElastanceVentricle::pressure(const double t, const double volume)
  {
    ++calls;
    return elastance(t) * (volume - params.unloaded_volume);
  }
} // namespace systole::Circulation
