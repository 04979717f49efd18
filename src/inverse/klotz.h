#pragma once

namespace systole::Inverse
{
  /// The empirical end-diastolic pressure-volume relation of Klotz et al.
  /// 2006 (Am. J. Physiol. Heart Circ. Physiol. 291:H403), built from one
  /// measured pair (EDP_m [mmHg], V_m [mL]):
  /// @f[ V_0 = V_m (0.6 - 0.006 V_m), \quad
  ///     V_{30} = V_0 + \frac{V_m - V_0}{(EDP_m / A_n)^{1/B_n}}, \quad
  ///     EDP = A_n \left(\frac{V - V_0}{V_{30} - V_0}\right)^{B_n} @f]
  /// with A_n = 27.78 mmHg, B_n = 2.76 (the normalised curve; V_0 and
  /// V_m in mL, so V_0 is negative for V_m > 100 mL: the regression's own
  /// form, kept as published). Units at this I/O boundary: mmHg and mL.
  class KlotzCurve
  {
  public:
    static constexpr double A_n = 27.78; ///< [mmHg]
    static constexpr double B_n = 2.76;  ///< [-]

    /// @param[in] edp_mmHg measured end-diastolic pressure (> 0)
    /// @param[in] edv_mL measured end-diastolic volume (> 0)
    /// Throws ExcMessage on a non-positive value.
    KlotzCurve(const double edp_mmHg, const double edv_mL);

    /// V_0 [mL], the volume at zero pressure.
    double
    v0_mL() const
    {
      return v0;
    }

    /// V_30 [mL], the normalising volume of the curve (which reaches it at
    /// EDP = A_n = 27.78 mmHg, as the formulas are quoted).
    double
    v30_mL() const
    {
      return v30;
    }

    /// The volume [mL] at pressure @p p_mmHg (>= 0) [mmHg].
    double
    volume_mL(const double p_mmHg) const;

    /// The pressure [mmHg] at volume @p v_mL (>= V_0) [mL].
    double
    pressure_mmHg(const double v_mL) const;

  private:
    double v0  = 0;
    double v30 = 0;
  };
} // namespace systole::Inverse
