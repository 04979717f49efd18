#pragma once

/// @file
/// The one unit system used inside Systole: millimetre, millisecond,
/// kilopascal. Derived: volume mm^3, energy kPa mm^3 (= µJ), conductivity
/// mS/mm. Conversions happen only at input/output boundaries, with the factors
/// below.

namespace systole::Units
{
  /// Pressure: 1 mmHg in kPa.
  constexpr double mmHg = 0.133322387415;
  /// Volume: 1 mL in mm^3.
  constexpr double mL = 1000.0;
  /// Time: 1 s in ms.
  constexpr double second = 1000.0;

  constexpr double
  kPa_to_mmHg(const double p)
  {
    return p / mmHg;
  }
  constexpr double
  mmHg_to_kPa(const double p)
  {
    return p * mmHg;
  }
  constexpr double
  mm3_to_mL(const double v)
  {
    return v / mL;
  }
  constexpr double
  mL_to_mm3(const double v)
  {
    return v * mL;
  }
} // namespace systole::Units
