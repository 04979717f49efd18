#include "circulation/closed_loop.h"

#include <deal.II/base/parameter_handler.h>

#include "base/units.h"

#include <utility>

namespace systole::Circulation
{
  namespace
  {
    const std::string closed_loop_path = "Circulation / Closed loop";

    constexpr double       mmHg_s_per_mL  = resistance_from_mmHg_s_per_mL(1.0);
    constexpr double       mL_per_mmHg    = compliance_from_mL_per_mmHg(1.0);
    constexpr double       mmHg_s2_per_mL = inductance_from_mmHg_s2_per_mL(1.0);
    constexpr double       one_millisecond = 1.0; ///< [ms], see StateInfo
    constexpr unsigned int n_chambers      = 4;

    /// A compartment's subsection and what lies downstream of it (help).
    struct CompartmentName
    {
      const char *subsection;
      const char *downstream;
    };

    /// The compartments in state order.
    const std::array<CompartmentName, 4> compartment_names = {
      {{"Systemic arteries", "VEN,SYS"},
       {"Systemic veins", "RA"},
       {"Pulmonary arteries", "VEN,PUL"},
       {"Pulmonary veins", "LA"}}};

    /// The compartments of @p p (ClosedLoop::Parameters, const or not), in
    /// the order of compartment_names and of their pressure and flow states.
    template <class P>
    auto
    compartments(P &p)
    {
      return std::array<decltype(&p.systemic_arteries), 4>{
        {&p.systemic_arteries,
         &p.systemic_veins,
         &p.pulmonary_arteries,
         &p.pulmonary_veins}};
    }

    void
    declare_compartment(dealii::ParameterHandler      &prm,
                        const ClosedLoop::Compartment &d,
                        const std::string             &name,
                        const std::string             &downstream)
    {
      using namespace dealii::Patterns;
      const std::string source =
        " Default: reference/physiology.md (Regazzoni et al. 2022).";
      prm.enter_subsection(name);
      prm.declare_entry("Resistance",
                        format_value(d.resistance / mmHg_s_per_mL),
                        Double(0.0),
                        "R of the " + name + ": L dQ/dt = -R Q - (p_" +
                          downstream +
                          " - p). Units: mmHg s/mL (converted to kPa "
                          "ms/mm^3)." +
                          source);
      prm.declare_entry("Compliance",
                        format_value(d.compliance / mL_per_mmHg),
                        Double(0.0),
                        "C of the " + name +
                          ": C dp/dt = inflow - Q. Units: mL/mmHg (converted "
                          "to mm^3/kPa)." +
                          source);
      prm.declare_entry("Inductance",
                        format_value(d.inductance / mmHg_s2_per_mL),
                        Double(0.0),
                        "L (inertance) of the " + name +
                          ". Units: mmHg s^2/mL (converted to kPa "
                          "ms^2/mm^3)." +
                          source);
      prm.declare_entry("Initial pressure",
                        format_value(Units::kPa_to_mmHg(d.initial_pressure)),
                        Double(),
                        "p of the " + name + " at time 0. Units: mmHg." +
                          source);
      prm.declare_entry("Initial flow",
                        format_value(flow_to_mL_per_s(d.initial_flow)),
                        Double(),
                        "Q out of the " + name +
                          " at time 0. Units: mL/s (= mm^3/ms)." + source);
      prm.leave_subsection();
    }

    ClosedLoop::Compartment
    parse_compartment(const dealii::ParameterHandler &prm,
                      const std::string              &name)
    {
      const std::vector<std::string> path = {"Circulation",
                                             "Closed loop",
                                             name};
      return ClosedLoop::Compartment::from_file_units(
        prm.get_double(path, "Resistance"),
        prm.get_double(path, "Compliance"),
        prm.get_double(path, "Inductance"),
        prm.get_double(path, "Initial pressure"),
        prm.get_double(path, "Initial flow"));
    }

    void
    validate_compartment(const ClosedLoop::Compartment &c,
                         const std::string             &name)
    {
      const auto require_positive = [&](const double       value,
                                        const char        *entry,
                                        const std::string &unit) {
        AssertThrow(value > 0,
                    dealii::ExcMessage(closed_loop_path + " / " + name + " / " +
                                       entry + " = " + format_value(value) +
                                       " " + unit + ": must be positive."));
      };
      require_positive(c.resistance / mmHg_s_per_mL, "Resistance", "mmHg s/mL");
      require_positive(c.compliance / mL_per_mmHg, "Compliance", "mL/mmHg");
      require_positive(c.inductance / mmHg_s2_per_mL,
                       "Inductance",
                       "mmHg s^2/mL");
    }

