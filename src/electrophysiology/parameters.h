#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include "electrophysiology/ecg.h"
#include "electrophysiology/ionic_model.h"
#include "electrophysiology/purkinje.h"
#include "electrophysiology/stimulus.h"

#include <memory>
#include <string>
#include <vector>

namespace systole::Electrophysiology
{
  /// A named point whose potential and activation time a run reports.
  struct Probe
  {
    std::string      name;
    dealii::Point<3> position; ///< reference position [mm]
  };

  /// Conduction velocities of the eikonal model and its fast endocardial
  /// layer (Parameters, entries "Conduction velocity ..." and "Fast
  /// endocardial layer ...").
  struct EikonalSettings
  {
    double velocity_fibre  = 0.611; ///< along f [mm/ms]
    double velocity_sheet  = 0.222; ///< along s, across the fibres [mm/ms]
    double velocity_normal = 0.222; ///< along n = f x s [mm/ms]
    /// The cells whose centre lies within @p endocardial_thickness of these
    /// boundary parts (a comma-separated list) conduct isotropically at @p
    /// endocardial_velocity (a fast endocardial, Purkinje-like layer);
    /// empty: none.
    std::string endocardial_part;
    double      endocardial_thickness = 0; ///< [mm]
    double      endocardial_velocity  = 2; ///< [mm/ms]
  };

  /// The time integration of the monodomain and of a single cell (the ARK
  /// IMEX method of ImexIntegrator, ImexIntegrator::Settings::of()).
  struct TimeSteps
  {
    double       time_step = 0.1;   ///< (maximum) ARKode step [ms]
    unsigned int order     = 3;     ///< order of the IMEX ARK method (3 to 5)
    bool         adaptive  = false; ///< adapt the step to the tolerances
    double       relative_tolerance = 1e-4; ///< adaptive steps only [-]
    double       absolute_tolerance = 1e-5; ///< adaptive steps [model units]
  };

  /// Subsection "Electrophysiology": the monodomain model, its
  /// discretization and time integration (TimeSteps), the stimulation
  /// protocol. Defaults: physiology.md (Niederer et al. 2011 tissue values).
  struct Parameters : TimeSteps
  {
    /// "Model": how the activation is computed. monodomain: the
    /// reaction-diffusion model; reaction_eikonal: the ionic model at every
    /// node excited at its eikonal activation time (with the diffusion: RE+,
    /// without: RE-; Neic et al. 2017); eikonal: the activation times alone.
    enum class Model
    {
      monodomain,
      reaction_eikonal,
      eikonal
    };
    Model model = Model::monodomain;
    /// Reaction-eikonal: keep the diffusion (RE+) or not (RE-).
    bool reaction_eikonal_diffusion = true;
    /// Conduction velocities and fast endocardial layer of the eikonal
    /// model.
    EikonalSettings eikonal;
    /// The Purkinje network that activates the eikonal models (subsection
    /// Purkinje; off by default).
    PurkinjeParameters purkinje;

    /// The ionic model ("Ionic model" and its subsection); never null.
    std::shared_ptr<const IonicModel> ionic_model;

    double sigma_l = 0.1334; ///< conductivity along the fibres [mS/mm]
    double sigma_t = 0.0176; ///< conductivity across the fibres [mS/mm]
    double chi     = 140.0;  ///< membrane surface-to-volume ratio [1/mm]
    double C_m     = 0.01;   ///< membrane capacitance [µF/mm²]

    unsigned int degree = 1; ///< Lagrange degree of the potential (1 or 2)
    /// Coupled problems: global refinements of the mechanics mesh that give
    /// the EP mesh.
    unsigned int mesh_refinement = 0;

    double      linear_tolerance = 1e-8;  ///< CG relative residual [-]
    std::string preconditioner   = "AMG"; ///< of CG: "AMG" or "Jacobi"
    /// Mass matrix of the potential: false: lumped (Gauss-Lobatto, diagonal);
    /// true: consistent (Gauss), with the ionic current still at the nodes.
    bool consistent_mass = false;

    double activation_threshold_mV = -30.0; ///< upstroke threshold [mV]

    std::vector<Stimulus> stimuli;
    double                stimulus_period = 0; ///< beat period [ms]; 0: once

    /// Pull the conductivity back through the deformation, J F^-1 σ F^-T,
    /// when the mechanics passes F (Monodomain::set_deformation_gradients).
    bool pull_back = false;

    std::vector<Probe> probes;

    /// The pseudo-ECG (entries ECG ...).
    EcgParameters ecg;

    /// Diffusivity along / across the fibres D = σ/(χ C_m) [mm²/ms].
    double
    diffusivity_l() const;
    double
    diffusivity_t() const;

    /// Declares subsection "Electrophysiology" (and the ionic models' own
    /// subsections inside it).
    static void
    declare(dealii::ParameterHandler &prm);

    /// Reads and validates it (builds the ionic model).
    static Parameters
    parse(const dealii::ParameterHandler &prm);

    /// Defaults with the ionic model called @p model_name (tests).
    static Parameters
    defaults(const std::string &model_name = "Aliev-Panfilov");
  };
} // namespace systole::Electrophysiology
