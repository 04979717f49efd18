#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace systole::Circulation
{
  /// A heart chamber as a time-varying elastance (Regazzoni et al. 2022,
  /// reference/physiology.md "Closed-loop circulation"):
  /// @f[ p = E(t)\,(V - V_0),\qquad E(t) = E_B + E_A\, e(t), @f]
  /// @f[ e(t) = \tfrac12\left(1 - \cos\frac{\pi \tau}{T_C}\right)
  ///     \ (0 \le \tau < T_C),\quad
  ///     \tfrac12\left(1 + \cos\frac{\pi(\tau - T_C)}{T_R}\right)
  ///     \ (T_C \le \tau < T_C + T_R),\quad 0\ \text{else}, @f]
  /// with τ = (t - t_C) mod T in [0, T): the activation may wrap around the
  /// end of the beat (the atria contract from 700 ms into an 800 ms beat
  /// for 340 ms). e is C^1 in time. Internal units.
  class ChamberElastance
  {
  public:
    struct Parameters
    {
      double active_elastance;     ///< E_A [kPa/mm^3], >= 0
      double passive_elastance;    ///< E_B [kPa/mm^3], > 0
      double contraction_onset;    ///< t_C [ms] (taken modulo the period)
      double contraction_duration; ///< T_C [ms], > 0
      double relaxation_duration;  ///< T_R [ms], > 0, T_C + T_R <= T
      double unloaded_volume;      ///< V_0 [mm^3], >= 0
      double initial_volume;       ///< V(0) [mm^3], > 0

      /// From the units of the parameter file: elastances in mmHg/mL,
      /// times in ms, volumes in mL.
      static Parameters
      from_file_units(const double active_elastance_mmHg_per_mL,
                      const double passive_elastance_mmHg_per_mL,
                      const double contraction_onset_ms,
                      const double contraction_duration_ms,
                      const double relaxation_duration_ms,
                      const double unloaded_volume_mL,
                      const double initial_volume_mL);

      /// Declares the entries (Active elastance, Passive elastance,
      /// Contraction onset, Contraction duration, Relaxation duration,
      /// Unloaded volume, Initial volume) in the current subsection, with
      /// @p defaults as default values (in file units). @p chamber names the
      /// chamber in the help texts ("left atrium").
      static void
      declare(dealii::ParameterHandler &prm,
              const Parameters         &defaults,
              const std::string        &chamber);

      /// Reads the entries of subsection @p path (as declared by
      /// declare()), converted to internal units, unvalidated.
      static Parameters
      parse(const dealii::ParameterHandler &prm,
            const std::vector<std::string> &path);

      /// Throws ExcMessage naming "@p where / <entry>" for a value out of
      /// range, including an activation longer than the @p period [ms].
      void
      validate(const std::string &where, const double period) const;
    };

    /// @param[in] period length of the beat T [ms]; validates.
    ChamberElastance(const Parameters &parameters, const double period);

    /// e(t) in [0, 1].
    double
    activation(const double t) const;

    /// E(t) [kPa/mm^3].
    double
    elastance(const double t) const;

    /// p = E(t) (V - V_0) [kPa]; dp/dV = E(t).
    double
    pressure(const double t, const double volume) const;

    const Parameters &
    parameters() const
    {
      return params;
    }

  private:
    Parameters params;
    double     period;
  };

  /// The chambers of the closed loop of reference/physiology.md (Regazzoni
  /// et al. 2022 defaults, period 800 ms; the atria start at 700 ms, 200 ms
  /// before the ventricles of the next beat), with their initial volumes.
  ChamberElastance::Parameters
  default_left_atrium();
  ChamberElastance::Parameters
  default_right_atrium();
  ChamberElastance::Parameters
  default_left_ventricle();
  ChamberElastance::Parameters
  default_right_ventricle();
} // namespace systole::Circulation
