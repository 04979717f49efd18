#include "inverse/klotz.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <cmath>

namespace systole::Inverse
{
  KlotzCurve::KlotzCurve(const double edp_mmHg, const double edv_mL)
  {
    AssertThrow(edp_mmHg > 0 && edp_mmHg < 100 && edv_mL > 0,
                dealii::ExcMessage(
                  "Klotz's EDPVR needs an end-diastolic pressure in (0, 100) "
                  "mmHg (V_0 is not positive above) and a positive volume "
                  "(got " +
                  dealii::Utilities::to_string(edp_mmHg) + " mmHg, " +
                  dealii::Utilities::to_string(edv_mL) +
                  " mL): set Calibration / Klotz end-diastolic pressure and "
                  "volume."));
    // Klotz et al. 2006, eq. for V0: 0.006 per mmHg of the measured EDP.
    v0  = edv_mL * (0.6 - 0.006 * edp_mmHg);
    v30 = v0 + (edv_mL - v0) / std::pow(edp_mmHg / A_n, 1.0 / B_n);
  }

  double
  KlotzCurve::volume_mL(const double p_mmHg) const
  {
    AssertThrow(p_mmHg >= 0,
                dealii::ExcMessage("Klotz's EDPVR: negative pressure " +
                                   dealii::Utilities::to_string(p_mmHg) +
                                   " mmHg."));
    return v0 + (v30 - v0) * std::pow(p_mmHg / A_n, 1.0 / B_n);
  }

  double
  KlotzCurve::pressure_mmHg(const double v_mL) const
  {
    AssertThrow(v_mL >= v0,
                dealii::ExcMessage("Klotz's EDPVR: the volume " +
                                   dealii::Utilities::to_string(v_mL) +
                                   " mL is below V_0."));
    return A_n * std::pow((v_mL - v0) / (v30 - v0), B_n);
  }
} // namespace systole::Inverse
