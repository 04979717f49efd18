#pragma once

#include "base/units.h"

/// @file
/// The afterload: a 2- or 3-element Windkessel model of the systemic
/// arteries, in internal units (kPa, ms, mm^3).

namespace systole::Circulation
{
  /// Resistance from mmHg s/mL (parameter files) to kPa ms/mm^3 (internal):
  /// 1 mmHg s/mL = 0.133322 kPa x 1000 ms / 1000 mm^3 = 0.133322 kPa ms/mm^3.
  constexpr double
  resistance_from_mmHg_s_per_mL(const double r)
  {
    return r * Units::mmHg * Units::second / Units::mL;
  }

  /// Compliance from mL/mmHg (parameter files) to mm^3/kPa (internal):
  /// 1 mL/mmHg = 1000 / 0.133322 mm^3/kPa = 7500.6 mm^3/kPa.
  constexpr double
  compliance_from_mL_per_mmHg(const double c)
  {
    return c * Units::mL / Units::mmHg;
  }

  /// Flow from mm^3/ms (internal) to mL/s (output): 1 mm^3/ms = 1 mL/s.
  constexpr double
  flow_to_mL_per_s(const double q)
  {
    return q / Units::mL * Units::second;
  }

  /// Flow from mL/s (parameter files) to mm^3/ms (internal).
  constexpr double
  flow_from_mL_per_s(const double q)
  {
    return q * Units::mL / Units::second;
  }

  /// Elastance from mmHg/mL (parameter files) to kPa/mm^3 (internal):
  /// 1 mmHg/mL = 0.133322 kPa / 1000 mm^3.
  constexpr double
  elastance_from_mmHg_per_mL(const double e)
  {
    return e * Units::mmHg / Units::mL;
  }

  /// Inductance (inertance) from mmHg s^2/mL (parameter files) to
  /// kPa ms^2/mm^3 (internal): 1 mmHg s^2/mL = 0.133322 kPa x 10^6 ms^2 /
  /// 1000 mm^3 = 133.322 kPa ms^2/mm^3.
  constexpr double
  inductance_from_mmHg_s2_per_mL(const double l)
  {
    return l * Units::mmHg * Units::second * Units::second / Units::mL;
  }

  /// The Windkessel model of the systemic arteries with one state, the
  /// distal (capacitor) pressure p_ar:
  /// @f[ C \frac{dp_{ar}}{dt} = Q_{ao} - \frac{p_{ar} - p_{ven}}{R_p},
  ///     \qquad Q_{ao} = \frac{p - p_{ar}}{R_s}\ \text{(aortic valve open)}
  /// @f]
  /// with p the cavity pressure. The series resistance R_s between cavity and
  /// capacitor is the characteristic impedance Z_c in the 3-element model
  /// (the valve itself is ideal) and the aortic valve resistance R_av in the
  /// 2-element model. The aortic root pressure is p_ar + R_s Q_ao. This is
  /// the 4-element law of reference/physiology.md with L = 0 (3-element) and
  /// additionally Z_c = 0 (2-element, the valve resistance taking its place).
  class Windkessel
  {
  public:
    enum class Model
    {
      two_element,
      three_element
    };

    /// Constants in internal units; the defaults are those of the parameter
    /// file (Circulation::Parameters), converted.
    struct Parameters
    {
      Model model = Model::three_element;
      /// R_p [kPa ms/mm^3]
      double peripheral_resistance = resistance_from_mmHg_s_per_mL(1.0);
      /// C [mm^3/kPa]
      double compliance = compliance_from_mL_per_mmHg(1.5);
      /// Z_c [kPa ms/mm^3] (3-element model only)
      double characteristic_impedance = resistance_from_mmHg_s_per_mL(0.05);
      /// R_av [kPa ms/mm^3] (2-element model only)
      double aortic_valve_resistance = resistance_from_mmHg_s_per_mL(0.0075);
      /// p_ven [kPa], the pressure at the outflow end of R_p
      double venous_pressure = 0.0;
    };

    explicit Windkessel(const Parameters &parameters);

    /// R_s [kPa ms/mm^3]: Z_c (3-element) or R_av (2-element).
    double
    series_resistance() const;

    /// Aortic outflow Q_ao = (p - p_ar) / R_s [mm^3/ms] through the open
    /// valve, for cavity pressure @p p and distal pressure @p p_ar [kPa]. The
    /// caller decides whether the valve is open.
    double
    outflow(const double p, const double p_ar) const;

    /// dp_ar/dt [kPa/ms] for distal pressure @p p_ar [kPa] and aortic
    /// outflow @p q_ao [mm^3/ms].
    double
    pressure_rate(const double p_ar, const double q_ao) const;

    /// Aortic root pressure p_ar + R_s Q_ao [kPa].
    double
    root_pressure(const double p_ar, const double q_ao) const;

    const Parameters &
    parameters() const
    {
      return params;
    }

  private:
    const Parameters params;
  };
} // namespace systole::Circulation
