#include "electrophysiology/parameters.h"

#include <deal.II/base/parameter_handler.h>

#include "electrophysiology/ionic_factory.h"

#include <cmath>

namespace systole::Electrophysiology
{
  namespace
  {
    const std::string section = "Electrophysiology";

    std::vector<Probe>
    parse_probes(const std::string &text)
    {
      std::vector<Probe> probes;
      for (const auto &item : dealii::Utilities::split_string_list(text, ';'))
        {
          const auto colon = item.find(':');
          const auto bad   = [&]() {
            AssertThrow(false,
                        dealii::ExcMessage(
                          "Electrophysiology / Probes: '" + item +
                          "' is not of the form 'name: x, y, z'."));
          };
          if (colon == std::string::npos)
            bad();
          Probe p;
          p.name = dealii::Utilities::trim(item.substr(0, colon));
          const auto xyz =
            dealii::Utilities::split_string_list(item.substr(colon + 1), ',');
          if (p.name.empty() || xyz.size() != 3)
            bad();
          for (unsigned int d = 0; d < 3; ++d)
            p.position[d] = dealii::Utilities::string_to_double(xyz[d]);
          for (const auto &other : probes)
            AssertThrow(other.name != p.name,
                        dealii::ExcMessage("Electrophysiology / Probes: the "
                                           "name '" +
                                           p.name + "' is used twice."));
          probes.push_back(p);
        }
      return probes;
    }
  } // namespace


  double
  Parameters::diffusivity_l() const
  {
    return sigma_l / (chi * C_m);
  }

  double
  Parameters::diffusivity_t() const
  {
    return sigma_t / (chi * C_m);
  }


  namespace
  {
    /// The entries of the eikonal models (in subsection Electrophysiology).
    void
    declare_eikonal(dealii::ParameterHandler &prm, const Parameters &d)
    {
      using namespace dealii::Patterns;
      using Tools::to_string;
      prm.declare_entry(
        "Model",
        "monodomain",
        Selection("monodomain|reaction-eikonal|eikonal"),
        "How the activation is computed. monodomain: the reaction-diffusion "
        "model (the entries below). reaction-eikonal: the activation times "
        "come from the anisotropic eikonal equation (Conduction velocity "
        "entries, from the Stimuli with their start times), and the ionic "
        "model runs at every node, excited at its eikonal time by a stimulus "
        "current of the first stimulus's amplitude and duration, with the "
        "diffusion (Reaction-eikonal variant = RE+) or without (RE-) (Neic et "
        "al. 2017, J Comput Phys 346); accurate on coarse meshes. eikonal: the "
        "activation times alone (no ionic model: for the prescribed-shape "
        "tension, Active tension / Activation map = electrophysiology; the "
        "potential is a square wave for display). Degree 1 only. Units: -.");
      prm.declare_entry(
        "Reaction-eikonal variant",
        "RE+",
        Selection("RE+|RE-"),
        "Model = reaction-eikonal: RE+ keeps the diffusion of the monodomain "
        "(the eikonal-timed stimulus only starts the upstroke where the "
        "diffusion has not: smooth fronts and repolarisation), RE- drops it "
        "(the ionic ODEs at the nodes only: no linear solves; the potential "
        "has no electrotonic coupling). Units: -.");
      prm.declare_entry(
        "Conduction velocity along fibres",
        to_string(d.eikonal.velocity_fibre),
        Double(0.0),
        "Eikonal models: speed of a plane front along the fibres f. Units: "
        "mm/ms (= m/s). Default: the converged monodomain speed of the "
        "Niederer et al. 2011 tissue (ten Tusscher-Panfilov epicardial, "
        "sigma_l = 0.1334 mS/mm, chi = 140 /mm, C_m = 0.01 µF/mm²) on a cable "
        "of 0.025 mm cells, 0.610-0.612 (docs/verification.md).");
      prm.declare_entry(
        "Conduction velocity across fibres",
        to_string(d.eikonal.velocity_sheet),
        Double(0.0),
        "Eikonal models: speed along the sheet direction s. Units: mm/ms. "
        "Default: the fibre speed times sqrt(sigma_t/sigma_l) of the Niederer "
        "tissue (the monodomain speed scales with sqrt(D)): 0.611 x 0.3632.");
      prm.declare_entry(
        "Conduction velocity normal to sheets",
        to_string(d.eikonal.velocity_normal),
        Double(0.0),
        "Eikonal models: speed along the sheet normal n = f x s. Units: mm/ms. "
        "Default: as across the fibres (transversely isotropic tissue).");
      prm.declare_entry(
        "Fast endocardial layer",
        "",
        Anything(),
        "Eikonal models: names of boundary parts, comma-separated (e.g. "
        "endocardium, or lv_endocardium, rv_endocardium), whose cells within "
        "Fast endocardial layer thickness conduct isotropically at Fast "
        "endocardial layer velocity (a Purkinje-like layer); empty: none. "
        "Units: -.");
      prm.declare_entry(
        "Fast endocardial layer thickness",
        "0",
        Double(0.0),
        "Eikonal models: thickness of the fast layer, measured from the "
        "boundary part to the cell centres. Units: mm.");
      prm.declare_entry(
        "Fast endocardial layer velocity",
        "2",
        Double(0.0),
        "Eikonal models: isotropic conduction velocity in the fast layer "
        "(Purkinje-like; 2-4 mm/ms in the literature). Units: mm/ms.");
    }

