#pragma once

namespace systole::Inverse
{
  /// The empirical end-diastolic pressure-volume relation of Klotz et al.
  /// 2006 (Am. J. Physiol. Heart Circ. Physiol. 291:H403; the recipe again
  /// in Klotz, Dickstein & Burkhoff 2007, Nature Protocols 2:2152), built
  /// from one measured pair (EDP_m [mmHg], V_m [mL]):
  /// @f[ V_0 = V_m (0.6 - 0.006\,EDP_m), \quad
  ///     V_{30} = V_0 + \frac{V_m - V_0}{(EDP_m / A_n)^{1/B_n}}, \quad
  ///     EDP = A_n \left(\frac{V - V_0}{V_{30} - V_0}\right)^{B_n} @f]
  /// with A_n = 27.78 mmHg, B_n = 2.76 (the normalised curve). The factor
  /// 0.006 is per mmHg of EDP_m, so 0 < V_0 < V_m for EDP_m < 100 mmHg.
  /// (../shared/reference/physiology.md quotes V_0 = V_m (0.6 - 0.006 V_m),
  /// with V_m where both papers have EDP_m: a typo, which this class
  /// once followed, giving V_0 = 2.4 mL for a 95.8 mL ventricle and a
  /// negative V_0 above 100 mL.) Units at this I/O boundary: mmHg and mL.
  class KlotzCurve
  {
  public:
    static constexpr double A_n = 27.78; ///< [mmHg]
    static constexpr double B_n = 2.76;  ///< [-]

    /// @param[in] edp_mmHg measured end-diastolic pressure (> 0, < 100)
    /// @param[in] edv_mL measured end-diastolic volume (> 0)
    /// Throws ExcMessage on a value outside those ranges.
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
