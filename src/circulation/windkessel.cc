#include "circulation/windkessel.h"

#include <deal.II/base/exceptions.h>

namespace systole::Circulation
{
  Windkessel::Windkessel(const Parameters &parameters)
    : params(parameters)
  {
    AssertThrow(params.peripheral_resistance > 0 && params.compliance > 0 &&
                  series_resistance() > 0,
                dealii::ExcMessage(
                  "Windkessel: the peripheral resistance, the compliance and "
                  "the series resistance (characteristic impedance or aortic "
                  "valve resistance) must be positive."));
  }

  double
  Windkessel::series_resistance() const
  {
    return params.model == Model::three_element
             ? params.characteristic_impedance
             : params.aortic_valve_resistance;
  }

  double
  Windkessel::outflow(const double p, const double p_ar) const
  {
    return (p - p_ar) / series_resistance();
  }

  double
  Windkessel::pressure_rate(const double p_ar, const double q_ao) const
  {
    return (q_ao -
            (p_ar - params.venous_pressure) / params.peripheral_resistance) /
           params.compliance;
  }

  double
  Windkessel::root_pressure(const double p_ar, const double q_ao) const
  {
    return p_ar + series_resistance() * q_ao;
  }
} // namespace systole::Circulation
