#pragma once

#include "postprocess/postprocessor.h"

namespace systole::Postprocess
{
  /// The shape of the left ventricle at one step, from the vertices and the
  /// points of its wall (LvWall: the whole mesh of a left ventricle, the LV
  /// free wall and the septum of two ventricles; ventricle_shape()).
  struct VentricleShape
  {
    /// The deformed epicardial apex (the vertex at the reference apex) [mm].
    dealii::Point<3> apex;
    /// The mean deformed position of the LV wall's base vertices (of two
    /// ventricles: the mitral side, without the RV free wall) [mm].
    dealii::Point<3> base;
    /// The mean rotation [rad] from the reference about the long axis
    /// (counter-clockwise seen from the apex) of the vertices of the apical
    /// and of the basal ring (AHA levels), each ring about the axis through
    /// its centroid (a translation does not rotate).
    double apical_rotation = 0, basal_rotation = 0;
    /// The mean wall thickness T = 2 V_wall / (A_endo + A_epi) [mm]: the
    /// deformed wall volume over the mean of the deformed endocardial and
    /// outer areas (for two ventricles the LV wall's: its cells, bounded by
    /// the LV endocardium, the epicardium and the septum's RV side).
    double thickness = 0;
  };

  /// The shape of the ventricle of @p data (needs the segments, vertices and
  /// areas). Collective; throws if the mesh has no apex vertex, base
  /// vertices or vertices in the apical and basal rings.
  VentricleShape
  ventricle_shape(const StepData &data);

  /// Global measures of the ventricle every step ("ventricle function"),
  /// against the first step (the reference state), from ventricle_shape():
  /// - long_axis_shortening = 1 - L / L0, L the distance along the long axis
  ///   from the deformed epicardial apex to the mean deformed base vertex;
  /// - wall_thickening = T / T0 - 1, T the mean wall thickness;
  /// - torsion = theta_apical - theta_basal [deg], the mean rotation of the
  ///   apical ring minus that of the basal ring;
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
