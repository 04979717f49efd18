#include "circulation/chamber_elastance.h"

#include <deal.II/base/parameter_handler.h>

#include "base/units.h"
#include "circulation/windkessel.h"

#include <cmath>

namespace systole::Circulation
{
  namespace
  {
    constexpr double per_mmHg_per_mL = elastance_from_mmHg_per_mL(1.0);
  } // namespace

  ChamberElastance::Parameters
  ChamberElastance::Parameters::from_file_units(const double E_A,
                                                const double E_B,
                                                const double t_C,
                                                const double T_C,
                                                const double T_R,
                                                const double V_0,
                                                const double V_initial)
  {
    Parameters p;
    p.active_elastance     = elastance_from_mmHg_per_mL(E_A);
    p.passive_elastance    = elastance_from_mmHg_per_mL(E_B);
    p.contraction_onset    = t_C;
    p.contraction_duration = T_C;
    p.relaxation_duration  = T_R;
    p.unloaded_volume      = Units::mL_to_mm3(V_0);
    p.initial_volume       = Units::mL_to_mm3(V_initial);
    return p;
  }

  void
  ChamberElastance::Parameters::declare(dealii::ParameterHandler &prm,
                                        const Parameters         &d,
                                        const std::string        &chamber)
  {
    using namespace dealii::Patterns;
    const std::string source =
      " Default: reference/physiology.md (Regazzoni et al. 2022).";
    prm.declare_entry("Active elastance",
                      format_value(d.active_elastance / per_mmHg_per_mL),
                      Double(0.0),
                      "E_A of the " + chamber +
                        ": E(t) = E_B + E_A e(t), p = E(t) (V - V_0). Units: "
                        "mmHg/mL (converted to kPa/mm^3)." +
                        source);
    prm.declare_entry("Passive elastance",
                      format_value(d.passive_elastance / per_mmHg_per_mL),
                      Double(0.0),
                      "E_B of the " + chamber +
                        ", the elastance at rest. Units: mmHg/mL. Must be "
                        "positive." +
                        source);
    prm.declare_entry(
      "Contraction onset",
      format_value(d.contraction_onset),
      Double(),
      "t_C: time within the beat at which the " + chamber +
        " starts to contract (taken modulo the period, so the activation may "
        "wrap around the beat's end). Units: ms. The atria lead the "
        "ventricles by the P-R interval (about 200 ms): atria at 700 ms, "
        "ventricles at 100 ms of an 800 ms beat; keep that lead at other "
        "periods." +
        source);
    prm.declare_entry("Contraction duration",
                      format_value(d.contraction_duration),
                      Double(0.0),
                      "T_C: from the onset to the peak elastance of the " +
                        chamber + " (raised cosine). Units: ms." + source);
    prm.declare_entry("Relaxation duration",
                      format_value(d.relaxation_duration),
                      Double(0.0),
                      "T_R: from the peak back to E_B (raised cosine); T_C "
                      "+ T_R must not exceed the period. Units: ms." +
                        source);
    prm.declare_entry("Unloaded volume",
                      format_value(Units::mm3_to_mL(d.unloaded_volume)),
                      Double(0.0),
                      "V_0 of the " + chamber +
                        ", the volume at zero pressure. Units: mL." + source);
    prm.declare_entry("Initial volume",
                      format_value(Units::mm3_to_mL(d.initial_volume)),
                      Double(0.0),
                      "Volume of the " + chamber + " at time 0. Units: mL." +
                        source);
  }

  ChamberElastance::Parameters
  ChamberElastance::Parameters::parse(const dealii::ParameterHandler &prm,
                                      const std::vector<std::string> &path)
  {
    return from_file_units(prm.get_double(path, "Active elastance"),
                           prm.get_double(path, "Passive elastance"),
                           prm.get_double(path, "Contraction onset"),
                           prm.get_double(path, "Contraction duration"),
                           prm.get_double(path, "Relaxation duration"),
                           prm.get_double(path, "Unloaded volume"),
                           prm.get_double(path, "Initial volume"));
  }

