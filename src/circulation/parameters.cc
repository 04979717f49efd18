#include "circulation/parameters.h"

#include <deal.II/base/parameter_handler.h>


namespace systole::Circulation
{
  namespace
  {
    /// A value that must be positive: internal, in the parameter-file unit
    /// (for the message), its entry and that unit.
    struct Positive
    {
      double      value;
      double      value_in_file;
      const char *entry;
      const char *unit;
    };

    /// Throws unless @p e.value > 0, naming "Circulation / <entry>" and the
    /// value in the parameter-file unit.
    void
    require_positive(const Positive &e)
    {
      AssertThrow(e.value > 0,
                  dealii::ExcMessage(std::string("Circulation / ") + e.entry +
                                     " = " + format_number(e.value_in_file) +
                                     " " + e.unit + ": must be positive."));
    }

    /// The tolerances and steps of the time integration of subsection
    /// Circulation.
    void
    declare_time_stepping(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry("Relative tolerance",
                        "1e-4",
                        Double(0.0, 1.0),
                        "Relative tolerance of the adaptive time steps: of "
                        "the BDF2 local error of the 0D states and the "
                        "curvature of the 3D cavity pressures for Problem = "
                        "heartbeat; of SUNDIALS ARKode's implicit DIRK "
                        "(order 5) for Problem = circulation. Units: -.");
      prm.declare_entry("Absolute volume tolerance",
                        "1e-3",
                        Double(0.0),
                        "Absolute tolerance of the cavity volume and the "
                        "integrated flows; that of the arterial pressure is "
                        "this divided by the compliance (Problem = "
                        "circulation: every volume; a pressure gets this "
                        "divided by its compliance, a flow this per ms). "
                        "Units: mL.");
      prm.declare_entry("Absolute pressure tolerance",
                        "0.1",
                        Double(0.0),
                        "Problem = heartbeat: absolute tolerance of the 3D "
                        "cavity pressures in the step-size control (beside "
                        "the relative tolerance times the pressure); the "
                        "steps are short where the pressure curves, as in "
                        "the isovolumetric contraction. Units: mmHg "
                        "(converted to kPa).");
      prm.declare_entry("Event time tolerance",
                        "0.1",
                        Double(0.0),
                        "Problem = heartbeat: a step that crosses a valve "
                        "event (a valve's pressure drop changes sign) is "
                        "redone until it ends at most this long after the "
                        "event. Units: ms.");
      prm.declare_entry(
        "Displacement tolerance",
        "0.25",
        Double(0.0),
        "Problem = heartbeat: the largest nodal distance by which the start of "
        "a coupled step's Newton iteration (the displacement extrapolated from "
        "the last two states) may miss its solution. After every step, the "
        "next one is limited so that its miss is expected within this (it "
        "grows with the square of the step): where the motion accelerates, as "
        "at the contraction onset, the steps stay short enough for Newton to "
        "converge within Mechanics / Maximum Newton iterations instead of "
        "failing and being halved. 0: the steps follow the 0D and pressure "
        "errors alone. Units: mm.");
      prm.declare_entry(
        "Newton iterations target",
        "3",
        Integer(0),
        "Problem = heartbeat: the Newton iterations with a new tangent (a "
        "chord iteration on an earlier factorization does not count) a "
        "coupled step aims at. After a step whose solve needed N of them, N "
        "above the target, the next step is at most sqrt(target / N) as long: "
        "where the equilibrium path bends faster than the predictor sees "
        "(Newton converges, but slowly), the steps shorten before a solve "
        "fails. 0: not controlled. Units: -.");
      prm.declare_entry("Maximum time step",
                        "10",
                        Double(0.0),
                        "Largest time step (Problem = heartbeat: of the "
                        "coupled mechanics and circulation step, in "
                        "diastasis). Units: ms.");
      prm.declare_entry("Initial time step",
                        "0.5",
                        Double(0.0),
                        "First step of the integrator, and (Problem = "
                        "heartbeat) the first step after every valve event. "
                        "Units: ms.");
    }


