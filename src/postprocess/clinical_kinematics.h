#pragma once

#include <deal.II/base/tensor.h>

#include "postprocess/aha_regional.h"
#include "postprocess/postprocessor.h"
#include "postprocess/ventricle_function.h"

#include <array>
#include <string>
#include <vector>

namespace systole::Postprocess
{
  /// The kinematics of the left ventricle as echocardiography and MRI
  /// report them ("clinical kinematics"), referred to the end-diastolic (ED)
  /// state of each beat (docs/architecture.md, "Clinical kinematics"). The
  /// wall is the LV wall of StepData::in_wall() (of two ventricles: the LV
  /// free wall and the septum), its rings, apex and base those of
  /// VentricleShape, the volume that of the LV cavity.
  ///
  /// Strain along a unit direction e of the cardiac frame in the ED
  /// configuration: the Lagrangian engineering strain referred to ED,
  /// @f$\varepsilon = |F F_{ED}^{-1} e| - 1@f$ (Voigt et al. 2015, J. Am.
  /// Soc. Echocardiogr. 28:183), so that the Green-Lagrange strain referred
  /// to ED is @f$((1 + \varepsilon)^2 - 1) / 2@f$. The ED frame at a point
  /// of reference frame (E_c, E_l, E_r): e_c = F_ED E_c / |F_ED E_c| (the
  /// circumferential material line), e_r = F_ED^-T E_r / |F_ED^-T E_r| (the
  /// ED wall normal, orthogonal to e_c), e_l = e_r x e_c (in the ED wall,
  /// orthogonal to e_c).
  ///
  /// /timeseries every step, referred to the current beat's ED:
  /// - global_{longitudinal,circumferential,radial}_strain: the mean over
  ///   the wall, weighted by the points' reference volume;
  /// - endocardial_{longitudinal,circumferential,radial}_strain: the same
  ///   over the inner third of the wall (transmural coordinate < 1/3);
  /// - twist [deg]: the rotation of the apical ring minus that of the basal
  ///   ring since ED (VentricleShape), counter-clockwise seen from the apex;
  /// - torsion_per_length [deg/mm]: twist over the ED distance from the
  ///   epicardial apex to the mean base vertex;
  /// - av_plane_displacement [mm]: the motion of the mean base vertex since
  ///   ED along the ED long axis (apex to mean base vertex), positive
  ///   toward the apex;
  /// - apex_displacement [mm]: the distance of the epicardial apex from its
  ///   ED position;
  /// - wall_thickening_ed [-]: T / T_ED - 1, T the mean wall thickness of
  ///   VentricleShape.
  ///
  /// /summary per beat: peak_<column> for each of these (the value of
  /// largest magnitude, with its sign, from the beat's ED on),
  /// end_diastolic_time [ms in the beat], and
  /// aha_NN_peak_ed_strain_{circumferential,longitudinal,radial}: the peak
  /// of the segment's mean strain referred to ED (NN = 01 ... 17).
  ///
  /// End-diastole: the closure of the mitral valve. Where the circulation
  /// says whether the ventricle fills (StepData::filling, the heartbeat):
  /// the first step of each beat, every filling step after it, and the step
  /// that ends the filling; if the valve reopens before the ejection (the
  /// base springs of `end-diastole` released at the closure), the filling
  /// moves ED on to its last closure; once the volume has fallen more than
  /// fall_tolerance below the ED volume, ED stays until the next beat. (The
  /// volume creeps on in the isovolumic phases with the leaks of the closed
  /// valves.) Without that: the first step of each beat, then every step
  /// whose cavity volume exceeds the ED volume by more than rise_tolerance
  /// of it, until the volume has once fallen below the ED volume by more
  /// than fall_tolerance of it. Without a cavity (NaN volume): the first
  /// step of each beat. Each new ED restarts the peaks.
  class ClinicalKinematics : public Postprocessor
  {
  public:
    /// A rise of the volume that moves ED, relative to the ED volume: above
    /// the solver's noise in the isovolumic phases (about 1e-9).
    static constexpr double rise_tolerance = 1e-6;
    /// A fall of the volume that fixes ED for the rest of the beat,
    /// relative to the ED volume.
    static constexpr double fall_tolerance = 1e-2;
    /// The endocardial layer: transmural coordinate below this.
    static constexpr double endocardial_layer = 1.0 / 3;

    ClinicalKinematics();

    Needs
    needs() const override;

    void
    step(const StepData &data, std::vector<IO::Column> &row) override;

    void
    end_beat(const StepData                         &data,
             const std::vector<std::vector<double>> *activation_times,
             std::vector<IO::Column>                &row) override;

    /// The ED state and the peaks so far, and every point's ED directions
    /// with its reference position, gathered on rank 0 (collective).
    std::vector<double>
    state() const override;

    /// Restore what state() returned; the points find their ED directions
    /// by their reference positions at the next step() (where one does not,
    /// that step becomes the ED of the beat).
    void
    set_state(const std::vector<double> &values) override;

  private:
    static constexpr unsigned int n_columns = 11;

    /// Make the state of @p data the ED reference and restart the peaks.
    void
    take_reference(const StepData &data, const VentricleShape &shape);

    /// Restore the saved ED directions at the points of @p data; false
    /// (on every rank) if a point has none.
    bool
    restore_points(const StepData &data);

    /// No peaks yet (NaN).
    void
    reset_peaks();

    bool         has_reference = false;
    unsigned int beat          = 0;
    double       ed_volume     = 0;
    double       ed_time       = 0; ///< [ms in the beat]
    /// Where ED stands: moves with every step that takes it, held at a
    /// closure (it moves again if the ventricle refills before ejecting),
    /// fixed for the rest of the beat. Saved as 0, 0.5 and 1.
    enum class EdStage
    {
      moving,
      held,
      fixed
    };
    EdStage        ed_stage = EdStage::moving;
    VentricleShape ed_shape;
    /// Per point [cell][q]: F_ED^-1 e_k for the ED frame e_c, e_l, e_r, so
    /// that the stretch along e_k is |F F_ED^-1 e_k|.
    std::vector<std::vector<std::array<dealii::Tensor<1, 3>, 3>>> directions;
    /// The reference positions of the points of directions (for state()).
    std::vector<std::vector<dealii::Point<3>>> positions;
    std::array<double, n_columns>              peaks{};
    AhaRegional::SegmentValues                 segment_peaks{};
    /// set_state()'s points (X, three directions: 12 numbers each), until
    /// the next step() places them.
    std::vector<double> saved_points;
    /// Whether saved_points are still to be placed.
    bool     restoring = false;
    MPI_Comm comm      = MPI_COMM_WORLD;
  };
} // namespace systole::Postprocess
