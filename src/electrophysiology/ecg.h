#pragma once

#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>

#include "fibres/fibre_field.h"

#include <array>
#include <string>
#include <vector>

/// @file
/// The pseudo-ECG of the monodomain model: electrode potentials in an
/// infinite homogeneous volume conductor, the 12 standard leads and their
/// per-beat biomarkers.

namespace systole::Electrophysiology
{
  /// A named electrode [mm, the mesh's reference coordinates].
  struct Electrode
  {
    std::string      name;
    dealii::Point<3> position;
  };

  /// The names of the nine electrodes the 12 leads need: the limb
  /// electrodes RA, LA, LL and the precordial V1 ... V6.
  const std::vector<std::string> &
  electrode_names();

  /// The 12 leads in the usual order: I, II, III, aVR, aVL, aVF, V1 ... V6.
  const std::array<std::string, 12> &
  lead_names();

  /// Entries "ECG ..." of subsection Electrophysiology.
  struct EcgParameters
  {
    bool enabled = false; ///< compute the pseudo-ECG
    /// The nine electrodes of electrode_names(), in that order.
    std::vector<Electrode> electrodes;
    /// Conductivity of the infinite homogeneous medium around the heart
    /// sigma_b [mS/mm].
    double bath_conductivity = 0.2;
    /// Biomarkers: fraction of the peak RMS amplitude of the beat (the QRS
    /// core, widened to its first deflection and J point) and after the QRS
    /// (T-wave end) [-] (ecg_biomarkers()).
    double threshold = 0.1;

    /// Declares the ECG entries (inside subsection Electrophysiology).
    static void
    declare(dealii::ParameterHandler &prm);
    /// Reads them (inside subsection Electrophysiology, i.e. @p prm entered
    /// nowhere: the paths are given); throws naming the entry on bad
    /// electrodes.
    static EcgParameters
    parse(const dealii::ParameterHandler &prm);
  };

  /// Parse "name: x y z; name: x y z; ..." (the nine electrodes of
  /// electrode_names(), any order; commas may separate the coordinates).
  /// Returns them in the order of electrode_names(); throws naming the
  /// entry for a missing, unknown or repeated electrode.
  std::vector<Electrode>
  parse_electrodes(const std::string &text);

  /// The 12 leads [the units of @p phi] from the potentials @p phi of the
  /// nine electrodes (order of electrode_names()): Einthoven's I = LA − RA,
  /// II = LL − RA, III = LL − LA; Goldberger's augmented aVR = RA − (LA +
  /// LL)/2, aVL = LA − (RA + LL)/2, aVF = LL − (RA + LA)/2; the precordial
  /// Vi = φ_Vi − WCT, Wilson's central terminal WCT = (RA + LA + LL)/3.
  std::array<double, 12>
  leads_from_electrodes(const std::vector<double> &phi);

  /// The lead field of the pseudo-ECG on a finite-element space: for each
  /// electrode e at x_e the weights
  /// @f[ w_{e,i} = \frac{1}{4\pi\sigma_b}\int_\Omega \sigma\nabla\varphi_i
  ///     \cdot \frac{x - x_e}{|x - x_e|^3}\,dV, @f]
  /// so that the electrode potential of the nodal transmembrane potential V
  /// is the dot product
  /// @f[ \phi_e = \sum_i w_{e,i} V_i = \frac{1}{4\pi\sigma_b}\int_\Omega
  ///     \sigma\nabla V_m\cdot\nabla_{x_e}\frac{1}{r}\,dV,\quad
  ///     r = |x - x_e| @f]
  /// (the gradient of 1/r taken with respect to the electrode position:
  /// equivalently −∫ σ∇V_m · ∇_x(1/r) = ∫ J_i · ∇_x(1/r) with the impressed
  /// current J_i = −σ∇V_m, so a depolarization front moving towards an
  /// electrode gives a positive deflection), with
  /// σ = σ_t I + (σ_l − σ_t) f0 ⊗ f0.
  ///
  /// Assembled once over the locally owned cells (any cell shape the
  /// DoFHandler's element and @p quadrature fit) and summed into the owned
  /// DoFs of each rank; potentials() is then one dot product per electrode
  /// and a sum over the ranks. The electrodes must lie outside the mesh
  /// (1/r is singular at an electrode).
  class LeadField
  {
  public:
    /// @param[in] quadrature the cell rule of the integral (the integrand
    ///            is smooth for electrodes away from the mesh; one Gauss
    ///            point more than the element's degree + 1 is plenty)
    /// @param[in] sigma_l, sigma_t conductivity along and across the fibres
    ///            [mS/mm]
    /// @param[in] sigma_b bath conductivity [mS/mm]
    /// Collective.
    LeadField(const dealii::DoFHandler<3>         &dof_handler,
              const dealii::Mapping<3, 3>         &mapping,
              const dealii::Quadrature<3>         &quadrature,
              const Fibres::FibreField            &fibres,
              const double                         sigma_l,
              const double                         sigma_t,
              const std::vector<dealii::Point<3>> &electrodes,
              const double                         sigma_b);