    /// The Windkessel and valve entries of subsection Circulation.
    void
    declare_windkessel(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Peripheral resistance",
        "1.0",
        Double(0.0),
        "R_p, systemic peripheral resistance. Units: mmHg s/mL. "
        "Typical 1.0-1.3 (reference/physiology.md).");
      prm.declare_entry("Compliance",
                        "1.5",
                        Double(0.0),
                        "C, arterial compliance. Units: mL/mmHg. Typical 1-2.");
      prm.declare_entry("Characteristic impedance",
                        "0.05",
                        Double(0.0),
                        "Z_c of the proximal aorta (Model = 3- and 4-element "
                        "Windkessel). "
                        "Units: mmHg s/mL. Typical 0.03-0.07.");
      prm.declare_entry("Aortic valve resistance",
                        "0.0075",
                        Double(0.0),
                        "Resistance of the open aortic valve: the R_min of the "
                        "aortic diode valve of every Model = n-element "
                        "Windkessel. Units: "
                        "mmHg s/mL.");
      prm.declare_entry("Mitral valve resistance",
                        "0.0075",
                        Double(0.0),
                        "Resistance of the open mitral valve: the filling flow "
                        "is (atrial pressure - cavity pressure) / this. Units: "
                        "mmHg s/mL.");
      prm.declare_entry("Atrial pressure",
                        "10",
                        Double(0.0),
                        "Left atrial pressure, constant. Units: mmHg. Typical "
                        "end-diastolic pressure 8-12.");
      prm.declare_entry("Venous pressure",
                        "0",
                        Double(0.0),
                        "Pressure at the outflow end of the peripheral "
                        "resistance. Units: mmHg.");
      prm.declare_entry(
        "Initial aortic pressure",
        "80",
        Double(0.0),
        "Distal arterial (capacitor) pressure at time 0. Units: "
        "mmHg. Typical diastolic aortic pressure 80.");
    }

  } // namespace

  void
  Parameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Circulation");
    declare_windkessel(prm);
    prm.declare_entry("Period",
                      "800",
                      Double(0.0),
                      "Length of one heartbeat. Units: ms. Typical 800-1000.");
    prm.declare_entry("Number of beats",
                      "4",
                      Integer(1),
                      "Largest number of beats to simulate, heartbeat and "
                      "circulation problems (the run may stop earlier, see "
                      "Periodicity tolerance). Units: -.");
    prm.declare_entry(
      "Periodicity tolerance",
      "0.01",
      Double(0.0, 1.0),
      "The run stops after a beat (from the second on) in which every "
      "ventricle's end-diastolic volume (0D or 3D) differs from that of the "
      "previous beat by less than this fraction and, when both ventricles "
      "of the closed loop are 3D (Problem = heartbeat on a biventricular "
      "mesh), their stroke volumes differ by less than this fraction of "
      "their mean (the /summary columns EDV_change, SV_difference and "
      "periodicity); 0 runs all beats. Units: -.");
    declare_time_stepping(prm);
    prm.leave_subsection();
  }

  Parameters
  Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> s = {"Circulation"};
    Parameters                     p;

    const auto resistance = [&](const std::string &entry) {
      return resistance_from_mmHg_s_per_mL(prm.get_double(s, entry));
    };
    p.windkessel.peripheral_resistance = resistance("Peripheral resistance");
    p.windkessel.compliance =
      compliance_from_mL_per_mmHg(prm.get_double(s, "Compliance"));
    p.windkessel.characteristic_impedance =
      resistance("Characteristic impedance");
    p.windkessel.aortic_valve_resistance =
      resistance("Aortic valve resistance");
    p.windkessel.venous_pressure =
      Units::mmHg_to_kPa(prm.get_double(s, "Venous pressure"));
    p.mitral_valve_resistance = resistance("Mitral valve resistance");
    p.atrial_pressure =
      Units::mmHg_to_kPa(prm.get_double(s, "Atrial pressure"));
    p.initial_arterial_pressure =
      Units::mmHg_to_kPa(prm.get_double(s, "Initial aortic pressure"));
    StepControl &t          = p.steps;
    t.period                = prm.get_double(s, "Period");
    t.n_max_beats           = prm.get_integer(s, "Number of beats");
    t.periodicity_tolerance = prm.get_double(s, "Periodicity tolerance");
    t.relative_tolerance    = prm.get_double(s, "Relative tolerance");
    t.absolute_volume_tolerance =
      Units::mL_to_mm3(prm.get_double(s, "Absolute volume tolerance"));
    t.absolute_pressure_tolerance =
      Units::mmHg_to_kPa(prm.get_double(s, "Absolute pressure tolerance"));
    t.event_time_tolerance     = prm.get_double(s, "Event time tolerance");
    t.displacement_tolerance   = prm.get_double(s, "Displacement tolerance");
    t.newton_iterations_target = prm.get_integer(s, "Newton iterations target");
    t.max_step                 = prm.get_double(s, "Maximum time step");
    t.initial_step             = prm.get_double(s, "Initial time step");
    p.validate();
    return p;
  }

  void
  Parameters::validate() const
  {
    // Messages give values in the units of the parameter file.
    const double r = resistance_from_mmHg_s_per_mL(1.0);
    const auto  &w = windkessel;
    for (const Positive &e : {Positive{w.peripheral_resistance,
                                       w.peripheral_resistance / r,
                                       "Peripheral resistance",
                                       "mmHg s/mL"},
                              {w.compliance,
                               w.compliance / compliance_from_mL_per_mmHg(1.0),
                               "Compliance",
                               "mL/mmHg"},
                              {w.aortic_valve_resistance,
                               w.aortic_valve_resistance / r,
                               "Aortic valve resistance",
                               "mmHg s/mL"},
                              {mitral_valve_resistance,
                               mitral_valve_resistance / r,
                               "Mitral valve resistance",
                               "mmHg s/mL"},
                              {atrial_pressure,
                               Units::kPa_to_mmHg(atrial_pressure),
                               "Atrial pressure",
                               "mmHg"}})
      require_positive(e);
    AssertThrow(w.venous_pressure >= 0,
                dealii::ExcMessage(
                  "Circulation / Venous pressure = " +
                  format_number(Units::kPa_to_mmHg(w.venous_pressure)) +
                  " mmHg: must not be negative."));
    AssertThrow(initial_arterial_pressure >= 0,
                dealii::ExcMessage(
                  "Circulation / Initial aortic pressure = " +
                  format_number(Units::kPa_to_mmHg(initial_arterial_pressure)) +
                  " mmHg: must not be negative."));
    const StepControl &t = steps;
    require_positive({t.period, t.period, "Period", "ms"});
    AssertThrow(t.n_max_beats >= 1,
                dealii::ExcMessage(
                  "Circulation / Number of beats must be at least 1."));
    AssertThrow(t.periodicity_tolerance >= 0 && t.periodicity_tolerance < 1,
                dealii::ExcMessage("Circulation / Periodicity tolerance = " +
                                   format_number(t.periodicity_tolerance) +
                                   ": must be in [0, 1)."));
    AssertThrow(t.relative_tolerance > 0 && t.relative_tolerance < 1,
                dealii::ExcMessage("Circulation / Relative tolerance = " +
                                   format_number(t.relative_tolerance) +
                                   ": must be in (0, 1)."));
    for (const Positive &e :
         {Positive{t.absolute_volume_tolerance,
                   Units::mm3_to_mL(t.absolute_volume_tolerance),
                   "Absolute volume tolerance",
                   "mL"},
          {t.absolute_pressure_tolerance,
           Units::kPa_to_mmHg(t.absolute_pressure_tolerance),
           "Absolute pressure tolerance",
           "mmHg"},
          {t.event_time_tolerance,
           t.event_time_tolerance,
           "Event time tolerance",
           "ms"},
          {t.max_step, t.max_step, "Maximum time step", "ms"},
          {t.initial_step, t.initial_step, "Initial time step", "ms"}})
      require_positive(e);
    AssertThrow(t.initial_step <= t.max_step,
                dealii::ExcMessage("Circulation / Initial time step (" +
                                   format_number(t.initial_step) +
                                   " ms) must not exceed Maximum time step (" +
                                   format_number(t.max_step) + " ms)."));
    AssertThrow(t.max_step <= t.period,
                dealii::ExcMessage("Circulation / Maximum time step (" +
                                   format_number(t.max_step) +
                                   " ms) must not exceed the Period (" +
                                   format_number(t.period) + " ms)."));
  }
} // namespace systole::Circulation
