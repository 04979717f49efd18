#pragma once

#include "materials/bestel.h"
#include "materials/tension_model.h"

namespace systole::Materials
{
  /// The Bestel law (materials/bestel.h) as a tension model: the tabulated
  /// periodic curve started at each point's activation time, prescribed or
  /// from the electrophysiology. No state and no stretch dependence
  /// (dT/dλ = 0).
  class BestelTension : public TensionModel
  {
  public:
    static constexpr const char *model_name = "Bestel";

    /// @param[in] period beat period [ms]
    BestelTension(const Bestel::Parameters &params, const double period);

    void
    initial_state(double *state) const override;
    /// T = Bestel::tension(time, activation time), 0 while the point is not
    /// activated (activation time NaN).
    void
    step(const double       *accepted,
         const TensionInput &in,
         double             *trial,
         TensionOutput      &out) const override;
    /// Not defined without a time: throws.
    double
    tension_of_state(const double *state, const double stretch) const override;

    /// The Bestel curve's onset [ms].
    double
    onset_delay() const override;

    /// The underlying curve.
    const Bestel &
    law() const;

  private:
    Bestel bestel;
  };
} // namespace systole::Materials