    /// The potential at every electrode [units of @p owned_values] of the
    /// nodal potential whose locally owned entries (the DoFHandler's owned
    /// DoFs in ascending order) are @p owned_values. Collective; the same
    /// result on every rank.
    std::vector<double>
    potentials(const dealii::ArrayView<const double> &owned_values) const;

    unsigned int
    n_electrodes() const
    {
      return weights.size();
    }

  private:
    MPI_Comm comm;
    /// Per electrode, the weights of the owned DoFs (dimensionless: φ_e
    /// [mV] = w_e · V [mV]).
    std::vector<std::vector<double>> weights;
  };

  /// The ECG biomarkers of one beat (times in the beat's clock: from the
  /// first sample given).
  struct EcgBiomarkers
  {
    double qrs_onset    = 0; ///< [ms]
    double qrs_end      = 0; ///< [ms]
    double qrs_duration = 0; ///< qrs_end − qrs_onset [ms]
    double t_end        = 0; ///< end of the T wave [ms]
    double qt_interval  = 0; ///< t_end − qrs_onset [ms]
    /// Largest positive value of each lead within the QRS (0 if none) [mV].
    std::array<double, 12> r_amplitude{};
  };

  /// Biomarkers of one beat from the 12 leads @p leads sampled at the
  /// ascending @p times [ms] (at least three samples), on the RMS amplitude
  /// over the leads a(t) = (Σ_L φ_L(t)² / 12)^½. The pseudo-ECG is exactly
  /// zero where ∇V_m = 0 (the tissue at rest before the beat and after its
  /// repolarization; nearly so on a flat plateau), so a(t) separates the
  /// waves without a baseline:
  /// - the QRS core: from the first time a reaches @p threshold × max a
  ///   (the peak of the beat, taken to lie in the QRS) to the next time it
  ///   falls below that level;
  /// - QRS onset: the last sample before the core at which a is at its
  ///   minimum over the samples before the core (at rest a = 0: the last
  ///   sample before the first deflection);
  /// - QRS end (the J point): the first sample after the core at which a is
  ///   at its minimum up to the T wave's peak (the largest a after the first
  ///   local minimum past the core); so the QRS spans the small first and
  ///   last deflections that a level relative to the peak would cut (the
  ///   first Purkinje junctions, the last basal cells), to within a sample
  ///   (values within 0.1 % of the peak of a minimum count as at it: the
  ///   ST segment drifts slowly);
  /// - T-wave end: the last time a is above @p threshold × the largest a
  ///   after the QRS end;
  /// - R amplitude of each lead: its largest positive sample within the QRS
  ///   (0 if none);
  /// the T end interpolated linearly in time. NaN where a level is not
  /// crossed (no signal, or the QRS or T wave not over by the last sample:
  /// a still falling there).
  EcgBiomarkers
  ecg_biomarkers(const std::vector<double>                 &times,
                 const std::vector<std::array<double, 12>> &leads,
                 const double                               threshold);
} // namespace systole::Electrophysiology
