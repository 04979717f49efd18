#pragma once

#include "circulation/ventricle.h"

namespace systole::Circulation
{
  /// The 0D surrogate of the ventricle: a time-varying elastance,
  /// @f[ p = E(t)\,(V - V_0),\qquad
  ///     E(t) = E_{min} + (E_{max} - E_{min})\, e(t \bmod T), @f]
  /// with a raised-cosine activation that rises from 0 at the contraction
  /// onset t_c to 1 over the contraction duration T_c and falls back to 0
  /// over the relaxation duration T_r (C^1 in time; Regazzoni et al. 2022):
  /// @f[ e(\tau) = \tfrac12\left(1 - \cos\frac{\pi(\tau - t_c)}{T_c}\right)
  ///     \ \text{on}\ [t_c, t_c + T_c],\quad
  ///     \tfrac12\left(1 + \cos\frac{\pi(\tau - t_c - T_c)}{T_r}\right)
  ///     \ \text{on}\ [t_c + T_c, t_c + T_c + T_r],\quad 0\ \text{else}. @f]
  /// Used by the tests and as a cheap stand-in for the 3D ventricle.
  class ElastanceVentricle : public Ventricle
  {
  public:
    /// All in internal units.
    struct Parameters
    {
      double minimum_elastance;    ///< E_min [kPa/mm^3]
      double maximum_elastance;    ///< E_max [kPa/mm^3]
      double unloaded_volume;      ///< V_0 [mm^3]
      double period;               ///< T [ms]
      double contraction_onset;    ///< t_c within the beat [ms]
      double contraction_duration; ///< T_c, onset to peak [ms]
      double relaxation_duration;  ///< T_r, peak to rest [ms]
    };

    /// Throws ExcMessage for non-positive elastances or durations, or an
    /// activation that does not fit into one period.
    explicit ElastanceVentricle(const Parameters &parameters);

    /// p = E(t) (V - V_0) [kPa]. Counts the calls.
    double
    pressure(const double t, const double volume) override;

    /// e(t mod T) in [0, 1].
    double
    activation(const double t) const;

    /// E(t) [kPa/mm^3].
    double
    elastance(const double t) const;

    /// Number of pressure() calls so far.
    unsigned long
    n_calls() const
    {
      return calls;
    }

  private:
    const Parameters params;
    unsigned long    calls = 0;
  };
} // namespace systole::Circulation