    /// The element, time integration and linear solver of the monodomain.
    void
    declare_discretization(dealii::ParameterHandler &prm, const Parameters &d)
    {
      using namespace dealii::Patterns;
      using Tools::to_string;
      prm.declare_entry(
        "Polynomial degree",
        to_string(d.degree),
        Integer(1, 2),
        "Degree of the Lagrange elements of the potential (Q1 or Q2, with a "
        "Gauss-Lobatto lumped mass), on the mesh of the problem. Units: -.");
      prm.declare_entry(
        "Mesh refinement",
        to_string(d.mesh_refinement),
        Integer(0, 6),
        "Problem = heartbeat: the EP mesh is the mechanics mesh refined this "
        "many times (each refinement halves the cell size; the wave front is "
        "about a millimetre wide, so a ventricle meshed for the mechanics "
        "needs 2-3; docs/verification.md has the study). The electrophysiology "
        "problem uses the Geometry mesh as it is. Units: -.");
      prm.declare_entry(
        "Time step",
        to_string(d.time_step),
        Double(0.0),
        "Step of the ARKode integration (the maximum step when adaptive); the "
        "potential is sampled for activation times at this interval, and EP "
        "sub-cycles with it inside each step of the outer time loop. Units: "
        "ms. Typical 0.05-0.1 ms for the phenomenological models "
        "(physiology.md), 0.005-0.05 ms for ten Tusscher-Panfilov (its gates "
        "advance by Rush-Larsen, stable at any step; Problem = cell agrees "
        "with SciPy to 0.05 % at 0.02 ms, docs/verification.md).");
      prm.declare_entry(
        "ARKode order",
        to_string(d.order),
        Integer(3, 5),
        "Order of the IMEX additive Runge-Kutta method, SUNDIALS' default "
        "table of that order (3: ARK-4(2)3, 4: ARK-6(3)4, 5: ARK-8(4)5 of "
        "Kennedy and Carpenter; SUNDIALS 6.4 has no second-order pair): "
        "diffusion implicit, ionic currents and stimulus explicit. Units: -.");
      prm.declare_entry(
        "Adaptive time step",
        d.adaptive ? "true" : "false",
        Bool(),
        "Adapt the ARKode step to the tolerances below, bounded by Time step "
        "and by the stability of the explicit ionic currents (0.9 of the "
        "largest stable step at the stiffest node; docs/architecture.md); "
        "false: fixed steps of Time step. Units: -.");
      prm.declare_entry("Relative tolerance",
                        to_string(d.relative_tolerance),
                        Double(0.0),
                        "Relative tolerance of the adaptive steps. Units: -.");
      prm.declare_entry("Absolute tolerance",
                        to_string(d.absolute_tolerance),
                        Double(0.0),
                        "Absolute tolerance of the adaptive steps, on the "
                        "model's potential and states. Units: model units.");
      prm.declare_entry(
        "Linear solver tolerance",
        to_string(d.linear_tolerance),
        Double(0.0, 1.0),
        "Relative residual reduction of CG + BoomerAMG on the implicit stage "
        "systems (M + gamma K) x = M b. Units: -.");
      prm.declare_entry(
        "Preconditioner",
        d.preconditioner,
        Selection("AMG|Jacobi"),
        "Preconditioner of CG on the stage systems: AMG (BoomerAMG, set up "
        "once per step size; iteration counts independent of the mesh) or "
        "Jacobi (cheaper per iteration; the systems are dominated by the mass "
        "matrix at the usual steps, so its iteration count grows only slowly "
        "under refinement; docs/verification.md compares the costs). Units: "
        "-.");
      prm.declare_entry(
        "Mass matrix",
        d.consistent_mass ? "consistent" : "lumped",
        Selection("lumped|consistent"),
        "Mass matrix M of M dv/dt = -K v - M I_ion: lumped (Gauss-Lobatto "
        "points, diagonal; the cheaper one) or consistent (Gauss points; each "
        "evaluation of the diffusion term solves with M by CG + Jacobi). The "
        "ionic currents are evaluated at the nodes either way. On coarse "
        "meshes the lumped mass slows a sharp front (ten Tusscher-Panfilov) "
        "more than the consistent one (docs/verification.md, Niederer "
        "benchmark). Units: -.");
    }


