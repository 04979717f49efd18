#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace systole::Materials
{
  /// The Bestel-type active tension law (Bestel, Clement, Sorine 2001; as in
  /// Regazzoni et al.): per point,
  /// @f[ \dot\tau = -|a(t)|\,\tau + \sigma_0 \max(a(t), 0),\qquad
  ///     a(t) = a_{max} f(t) + a_{min}(1 - f(t)),\quad
  ///     f = S^+(t - t_{sys}) S^-(t - t_{dias}),\quad
  ///     S^\pm(\Delta) = \tfrac12 (1 \pm \tanh(\Delta/\gamma)) @f]
  /// with t the time since the point's activation, periodic with the beat
  /// period. The law is linear in tau and driven by time alone, so every
  /// point follows one reference curve shifted by its activation time: the
  /// curve is integrated once (classical RK4, step 0.01 ms, over two periods
  /// from tau = 0; the second period is tabulated, so the table is the
  /// periodic solution) and interpolated linearly. The tension acts as the
  /// second Piola-Kirchhoff stress T_a f0 x f0 (Materials::add_active_stress).
  class Bestel
  {
  public:
    /// Subsection "Active tension" (internal units: kPa, ms).
    struct Parameters
    {
      double contractility = 100.0;  ///< sigma_0 [kPa]
      double a_max         = 5e-3;   ///< [1/ms]
      double a_min         = -30e-3; ///< [1/ms]
      double t_sys         = 160.0;  ///< [ms]
      double t_dias        = 484.0;  ///< [ms]
      double gamma         = 5.0;    ///< [ms]
      /// "electrophysiology" (the latest upstroke of the monodomain
      /// model), or prescribed: "uniform" (every point activates at 0) or
      /// "apex-to-base" (growing linearly with the height above the apex).
      std::string activation_map   = "apex-to-base";
      double      activation_delay = 30.0; ///< apex-to-base delay [ms]

      static void
      declare(dealii::ParameterHandler &prm);
      /// Parses and validates (throws ExcMessage naming the entry).
      static Parameters
      parse(const dealii::ParameterHandler &prm);
    };

    /// @param[in] period beat period [ms]
    Bestel(const Parameters &params, const double period);

    /// The tension [kPa] at @p time [ms] of a point activated at
    /// @p activation_time [ms] in every beat (beat k activates at
    /// k period + activation_time). Zero before the first activation.
    double
    tension(const double time, const double activation_time) const;

    /// The activation function a(t) [1/ms], t since activation in the beat.
    double
    activation(const double t) const;

    /// The earliest time in a beat (since activation) at which the tension
    /// starts to rise: where a(t) becomes positive [ms].
    double
    onset() const;

    const Parameters &
    parameters() const;

  private:
    Parameters          params;
    double              period;
    double              table_step;
    std::vector<double> table; ///< tau over one period, periodic solution
  };
} // namespace systole::Materials
