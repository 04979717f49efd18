#include "materials/bestel_tension.h"

#include <deal.II/base/exceptions.h>

#include <cmath>

namespace systole::Materials
{
  BestelTension::BestelTension(const Bestel::Parameters &params,
                               const double              period)
    : TensionModel(model_name, TensionDrive::activation_time, 0)
    , bestel(params, period)
  {}

  void
  BestelTension::initial_state(double *) const
  {}

  void
  BestelTension::step(const double *,
                      const TensionInput &in,
                      double *,
                      TensionOutput &out) const
  {
    // Not activated yet: at rest.
    out.tension           = std::isnan(in.activation_time)
                              ? 0.0
                              : bestel.tension(in.time, in.activation_time);
    out.dtension_dstretch = 0.0;
  }

  double
  BestelTension::tension_of_state(const double *, const double) const
  {
    AssertThrow(false,
                dealii::ExcMessage("The Bestel tension is a function of time "
                                   "and activation time, not of a state."));
    return 0.0;
  }

  const Bestel &
  BestelTension::law() const
  {
    return bestel;
  }

  double
  BestelTension::onset_delay() const
  {
    return law().onset();
  }
} // namespace systole::Materials