    /// The conductivities and membrane of the tissue.
    void
    declare_tissue(dealii::ParameterHandler &prm, const Parameters &d)
    {
      using namespace dealii::Patterns;
      using Tools::to_string;
      prm.declare_entry(
        "Longitudinal conductivity",
        to_string(d.sigma_l),
        Double(0.0),
        "Bulk conductivity sigma_l along the fibres (monodomain, "
        "sigma = sigma_t I + (sigma_l - sigma_t) f0 x f0). Units: mS/mm "
        "(= S/m). Source: physiology.md, Niederer et al. 2011, 0.1334.");
      prm.declare_entry(
        "Transverse conductivity",
        to_string(d.sigma_t),
        Double(0.0),
        "Bulk conductivity sigma_t across the fibres. Units: mS/mm. Source: "
        "physiology.md, Niederer et al. 2011, 0.0176.");
      prm.declare_entry("Surface to volume ratio",
                        to_string(d.chi),
                        Double(0.0),
                        "Membrane area per tissue volume chi. Units: 1/mm. "
                        "Source: physiology.md, Niederer et al. 2011, 140.");
      prm.declare_entry("Membrane capacitance",
                        to_string(d.C_m),
                        Double(0.0),
                        "Membrane capacitance per area C_m; the diffusivity is "
                        "D = sigma / (chi C_m). Units: µF/mm². Source: "
                        "physiology.md, Niederer et al. 2011, 0.01.");
    }

  } // namespace