    /// Sparse linear form in the unknowns of the Jacobian: the states
    /// (columns 0 ... n - 1) and the external cavity pressures (n, n + 1).
    using Form = std::vector<std::pair<unsigned int, double>>;

    /// a * x + b * y
    Form
    combine(const double a, const Form &x, const double b, const Form &y)
    {
      Form result;
      for (const auto &[j, v] : x)
        result.emplace_back(j, a * v);
      for (const auto &[j, v] : y)
        result.emplace_back(j, b * v);
      return result;
    }
  } // namespace

  ClosedLoop::Compartment
  ClosedLoop::Compartment::from_file_units(const double R,
                                           const double C,
                                           const double L,
                                           const double p0,
                                           const double Q0)
  {
    return {resistance_from_mmHg_s_per_mL(R),
            compliance_from_mL_per_mmHg(C),
            inductance_from_mmHg_s2_per_mL(L),
            Units::mmHg_to_kPa(p0),
            flow_from_mL_per_s(Q0)};
  }

  void
  ClosedLoop::Parameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    const Parameters d;
    prm.declare_entry(
      "Open valve resistance",
      format_value(d.valve.open_resistance / mmHg_s_per_mL),
      Double(0.0),
      "R_min of the four valves (mitral, aortic, tricuspid, pulmonary), "
      "non-ideal diodes: Q = (p_upstream - p_downstream) / R with R = R_min "
      "while the pressure drop is positive, R_max otherwise. Units: mmHg "
      "s/mL (converted to kPa ms/mm^3). Default: reference/physiology.md.");
    prm.declare_entry(
      "Closed valve resistance",
      format_value(d.valve.closed_resistance / mmHg_s_per_mL),
      Double(0.0),
      "R_max of the four valves (the leak of a closed valve); must exceed "
      "the open valve resistance. Units: mmHg s/mL. Default: "
      "reference/physiology.md.");
    prm.enter_subsection("Left atrium");
    ChamberElastance::Parameters::declare(prm, d.left_atrium, "left atrium");
    prm.leave_subsection();
    prm.enter_subsection("Right atrium");
    ChamberElastance::Parameters::declare(prm, d.right_atrium, "right atrium");
    prm.leave_subsection();
    for (unsigned int i = 0; i < compartment_names.size(); ++i)
      declare_compartment(prm,
                          *compartments(d)[i],
                          compartment_names[i].subsection,
                          compartment_names[i].downstream);
  }

  ClosedLoop::Parameters
  ClosedLoop::Parameters::parse(
    const dealii::ParameterHandler     &prm,
    const double                        period,
    const ChamberElastance::Parameters &left_ventricle,
    const ChamberElastance::Parameters &right_ventricle)
  {
    const std::vector<std::string> path = {"Circulation", "Closed loop"};
    Parameters                     p;
    p.period          = period;
    p.left_ventricle  = left_ventricle;
    p.right_ventricle = right_ventricle;
    p.left_atrium     = ChamberElastance::Parameters::parse(prm,
                                                        {"Circulation",
                                                             "Closed loop",
                                                             "Left atrium"});
    p.right_atrium    = ChamberElastance::Parameters::parse(prm,
                                                         {"Circulation",
                                                             "Closed loop",
                                                             "Right atrium"});
    for (unsigned int i = 0; i < compartment_names.size(); ++i)
      *compartments(p)[i] =
        parse_compartment(prm, compartment_names[i].subsection);
    p.valve.open_resistance = resistance_from_mmHg_s_per_mL(
      prm.get_double(path, "Open valve resistance"));
    p.valve.closed_resistance = resistance_from_mmHg_s_per_mL(
      prm.get_double(path, "Closed valve resistance"));
    p.validate();
    return p;
  }

  void
  ClosedLoop::Parameters::validate() const
  {
    AssertThrow(period > 0,
                dealii::ExcMessage(
                  "Circulation / Period = " + format_value(period) +
                  " ms: must be positive."));
    left_atrium.validate(closed_loop_path + " / Left atrium", period);
    right_atrium.validate(closed_loop_path + " / Right atrium", period);
    left_ventricle.validate("Circulation / Left ventricle", period);
    right_ventricle.validate("Circulation / Right ventricle", period);
    for (unsigned int i = 0; i < compartment_names.size(); ++i)
      validate_compartment(*compartments(*this)[i],
                           compartment_names[i].subsection);
    AssertThrow(valve.open_resistance > 0,
                dealii::ExcMessage(
                  closed_loop_path + " / Open valve resistance = " +
                  format_value(valve.open_resistance / mmHg_s_per_mL) +
                  " mmHg s/mL: must be positive."));
    AssertThrow(valve.closed_resistance > valve.open_resistance,
                dealii::ExcMessage(
                  closed_loop_path + " / Closed valve resistance = " +
                  format_value(valve.closed_resistance / mmHg_s_per_mL) +
                  " mmHg s/mL: must exceed the open valve resistance (" +
                  format_value(valve.open_resistance / mmHg_s_per_mL) + ")."));
  }

  namespace
  {
    const ClosedLoop::Parameters &
    validated(const ClosedLoop::Parameters &parameters)
    {
      parameters.validate();
      return parameters;
    }
  } // namespace

  ClosedLoop::ClosedLoop(const Parameters &parameters)
    : params(validated(parameters))
    , left_atrium(params.left_atrium, params.period)
    , right_atrium(params.right_atrium, params.period)
    , left_ventricle(params.left_ventricle, params.period)
    , right_ventricle(params.right_ventricle, params.period)
  {
    const auto volume   = Quantity::volume;
    const auto pressure = Quantity::pressure;
    const auto flow     = Quantity::flow;
    state_info          = {{"la_volume", volume, 1.0},
                           {"lv_volume", volume, 1.0},
                           {"ra_volume", volume, 1.0},
                           {"rv_volume", volume, 1.0},
                           {"systemic_arterial_pressure",
                            pressure,
                            params.systemic_arteries.compliance},
                           {"systemic_venous_pressure",
                            pressure,
                            params.systemic_veins.compliance},
                           {"pulmonary_arterial_pressure",
                            pressure,
                            params.pulmonary_arteries.compliance},
                           {"pulmonary_venous_pressure",
                            pressure,
                            params.pulmonary_veins.compliance},
                           {"systemic_arterial_flow", flow, one_millisecond},
                           {"systemic_venous_flow", flow, one_millisecond},
                           {"pulmonary_arterial_flow", flow, one_millisecond},
                           {"pulmonary_venous_flow", flow, one_millisecond}};
    cavity_info         = {
              {"lv", params.left_ventricle_kind, lv_volume, mitral, aortic},
              {"rv", params.right_ventricle_kind, rv_volume, tricuspid, pulmonary}};
    valve_info = {{"mitral"}, {"aortic"}, {"tricuspid"}, {"pulmonary"}};
    // One loop: LA -> LV -> systemic -> RA -> RV -> pulmonary -> LA.
    in_series   = true;
    output_info = {{"la_pressure", pressure},
                   {"lv_pressure", pressure},
                   {"ra_pressure", pressure},
                   {"rv_pressure", pressure},
                   {"mitral_valve_flow", flow},
                   {"aortic_valve_flow", flow},
                   {"tricuspid_valve_flow", flow},
                   {"pulmonary_valve_flow", flow}};
  }

  std::string
  ClosedLoop::name() const
  {
    return model_name;
  }

  void
  ClosedLoop::initial_state(dealii::Vector<double> &y) const
  {
    y.reinit(n_state_components);
    y[la_volume] = params.left_atrium.initial_volume;
    y[lv_volume] = params.left_ventricle.initial_volume;
    y[ra_volume] = params.right_atrium.initial_volume;
    y[rv_volume] = params.right_ventricle.initial_volume;
    static_assert(pulmonary_venous_pressure == systemic_arterial_pressure + 3 &&
                    pulmonary_venous_flow == systemic_arterial_flow + 3,
                  "the compartments' states in the order of compartments()");
    for (unsigned int i = 0; i < compartment_names.size(); ++i)
      {
        const Compartment &c              = *compartments(params)[i];
        y[systemic_arterial_pressure + i] = c.initial_pressure;
        y[systemic_arterial_flow + i]     = c.initial_flow;
      }
  }

  std::array<ClosedLoop::Chamber, 4>
  ClosedLoop::chambers() const
  {
    static_assert(la_volume == 0 && lv_volume == 1 && ra_volume == 2 &&
                    rv_volume == 3,
                  "the chambers' volume states in the order of chambers()");
    return {
      {{&left_atrium, false, 0},
       {&left_ventricle, params.left_ventricle_kind == CavityKind::external, 0},
       {&right_atrium, false, 1},
       {&right_ventricle,
        params.right_ventricle_kind == CavityKind::external,
        1}}};
  }

  std::array<double, 4>
  ClosedLoop::chamber_pressures(const Arguments &a) const
  {
    const auto &[t, y, p_ext] = a;
    Assert(y.size() == n_state_components,
           dealii::ExcDimensionMismatch(y.size(), n_state_components));
    Assert(p_ext.size() == 2, dealii::ExcDimensionMismatch(p_ext.size(), 2));
    const auto            c = chambers();
    std::array<double, 4> p;
    for (unsigned int i = 0; i < n_chambers; ++i)
      p[i] =
        c[i].external ? p_ext[c[i].cavity] : c[i].elastance->pressure(t, y[i]);
    return p;
  }

  void
  ClosedLoop::cavity_pressures(const Arguments        &a,
                               dealii::Vector<double> &p) const
  {
    const auto chambers = chamber_pressures(a);
    p.reinit(2);
    p[0] = chambers[1];
    p[1] = chambers[3];
  }

  void
  ClosedLoop::rhs(const Arguments &a, dealii::Vector<double> &f) const
  {
    const dealii::Vector<double> &y     = a.y;
    const auto [p_la, p_lv, p_ra, p_rv] = chamber_pressures(a);
    const auto  &v                      = params.valve;
    const double q_mv                   = v.flow(p_la - p_lv);
    const double q_av = v.flow(p_lv - y[systemic_arterial_pressure]);
    const double q_tv = v.flow(p_ra - p_rv);
    const double q_pv = v.flow(p_rv - y[pulmonary_arterial_pressure]);

    const double q_as = y[systemic_arterial_flow];
    const double q_vs = y[systemic_venous_flow];
    const double q_ap = y[pulmonary_arterial_flow];
    const double q_vp = y[pulmonary_venous_flow];

    f.reinit(n_state_components);
    f[la_volume] = q_vp - q_mv;
    f[lv_volume] = q_mv - q_av;
    f[ra_volume] = q_vs - q_tv;
    f[rv_volume] = q_tv - q_pv;
    // Each compartment (in the order of compartments()): C dp/dt = Q_in - Q,
    // L dQ/dt = -R Q - (p_down - p).
    const std::array<double, 4> q_in   = {{q_av, q_as, q_pv, q_ap}};
    const std::array<double, 4> p_down = {
      {y[systemic_venous_pressure], p_ra, y[pulmonary_venous_pressure], p_la}};
    for (unsigned int i = 0; i < q_in.size(); ++i)
      {
        const Compartment &c              = *compartments(params)[i];
        const double       q              = y[systemic_arterial_flow + i];
        const double       p              = y[systemic_arterial_pressure + i];
        f[systemic_arterial_pressure + i] = (q_in[i] - q) / c.compliance;
        f[systemic_arterial_flow + i] =
          (-c.resistance * q - (p_down[i] - p)) / c.inductance;
      }
  }

  void
  ClosedLoop::jacobian(const Arguments            &a,
                       dealii::FullMatrix<double> &df_dy,
                       dealii::FullMatrix<double> &df_dp) const
  {
    const double                  t     = a.t;
    const dealii::Vector<double> &y     = a.y;
    const unsigned int            n     = n_state_components;
    const auto [p_la, p_lv, p_ra, p_rv] = chamber_pressures(a);

    // The pressures as linear forms in (y, p_ext).
    const auto          c = chambers();
    std::array<Form, 4> d_chamber;
    for (unsigned int i = 0; i < n_chambers; ++i)
      d_chamber[i] = c[i].external ? Form{{n + c[i].cavity, 1.0}}
                                   : Form{{i, c[i].elastance->elastance(t)}};
    const Form &d_la = d_chamber[la_volume], &d_lv = d_chamber[lv_volume],
               &d_ra = d_chamber[ra_volume], &d_rv = d_chamber[rv_volume];
    const Form d_as = {{systemic_arterial_pressure, 1.0}};
    const Form d_vs = {{systemic_venous_pressure, 1.0}};
    const Form d_ap = {{pulmonary_arterial_pressure, 1.0}};
    const Form d_vp = {{pulmonary_venous_pressure, 1.0}};

    // Valve flows: dQ = (1 / R) (dp_up - dp_down), R on the current side.
    const auto &v     = params.valve;
    const auto  valve = [&](const double p_up,
                           const double p_down,
                           const Form  &d_up,
                           const Form  &d_down) {
      const double g = v.conductance(p_up - p_down);
      return combine(g, d_up, -g, d_down);
    };
    const Form d_mv  = valve(p_la, p_lv, d_la, d_lv);
    const Form d_av  = valve(p_lv, y[systemic_arterial_pressure], d_lv, d_as);
    const Form d_tv  = valve(p_ra, p_rv, d_ra, d_rv);
    const Form d_pv  = valve(p_rv, y[pulmonary_arterial_pressure], d_rv, d_ap);
    const Form d_qas = {{systemic_arterial_flow, 1.0}};
    const Form d_qvs = {{systemic_venous_flow, 1.0}};
    const Form d_qap = {{pulmonary_arterial_flow, 1.0}};
    const Form d_qvp = {{pulmonary_venous_flow, 1.0}};

    // Row i of f as a linear form.
    std::array<Form, n_state_components> rows;
    rows[la_volume] = combine(1, d_qvp, -1, d_mv);
    rows[lv_volume] = combine(1, d_mv, -1, d_av);
    rows[ra_volume] = combine(1, d_qvs, -1, d_tv);
    rows[rv_volume] = combine(1, d_tv, -1, d_pv);
    // The compartments as in rhs(): C dp/dt = Q_in - Q, L dQ/dt = -R Q -
    // p_down + p.
    const std::array<const Form *, 4> d_in   = {{&d_av, &d_qas, &d_pv, &d_qap}};
    const std::array<const Form *, 4> d_down = {{&d_vs, &d_ra, &d_vp, &d_la}};
    const std::array<const Form *, 4> d_p    = {{&d_as, &d_vs, &d_ap, &d_vp}};
    const std::array<const Form *, 4> d_q = {{&d_qas, &d_qvs, &d_qap, &d_qvp}};
    for (unsigned int i = 0; i < d_in.size(); ++i)
      {
        const Compartment &c = *compartments(params)[i];
        rows[systemic_arterial_pressure + i] =
          combine(1 / c.compliance, *d_in[i], -1 / c.compliance, *d_q[i]);
        rows[systemic_arterial_flow + i] =
          combine(1.0 / c.inductance,
                  combine(-c.resistance, *d_q[i], 1.0, *d_p[i]),
                  -1.0 / c.inductance,
                  *d_down[i]);
      }

    df_dy.reinit(n, n);
    df_dp.reinit(n, 2);
    for (unsigned int i = 0; i < n; ++i)
      for (const auto &[j, value] : rows[i])
        if (j < n)
          df_dy(i, j) += value;
        else
          df_dp(i, j - n) += value;
  }

  void
  ClosedLoop::valve_indicators(const Arguments        &a,
                               dealii::Vector<double> &g) const
  {
    const dealii::Vector<double> &y     = a.y;
    const auto [p_la, p_lv, p_ra, p_rv] = chamber_pressures(a);
    g.reinit(4);
    g[mitral]    = p_la - p_lv;
    g[aortic]    = p_lv - y[systemic_arterial_pressure];
    g[tricuspid] = p_ra - p_rv;
    g[pulmonary] = p_rv - y[pulmonary_arterial_pressure];
  }

  void
  ClosedLoop::evaluate_outputs(const Arguments        &a,
                               dealii::Vector<double> &values) const
  {
    const auto             chambers = chamber_pressures(a);
    dealii::Vector<double> g;
    valve_indicators(a, g);
    values.reinit(n_chambers + 4);
    for (unsigned int i = 0; i < n_chambers; ++i)
      values[i] = chambers[i];
    for (unsigned int i = 0; i < 4; ++i)
      values[n_chambers + i] = params.valve.flow(g[i]);
  }

  double
  ClosedLoop::total_blood_volume(const dealii::Vector<double> &y) const
  {
    return y[la_volume] + y[lv_volume] + y[ra_volume] + y[rv_volume] +
           params.systemic_arteries.compliance * y[systemic_arterial_pressure] +
           params.systemic_veins.compliance * y[systemic_venous_pressure] +
           params.pulmonary_arteries.compliance *
             y[pulmonary_arterial_pressure] +
           params.pulmonary_veins.compliance * y[pulmonary_venous_pressure];
  }
} // namespace systole::Circulation
