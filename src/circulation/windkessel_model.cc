#include "circulation/windkessel_model.h"

#include <deal.II/base/parameter_handler.h>

#include "base/units.h"
#include "circulation/parameters.h"


namespace systole::Circulation
{
  namespace
  {
    constexpr double mmHg_s_per_mL  = resistance_from_mmHg_s_per_mL(1.0);
    constexpr double mmHg_s2_per_mL = inductance_from_mmHg_s2_per_mL(1.0);

    enum State : unsigned int
    {
      volume            = 0,
      arterial_pressure = 1,
      arterial_flow     = 2
    };

    const WindkesselModel::Parameters &
    validated(const WindkesselModel::Parameters &parameters)
    {
      parameters.validate();
      return parameters;
    }
  } // namespace

  void
  WindkesselModel::Parameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    const Parameters d;
    prm.declare_entry(
      "Closed valve resistance",
      format_value(d.aortic_valve.closed_resistance / mmHg_s_per_mL),
      Double(0.0),
      "R_max of the mitral and aortic valves of Model = 2-, 3- and 4-element "
      "Windkessel, non-ideal diodes: Q = (p_upstream - p_downstream) / R, "
      "R = R_min (Mitral valve resistance, Aortic valve resistance) while "
      "the pressure drop is positive, R_max otherwise (the leak of a closed "
      "valve). Units: mmHg s/mL (converted to kPa ms/mm^3). Default: "
      "reference/physiology.md (Regazzoni et al. 2022).");
    prm.enter_subsection("4-element Windkessel");
    prm.declare_entry(
      "Inductance",
      format_value(d.inductance / mmHg_s2_per_mL),
      Double(0.0),
      "L, the inertance of the blood in series with the characteristic "
      "impedance (Model = 4-element Windkessel; the law of "
      "reference/physiology.md). Units: mmHg s^2/mL (converted to kPa "
      "ms^2/mm^3). Default: the systemic arterial inertance of the closed "
      "loop.");
    prm.declare_entry("Initial flow",
                      format_value(flow_to_mL_per_s(d.initial_arterial_flow)),
                      Double(),
                      "Flow through the inductance at time 0. Units: mL/s "
                      "(= mm^3/ms).");
    prm.leave_subsection();
  }

  WindkesselModel::Parameters
  WindkesselModel::Parameters::parse(
    const dealii::ParameterHandler     &prm,
    const unsigned int                  n_elements,
    const double                        period,
    const ChamberElastance::Parameters &left_ventricle)
  {
    // The Windkessel entries shared with the heartbeat.
    const auto shared = Circulation::Parameters::parse(prm);
    Parameters p;
    p.n_elements                = n_elements;
    p.period                    = period;
    p.peripheral_resistance     = shared.windkessel.peripheral_resistance;
    p.compliance                = shared.windkessel.compliance;
    p.characteristic_impedance  = shared.windkessel.characteristic_impedance;
    p.venous_pressure           = shared.windkessel.venous_pressure;
    p.atrial_pressure           = shared.atrial_pressure;
    p.initial_arterial_pressure = shared.initial_arterial_pressure;
    const double closed         = resistance_from_mmHg_s_per_mL(
      prm.get_double({"Circulation"}, "Closed valve resistance"));
    p.mitral_valve = {shared.mitral_valve_resistance, closed};
    p.aortic_valve = {shared.windkessel.aortic_valve_resistance, closed};
    p.inductance   = inductance_from_mmHg_s2_per_mL(
      prm.get_double({"Circulation", "4-element Windkessel"}, "Inductance"));
    p.initial_arterial_flow = flow_from_mL_per_s(
      prm.get_double({"Circulation", "4-element Windkessel"}, "Initial flow"));
    p.left_ventricle = left_ventricle;
    p.validate();
    return p;
  }

  void
  WindkesselModel::Parameters::validate() const
  {
    const std::string model =
      std::to_string(n_elements) + "-element Windkessel";
    AssertThrow(n_elements >= 2 && n_elements <= 4,
                dealii::ExcMessage("WindkesselModel: " + model +
                                   " does not exist (2, 3 or 4 elements)."));
    const auto require_positive = [&](const double       value,
                                      const std::string &entry,
                                      const std::string &unit) {
      AssertThrow(value > 0,
                  dealii::ExcMessage("Circulation / " + entry + " = " +
                                     format_value(value) + " " + unit +
                                     ": must be positive (Model = " + model +
                                     ")."));
    };
    require_positive(peripheral_resistance / mmHg_s_per_mL,
                     "Peripheral resistance",
                     "mmHg s/mL");
    require_positive(compliance / compliance_from_mL_per_mmHg(1.0),
                     "Compliance",
                     "mL/mmHg");
    if (n_elements >= 3)
      require_positive(characteristic_impedance / mmHg_s_per_mL,
                       "Characteristic impedance",
                       "mmHg s/mL");
    if (n_elements == 4)
      require_positive(inductance / mmHg_s2_per_mL,
                       "4-element Windkessel / Inductance",
                       "mmHg s^2/mL");
    require_positive(mitral_valve.open_resistance / mmHg_s_per_mL,
                     "Mitral valve resistance",
                     "mmHg s/mL");
    require_positive(aortic_valve.open_resistance / mmHg_s_per_mL,
                     "Aortic valve resistance",
                     "mmHg s/mL");
    for (const DiodeValve &v : {mitral_valve, aortic_valve})
      AssertThrow(v.closed_resistance > v.open_resistance,
                  dealii::ExcMessage(
                    "Circulation / Closed valve resistance = " +
                    format_value(v.closed_resistance / mmHg_s_per_mL) +
                    " mmHg s/mL: must exceed the mitral and aortic valve "
                    "resistances (" +
                    format_value(v.open_resistance / mmHg_s_per_mL) + ")."));
    left_ventricle.validate("Circulation / Left ventricle", period);
  }

  WindkesselModel::WindkesselModel(const Parameters &parameters)
    : params(validated(parameters))
    , left_ventricle(params.left_ventricle, params.period)
  {
    state_info = {{"lv_volume", Quantity::volume, 1.0},
                  {"arterial_pressure", Quantity::pressure, params.compliance}};
    if (params.n_elements == 4)
      state_info.push_back({"arterial_flow", Quantity::flow, 1.0});
    cavity_info = {{"lv", params.left_ventricle_kind, volume, 0, 1}};
    valve_info  = {{"mitral"}, {"aortic"}};
    output_info = {{"lv_pressure", Quantity::pressure},
                   {"atrial_pressure", Quantity::pressure},
                   {"aortic_root_pressure", Quantity::pressure},
                   {"mitral_valve_flow", Quantity::flow},
                   {"aortic_valve_flow", Quantity::flow}};
  }

  std::string
  WindkesselModel::name() const
  {
    return std::to_string(params.n_elements) + "-element Windkessel";
  }

  void
  WindkesselModel::initial_state(dealii::Vector<double> &y) const
  {
    y.reinit(n_states());
    y[volume]            = params.left_ventricle.initial_volume;
    y[arterial_pressure] = params.initial_arterial_pressure;
    if (params.n_elements == 4)
      y[arterial_flow] = params.initial_arterial_flow;
  }

  double
  WindkesselModel::lv_pressure(const Arguments &a) const
  {
    const auto &[t, y, p_ext] = a;
    Assert(y.size() == n_states(),
           dealii::ExcDimensionMismatch(y.size(), n_states()));
    Assert(p_ext.size() == 1, dealii::ExcDimensionMismatch(p_ext.size(), 1));
    return params.left_ventricle_kind == CavityKind::external
             ? p_ext[0]
             : left_ventricle.pressure(t, y[volume]);
  }

  double
  WindkesselModel::aortic_flow(const double                  p_lv,
                               const dealii::Vector<double> &y) const
  {
    if (params.n_elements == 4)
      return y[arterial_flow];
    const double dp = p_lv - y[arterial_pressure];
    const double z =
      params.n_elements == 3 ? params.characteristic_impedance : 0.0;
    return dp / (params.aortic_valve.resistance(dp) + z);
  }

  void
  WindkesselModel::cavity_pressures(const Arguments        &a,
                                    dealii::Vector<double> &p) const
  {
    p.reinit(1);
    p[0] = lv_pressure(a);
  }

  void
  WindkesselModel::rhs(const Arguments &a, dealii::Vector<double> &f) const
  {
    const double p    = lv_pressure(a);
    const double q_mv = params.mitral_valve.flow(params.atrial_pressure - p);
    const double q_av = aortic_flow(p, a.y);
    const double p_ar = a.y[arterial_pressure];
    f.reinit(n_states());
    f[volume] = q_mv - q_av;
    f[arterial_pressure] =
      (q_av - (p_ar - params.venous_pressure) / params.peripheral_resistance) /
      params.compliance;
    if (params.n_elements == 4)
      f[arterial_flow] = (p - p_ar -
                          (params.aortic_valve.resistance(q_av) +
                           params.characteristic_impedance) *
                            q_av) /
                         params.inductance;
  }

  void
  WindkesselModel::jacobian(const Arguments            &a,
                            dealii::FullMatrix<double> &df_dy,
                            dealii::FullMatrix<double> &df_dp) const
  {
    const dealii::Vector<double> &y = a.y;
    const unsigned int            n = n_states();
    df_dy.reinit(n, n);
    df_dp.reinit(n, 1);
    const bool   external = params.left_ventricle_kind == CavityKind::external;
    const double p        = lv_pressure(a);
    // dp/dV (elastance) or dp/dp_ext (external).
    const double dp_dV    = external ? 0.0 : left_ventricle.elastance(a.t);
    const double dp_dpext = external ? 1.0 : 0.0;
    const double g_mv =
      params.mitral_valve.conductance(params.atrial_pressure - p);
    const double C = params.compliance;

    // d Q_mv = -g_mv dp
    df_dy(volume, volume) += -g_mv * dp_dV;
    df_dp(volume, 0) += -g_mv * dp_dpext;
    if (params.n_elements < 4)
      {
        // Q_av = (p - p_ar) / (R + Z_c): d Q_av = s (dp - dp_ar)
        const double dp = p - y[arterial_pressure];
        const double z =
          params.n_elements == 3 ? params.characteristic_impedance : 0.0;
        const double s = 1.0 / (params.aortic_valve.resistance(dp) + z);
        df_dy(volume, volume) += -s * dp_dV;
        df_dy(volume, arterial_pressure) += s;
        df_dp(volume, 0) += -s * dp_dpext;
        df_dy(arterial_pressure, volume) += s * dp_dV / C;
        df_dy(arterial_pressure, arterial_pressure) +=
          (-s - 1.0 / params.peripheral_resistance) / C;
        df_dp(arterial_pressure, 0) += s * dp_dpext / C;
      }
    else
      {
        const double q = y[arterial_flow];
        const double L = params.inductance;
        df_dy(volume, arterial_flow) += -1.0;
        df_dy(arterial_pressure, arterial_flow) += 1.0 / C;
        df_dy(arterial_pressure, arterial_pressure) +=
          -1.0 / (params.peripheral_resistance * C);
        // L dQ/dt = p - p_ar - (R(Q) + Z_c) Q, R piecewise constant
        df_dy(arterial_flow, volume) += dp_dV / L;
        df_dp(arterial_flow, 0) += dp_dpext / L;
        df_dy(arterial_flow, arterial_pressure) += -1.0 / L;
        df_dy(arterial_flow, arterial_flow) +=
          -(params.aortic_valve.resistance(q) +
            params.characteristic_impedance) /
          L;
      }
  }

  void
  WindkesselModel::valve_indicators(const Arguments        &a,
                                    dealii::Vector<double> &g) const
  {
    const double p = lv_pressure(a);
    g.reinit(2);
    g[0] = params.atrial_pressure - p;
    g[1] =
      params.n_elements == 4 ? a.y[arterial_flow] : p - a.y[arterial_pressure];
  }

  void
  WindkesselModel::evaluate_outputs(const Arguments        &a,
                                    dealii::Vector<double> &values) const
  {
    const double p    = lv_pressure(a);
    const double q_av = aortic_flow(p, a.y);
    double       root = a.y[arterial_pressure];
    if (params.n_elements == 3)
      root += params.characteristic_impedance * q_av;
    else if (params.n_elements == 4)
      root = p - params.aortic_valve.resistance(q_av) * q_av;
    values.reinit(5);
    values[0] = p;
    values[1] = params.atrial_pressure;
    values[2] = root;
    values[3] = params.mitral_valve.flow(params.atrial_pressure - p);
    values[4] = q_av;
  }

  double
  WindkesselModel::total_blood_volume(const dealii::Vector<double> &y) const
  {
    return y[volume] + params.compliance * y[arterial_pressure];
  }
} // namespace systole::Circulation
