#pragma once

#include "base/format.h"
#include "base/units.h"

#include <string>

/// @file
/// Unit conversions of the 0D circulation (resistances, compliances,
/// inductances, flows) and the Windkessel constants, internal units (kPa,
/// ms, mm^3).

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

  /// @p x with 10 significant digits: a default of a parameter entry, or a
  /// value in an error message, in the units of the parameter file.
  inline std::string
  format_value(const double x)
  {
    return format_number(x, 10);
  }

  /// The constants of the Windkessel afterloads of the 0D models
  /// (WindkesselModel, the 2-, 3- and 4-element laws of
  /// reference/physiology.md), in internal units; the defaults are those of
  /// the parameter file (Circulation::Parameters), converted.
  struct Windkessel
  {
    struct Parameters
    {
      /// R_p [kPa ms/mm^3]
      double peripheral_resistance = resistance_from_mmHg_s_per_mL(1.0);
      /// C [mm^3/kPa]
      double compliance = compliance_from_mL_per_mmHg(1.5);
      /// Z_c [kPa ms/mm^3] (3- and 4-element models)
      double characteristic_impedance = resistance_from_mmHg_s_per_mL(0.05);
      /// R_min of the aortic valve [kPa ms/mm^3]
      double aortic_valve_resistance = resistance_from_mmHg_s_per_mL(0.0075);
      /// p_ven [kPa], the pressure at the outflow end of R_p
      double venous_pressure = 0.0;
    };
  };
} // namespace systole::Circulation