  void
  Parameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    using Tools::to_string;
    const Parameters d;
    prm.enter_subsection(section);
    declare_eikonal(prm, d);
    PurkinjeParameters::declare(prm);
    declare_ionic_model_parameters(prm);
    declare_tissue(prm, d);
    declare_discretization(prm, d);
    prm.declare_entry(
      "Activation threshold",
      to_string(d.activation_threshold_mV),
      Double(),
      "A point activates when its potential crosses this value upwards "
      "(located by linear interpolation in time between steps). Units: mV "
      "(the phenomenological models map their potential to V = 100 u - 80 "
      "mV, ten Tusscher-Panfilov is in mV; -30 mV is mid-upstroke for "
      "all).");
    prm.declare_entry(
      "Stimuli",
      "corner: box 0 0 0 1.5 1.5 1.5 from 0 for 2 at 50",
      Anything(),
      "Stimuli separated by ';', each '<name>: <region> from <start> for "
      "<duration> at <amplitude>', with <region> 'box x0 y0 z0 x1 y1 z1', "
      "'sphere x y z r' or 'surface <boundary part> <distance>' (the points "
      "within that distance of the boundary part, e.g. an endocardial "
      "layer). Units: mm, ms, µA/mm³ (current per tissue volume). Default: "
      "the Niederer et al. 2011 corner stimulus, 50 000 µA/cm³ for 2 ms in "
      "a 1.5 mm cube.");
    prm.declare_entry(
      "Stimulus period",
      to_string(d.stimulus_period),
      Double(0.0),
      "Every stimulus repeats with this period (the beat); 0: once. Units: "
      "ms.");
    prm.declare_entry(
      "Pull back conductivity",
      d.pull_back ? "true" : "false",
      Bool(),
      "In coupled problems, use the conductivity pulled back through the "
      "deformation, J F^-1 sigma F^-T, whenever the mechanics passes F; "
      "ignored by the electrophysiology problem. Units: -.");
    prm.declare_entry(
      "Probes",
      "",
      Anything(),
      "Points whose potential is written to the time series and whose "
      "activation time is written to the summary: 'name: x, y, z; name: x, "
      "y, z'. Units: mm.");
    prm.leave_subsection();
    EcgParameters::declare(prm);
  }


  Parameters
  Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> s = {section};
    Parameters                     p;
    p.ionic_model             = create_ionic_model(prm);
    p.sigma_l                 = prm.get_double(s, "Longitudinal conductivity");
    p.sigma_t                 = prm.get_double(s, "Transverse conductivity");
    p.chi                     = prm.get_double(s, "Surface to volume ratio");
    p.C_m                     = prm.get_double(s, "Membrane capacitance");
    p.degree                  = prm.get_integer(s, "Polynomial degree");
    p.mesh_refinement         = prm.get_integer(s, "Mesh refinement");
    p.time_step               = prm.get_double(s, "Time step");
    p.order                   = prm.get_integer(s, "ARKode order");
    p.adaptive                = prm.get_bool(s, "Adaptive time step");
    p.relative_tolerance      = prm.get_double(s, "Relative tolerance");
    p.absolute_tolerance      = prm.get_double(s, "Absolute tolerance");
    p.linear_tolerance        = prm.get_double(s, "Linear solver tolerance");
    p.preconditioner          = prm.get(s, "Preconditioner");
    p.consistent_mass         = prm.get(s, "Mass matrix") == "consistent";
    p.activation_threshold_mV = prm.get_double(s, "Activation threshold");
    p.stimuli                 = parse_stimuli(prm.get(s, "Stimuli"));
    p.stimulus_period         = prm.get_double(s, "Stimulus period");
    p.pull_back               = prm.get_bool(s, "Pull back conductivity");
    p.probes                  = parse_probes(prm.get(s, "Probes"));
    p.ecg                     = EcgParameters::parse(prm);
    {
      const std::string model = prm.get(s, "Model");
      p.model                 = model == "monodomain" ? Model::monodomain
                                : model == "reaction-eikonal" ? Model::reaction_eikonal
                                                              : Model::eikonal;
    }
    p.reaction_eikonal_diffusion =
      prm.get(s, "Reaction-eikonal variant") == "RE+";
    p.eikonal.velocity_fibre =
      prm.get_double(s, "Conduction velocity along fibres");
    p.eikonal.velocity_sheet =
      prm.get_double(s, "Conduction velocity across fibres");
    p.eikonal.velocity_normal =
      prm.get_double(s, "Conduction velocity normal to sheets");
    p.eikonal.endocardial_part =
      dealii::Utilities::trim(prm.get(s, "Fast endocardial layer"));
    p.eikonal.endocardial_thickness =
      prm.get_double(s, "Fast endocardial layer thickness");
    p.eikonal.endocardial_velocity =
      prm.get_double(s, "Fast endocardial layer velocity");
    p.purkinje = PurkinjeParameters::parse(prm);

    const auto positive = [](const double value, const std::string &entry) {
      AssertThrow(std::isfinite(value) && value > 0,
                  dealii::ExcMessage("Electrophysiology / " + entry +
                                     " must be > 0."));
    };
    positive(p.sigma_l, "Longitudinal conductivity");
    positive(p.sigma_t, "Transverse conductivity");
    positive(p.chi, "Surface to volume ratio");
    positive(p.C_m, "Membrane capacitance");
    positive(p.time_step, "Time step");
    if (p.model != Model::monodomain)
      {
        positive(p.eikonal.velocity_fibre, "Conduction velocity along fibres");
        positive(p.eikonal.velocity_sheet, "Conduction velocity across fibres");
        positive(p.eikonal.velocity_normal,
                 "Conduction velocity normal to sheets");
        AssertThrow(p.degree == 1,
                    dealii::ExcMessage(
                      "Electrophysiology / Model = " + prm.get(s, "Model") +
                      " needs Polynomial degree = 1 (the eikonal solver "
                      "works on the vertices)."));
        if (!p.eikonal.endocardial_part.empty())
          positive(p.eikonal.endocardial_velocity,
                   "Fast endocardial layer velocity");
      }
    AssertThrow(!p.purkinje.enabled || !p.stimuli.empty(),
                dealii::ExcMessage(
                  "Electrophysiology / Purkinje: the His bundle activates "
                  "with the first of the Stimuli; give one."));
    AssertThrow(!p.adaptive ||
                  (p.relative_tolerance > 0 && p.absolute_tolerance > 0),
                dealii::ExcMessage(
                  "Electrophysiology / Relative tolerance and Absolute "
                  "tolerance must be > 0 with Adaptive time step = true."));
    for (const auto &stimulus : p.stimuli)
      AssertThrow(
        p.stimulus_period == 0 || stimulus.duration < p.stimulus_period,
        dealii::ExcMessage("Electrophysiology / Stimuli: the duration of '" +
                           stimulus.name +
                           "' must be shorter than the Stimulus period."));
    return p;
  }


  Parameters
  Parameters::defaults(const std::string &model_name)
  {
    Parameters p;
    p.ionic_model = create_ionic_model(model_name);
    p.stimuli =
      parse_stimuli("corner: box 0 0 0 1.5 1.5 1.5 from 0 for 2 at 50");
    return p;
  }
} // namespace systole::Electrophysiology
