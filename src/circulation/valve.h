#pragma once

/// @file
/// The non-ideal diode valve of the 0D circulation models.

namespace systole::Circulation
{
  /// A valve as a non-ideal diode (Regazzoni et al. 2022): Q = Δp / R(Δp)
  /// with Δp = p_upstream - p_downstream and R = R_min while Δp > 0 (open),
  /// R_max otherwise (closed, a small leak). Q is continuous in Δp (0 at
  /// Δp = 0), its derivative jumps there. Internal units: kPa ms/mm^3,
  /// kPa, mm^3/ms.
  struct DiodeValve
  {
    double open_resistance;   ///< R_min [kPa ms/mm^3]
    double closed_resistance; ///< R_max [kPa ms/mm^3]

    /// R(Δp) [kPa ms/mm^3].
    double
    resistance(const double dp) const
    {
      return dp > 0 ? open_resistance : closed_resistance;
    }

    /// Q = Δp / R(Δp) [mm^3/ms].
    double
    flow(const double dp) const
    {
      return dp / resistance(dp);
    }

    /// dQ/dΔp = 1 / R(Δp) [mm^3/(ms kPa)].
    double
    conductance(const double dp) const
    {
      return 1.0 / resistance(dp);
    }
  };
} // namespace systole::Circulation
