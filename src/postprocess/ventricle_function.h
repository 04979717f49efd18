#pragma once

#include "postprocess/postprocessor.h"

namespace systole::Postprocess
{
  /// Global measures of the ventricle every step ("ventricle function"),
  /// against the first step (the reference state):
  /// - long_axis_shortening = 1 - L / L0, L the distance along the long axis
  ///   from the deformed epicardial apex to the mean deformed base vertex;
  /// - wall_thickening = T / T0 - 1, T = 2 V_wall / (A_endo + A_epi) the
  ///   mean wall thickness (deformed wall volume over the mean of the
  ///   deformed endocardial and epicardial areas);
  /// - torsion = theta_apical - theta_basal [deg], the mean rotation about
  ///   the long axis (counter-clockwise seen from the apex) of the vertices
  ///   of the apical ring minus that of the basal ring (AHA levels), each
  ///   ring about the axis through its centroid (a translation does not
  ///   rotate);
  /// - ejection_fraction = (V_max - V) / V_max, V_max the largest cavity
  ///   volume so far in the beat (NaN without a cavity).
  class VentricleFunction : public Postprocessor
  {
  public:
    Needs
    needs() const override;

    void
    step(const StepData &data, std::vector<IO::Column> &row) override;

    std::vector<double>
    state() const override;

    void
    set_state(const std::vector<double> &values) override;

  private:
    bool         initialized      = false;
    double       reference_length = 0, reference_thickness = 0;
    unsigned int beat       = 0;
    double       max_volume = 0;
  };
} // namespace systole::Postprocess