  void
  ChamberElastance::Parameters::validate(const std::string &where,
                                         const double       period) const
  {
    const auto fail = [&](const std::string &entry,
                          const double       value,
                          const std::string &unit,
                          const std::string &rule) {
      AssertThrow(false,
                  dealii::ExcMessage(where + " / " + entry + " = " +
                                     format_value(value) + " " + unit + ": " +
                                     rule + "."));
    };
    if (!(active_elastance >= 0))
      fail("Active elastance",
           active_elastance / per_mmHg_per_mL,
           "mmHg/mL",
           "must not be negative");
    if (!(passive_elastance > 0))
      fail("Passive elastance",
           passive_elastance / per_mmHg_per_mL,
           "mmHg/mL",
           "must be positive");
    if (!(contraction_duration > 0))
      fail("Contraction duration",
           contraction_duration,
           "ms",
           "must be positive");
    if (!(relaxation_duration > 0))
      fail("Relaxation duration",
           relaxation_duration,
           "ms",
           "must be positive");
    if (!(contraction_duration + relaxation_duration <= period))
      fail("Relaxation duration",
           relaxation_duration,
           "ms",
           "Contraction duration + Relaxation duration (" +
             format_value(contraction_duration + relaxation_duration) +
             " ms) must not exceed the period (" + format_value(period) +
             " ms)");
    if (!std::isfinite(contraction_onset))
      fail("Contraction onset", contraction_onset, "ms", "must be finite");
    if (!(unloaded_volume >= 0))
      fail("Unloaded volume",
           Units::mm3_to_mL(unloaded_volume),
           "mL",
           "must not be negative");
    if (!(initial_volume > 0))
      fail("Initial volume",
           Units::mm3_to_mL(initial_volume),
           "mL",
           "must be positive");
  }

  ChamberElastance::ChamberElastance(const Parameters &parameters,
                                     const double      period)
    : params(parameters)
    , period(period)
  {
    AssertThrow(period > 0,
                dealii::ExcMessage("ChamberElastance: the period (" +
                                   format_value(period) +
                                   " ms) must be positive."));
    params.validate("ChamberElastance", period);
  }

  double
  ChamberElastance::activation(const double t) const
  {
    double tau = std::fmod(t - params.contraction_onset, period);
    if (tau < 0)
      tau += period;
    const double T_C = params.contraction_duration;
    if (tau < T_C)
      return 0.5 * (1.0 - std::cos(M_PI * tau / T_C));
    if (tau < T_C + params.relaxation_duration)
      return 0.5 *
             (1.0 + std::cos(M_PI * (tau - T_C) / params.relaxation_duration));
    return 0.0;
  }

  double
  ChamberElastance::elastance(const double t) const
  {
    return params.passive_elastance + params.active_elastance * activation(t);
  }

  double
  ChamberElastance::pressure(const double t, const double volume) const
  {
    return elastance(t) * (volume - params.unloaded_volume);
  }

  // E_A [mmHg/mL], E_B [mmHg/mL], t_C, T_C, T_R [ms], V_0, V(0) [mL].
  ChamberElastance::Parameters
  default_left_atrium()
  {
    return ChamberElastance::Parameters::from_file_units(0.07,
                                                         0.18,
                                                         700,
                                                         170,
                                                         170,
                                                         4,
                                                         87.183);
  }

  ChamberElastance::Parameters
  default_right_atrium()
  {
    return ChamberElastance::Parameters::from_file_units(0.06,
                                                         0.07,
                                                         700,
                                                         170,
                                                         170,
                                                         4,
                                                         86.833);
  }

  ChamberElastance::Parameters
  default_left_ventricle()
  {
    return ChamberElastance::Parameters::from_file_units(4.482,
                                                         0.170,
                                                         100,
                                                         250,
                                                         400,
                                                         42,
                                                         118.520);
  }

  ChamberElastance::Parameters
  default_right_ventricle()
  {
    return ChamberElastance::Parameters::from_file_units(0.200,
                                                         0.029,
                                                         100,
                                                         250,
                                                         400,
                                                         16,
                                                         166.177);
  }
} // namespace systole::Circulation
