#include <deal.II/base/parameter_handler.h>

#include "base/units.h"
#include "circulation/closed_loop.h"
#include "circulation/model_factory.h"
#include "circulation/ode_integrator.h"
#include "circulation/parameters.h"
#include "circulation/windkessel_model.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <memory>
#include <string>
#include <vector>

using namespace systole;
using namespace systole::Circulation;

namespace
{
  using Vector = dealii::Vector<double>;

  /// A model with its name in the test output.
  struct Case
  {
    std::string            label;
    std::unique_ptr<Model> model;
  };

  /// Every table entry, with elastance and with external ventricles.
  std::vector<Case>
  all_models()
  {
    std::vector<Case> cases;
    for (const CavityKind kind : {CavityKind::elastance, CavityKind::external})
      {
        const std::string k =
          kind == CavityKind::elastance ? " (elastance)" : " (external)";
        ClosedLoop::Parameters c;
        c.left_ventricle_kind = c.right_ventricle_kind = kind;
        cases.push_back({"closed loop" + k, std::make_unique<ClosedLoop>(c)});
        for (unsigned int n = 2; n <= 4; ++n)
          {
            WindkesselModel::Parameters w;
            w.n_elements          = n;
            w.left_ventricle_kind = kind;
            cases.push_back({std::to_string(n) + "-element Windkessel" + k,
                             std::make_unique<WindkesselModel>(w)});
          }
      }
    return cases;
  }

  /// States along one beat of the model with elastance ventricles (valves
  /// open and closed), every 40 ms, and the cavity pressures there.
  void
  trajectory(const Model         &model,
             std::vector<double> &times,
             std::vector<Vector> &states)
  {
    // The same model with 0D ventricles drives the states; an external
    // cavity then gets the elastance pressure of its row (below).
    Vector               y;
    Integrator::Settings settings;
    settings.relative_tolerance = 1e-6;
    times.clear();
    states.clear();
    // Integrate the elastance variant of the same kind of model.
    std::unique_ptr<Model> driver;
    if (const auto *c = dynamic_cast<const ClosedLoop *>(&model))
      {
        auto p                 = c->parameters();
        p.left_ventricle_kind  = CavityKind::elastance;
        p.right_ventricle_kind = CavityKind::elastance;
        driver                 = std::make_unique<ClosedLoop>(p);
      }
    else
      {
        auto p = dynamic_cast<const WindkesselModel &>(model).parameters();
        p.left_ventricle_kind = CavityKind::elastance;
        driver                = std::make_unique<WindkesselModel>(p);
      }
    driver->initial_state(y);
    Integrator integrator(*driver, settings, 0.0, y);
    for (double t = 40; t <= 800; t += 40)
      {
        integrator.advance(t);
        times.push_back(t);
        states.push_back(integrator.state());
      }
  }

  /// External pressures equal to the elastance pressures of the default
  /// ventricles at (t, y).
  Vector
  external_pressures(const Model &model, const double t, const Vector &y)
  {
    Vector                 p(model.n_cavities());
    const ChamberElastance lv(default_left_ventricle(), 800.0);
    const ChamberElastance rv(default_right_ventricle(), 800.0);
    p[0] = lv.pressure(t, y[model.cavities()[0].volume_state]);
    if (model.n_cavities() > 1)
      p[1] = rv.pressure(t, y[model.cavities()[1].volume_state]);
    return p;
  }

  /// Whether every valve indicator keeps its sign between @p a and @p b.
  bool
  same_valve_states(const Model  &model,
                    const double  t,
                    const Vector &y_a,
                    const Vector &p_a,
                    const Vector &y_b,
                    const Vector &p_b)
  {
    Vector g_a, g_b;
    model.valve_indicators({t, y_a, p_a}, g_a);
    model.valve_indicators({t, y_b, p_b}, g_b);
    for (unsigned int i = 0; i < g_a.size(); ++i)
      if ((g_a[i] > 0) != (g_b[i] > 0))
        return false;
    return true;
  }
} // namespace

TEST_CASE("Every circulation model's Jacobians equal central differences of "
          "its right-hand side",
          "[circulation][fd]")
{
  for (const auto &c : all_models())
    {
      const Model &model = *c.model;
      INFO(c.label);
      std::vector<double> times;
      std::vector<Vector> states;
      trajectory(model, times, states);
      unsigned int n_checked = 0;
      for (unsigned int s = 0; s < states.size(); ++s)
        {
          const double  t = times[s];
          const Vector &y = states[s];
          const Vector  p = external_pressures(model, t, y);
          INFO("t = " << t << " ms");
          dealii::FullMatrix<double> df_dy, df_dp;
          model.jacobian({t, y, p}, df_dy, df_dp);
          REQUIRE(df_dy.m() == model.n_states());
          REQUIRE(df_dy.n() == model.n_states());
          REQUIRE(df_dp.m() == model.n_states());
          REQUIRE(df_dp.n() == model.n_cavities());

          Vector f;
          model.rhs({t, y, p}, f);
          // Size of the terms of f_i, for the round-off of differences.
          std::vector<double> row_scale(model.n_states());
          for (unsigned int i = 0; i < model.n_states(); ++i)
            {
              row_scale[i] = std::abs(f[i]);
              for (unsigned int k = 0; k < model.n_states(); ++k)
                row_scale[i] += std::abs(df_dy(i, k) * y[k]);
              for (unsigned int k = 0; k < model.n_cavities(); ++k)
                row_scale[i] += std::abs(df_dp(i, k) * p[k]);
            }

          // f is piecewise linear in (y, p_ext) at fixed t (elastance
          // pressures, diode valves, R-C-L compartments), so the central
          // difference is exact up to round-off within one valve state;
          // steps that would switch a valve are skipped.
          const auto check_column = [&](const Vector &y_plus,
                                        const Vector &p_plus,
                                        const Vector &y_minus,
                                        const Vector &p_minus,
                                        const double  h,
                                        const auto   &analytic) {
            if (!same_valve_states(model, t, y_plus, p_plus, y, p) ||
                !same_valve_states(model, t, y_minus, p_minus, y, p))
              return;
            Vector f_plus, f_minus;
            model.rhs({t, y_plus, p_plus}, f_plus);
            model.rhs({t, y_minus, p_minus}, f_minus);
            for (unsigned int i = 0; i < model.n_states(); ++i)
              {
                const double fd = (f_plus[i] - f_minus[i]) / (2 * h);
                CHECK(fd == Approx(analytic(i))
                              .epsilon(1e-7)
                              .margin(1e-13 * row_scale[i] / h));
              }
            ++n_checked;
          };
          for (unsigned int j = 0; j < model.n_states(); ++j)
            {
              const double h      = 1e-4 * std::max(std::abs(y[j]), 1e-3);
              Vector       y_plus = y, y_minus = y;
              y_plus[j] += h;
              y_minus[j] -= h;
              check_column(y_plus, p, y_minus, p, h, [&](unsigned int i) {
                return df_dy(i, j);
              });
            }
          for (unsigned int j = 0; j < model.n_cavities(); ++j)
            {
              const double h      = 1e-4 * std::max(std::abs(p[j]), 1e-2);
              Vector       p_plus = p, p_minus = p;
              p_plus[j] += h;
              p_minus[j] -= h;
              check_column(y, p_plus, y, p_minus, h, [&](unsigned int i) {
                return df_dp(i, j);
              });
              // An elastance cavity's pressure is no input.
              if (model.cavities()[j].kind == CavityKind::elastance)
                for (unsigned int i = 0; i < model.n_states(); ++i)
                  CHECK(df_dp(i, j) == 0.0);
            }
        }
      // Most columns are checked (few steps switch a valve).
      CHECK(n_checked >=
            0.9 * states.size() * (model.n_states() + model.n_cavities()));
    }
}

TEST_CASE("The closed loop conserves the blood volume: its flows cancel",
          "[circulation][conservation]")
{
  for (const CavityKind kind : {CavityKind::elastance, CavityKind::external})
    {
      ClosedLoop::Parameters params;
      params.left_ventricle_kind = params.right_ventricle_kind = kind;
      const ClosedLoop    model(params);
      std::vector<double> times;
      std::vector<Vector> states;
      trajectory(model, times, states);
      for (unsigned int s = 0; s < states.size(); ++s)
        {
          const Vector p = external_pressures(model, times[s], states[s]);
          Vector       f;
          model.rhs({times[s], states[s], p}, f);
          // d(blood volume)/dt = sum of the volume weights times f: the
          // blood volume is linear in y, its weights are its differences.
          Vector unit(model.n_states());
          double rate = 0, scale = 0;
          for (unsigned int i = 0; i < model.n_states(); ++i)
            {
              unit           = 0;
              unit[i]        = 1;
              const double w = model.total_blood_volume(unit);
              rate += w * f[i];
              scale += std::abs(w * f[i]);
            }
          CHECK(std::abs(rate) <= 1e-13 * scale);
        }
    }

  // Over two beats of the integrator, to round-off (the Runge-Kutta update
  // keeps linear invariants), at a loose tolerance.
  const ClosedLoop model{ClosedLoop::Parameters()};
  Vector           y;
  model.initial_state(y);
  const double         v0 = model.total_blood_volume(y);
  Integrator::Settings settings;
  settings.relative_tolerance = 1e-4;
  Integrator integrator(model, settings, 0.0, y);
  for (double t = 10; t <= 1600; t += 10)
    {
      integrator.advance(t);
      CHECK(std::abs(model.total_blood_volume(integrator.state()) - v0) <=
            1e-12 * v0);
    }
}

namespace
{
  /// The Windkessel model of @p n elements with an external ventricle and
  /// test-friendly constants: R_p = 1, C = 0.2 mmHg s/mL, mL/mmHg (R_p C =
  /// 200 ms, so that transients die within a few beats), Z_c 0.05, L 0.005,
  /// p_ven = 0, diode valves R_min 0.0075.
  WindkesselModel::Parameters
  windkessel_parameters(const unsigned int n)
  {
    WindkesselModel::Parameters w;
    w.n_elements            = n;
    w.compliance            = compliance_from_mL_per_mmHg(0.2);
    w.left_ventricle_kind   = CavityKind::external;
    w.venous_pressure       = 0;
    w.atrial_pressure       = Units::mmHg_to_kPa(10.0);
    w.peripheral_resistance = resistance_from_mmHg_s_per_mL(1.0);
    return w;
  }

  /// The input impedance of the Windkessel from the 4-element law of
  /// reference/physiology.md, C p' + p/R_p - (1 + Z_c/R_p) Q - (C Z_c +
  /// L/R_p) Q' - L C Q'' = 0, at s = i omega: p = Z(s) Q with
  /// Z = ((1 + Z_c/R_p) + s (C Z_c + L/R_p) + s^2 L C) / (s C + 1/R_p).
  std::complex<double>
  law_impedance(const WindkesselModel::Parameters &w, const double omega)
  {
    const std::complex<double> s(0.0, omega);
    const double               R = w.peripheral_resistance, C = w.compliance;
    const double Z = w.n_elements >= 3 ? w.characteristic_impedance : 0.0;
    const double L = w.n_elements == 4 ? w.inductance : 0.0;
    return ((1.0 + Z / R) + s * (C * Z + L / R) + s * s * L * C) /
           (s * C + 1.0 / R);
  }
} // namespace

TEST_CASE("The 2-element Windkessel behind a closed valve decays "
          "exponentially",
          "[circulation][analytic]")
{
  // Cavity pressure 0 < p_ar: the aortic valve leaks through R_max, so
  // C p' = (0 - p)/R_max - p/R_p: p = p(0) exp(-t/tau), 1/tau = (1/R_max +
  // 1/R_p)/C.
  const auto            w = windkessel_parameters(2);
  const WindkesselModel model(w);
  Vector                y;
  model.initial_state(y);
  const double p0 = y[1];
  CHECK(p0 == Approx(Units::mmHg_to_kPa(80.0)));
  Integrator::Settings settings;
  settings.relative_tolerance        = 1e-10;
  settings.absolute_volume_tolerance = 1e-9;
  Integrator   integrator(model, settings, 0.0, y, [](double, Vector &p) {
    p = 0;
  });
  const double tau = w.compliance / (1.0 / w.aortic_valve.closed_resistance +
                                     1.0 / w.peripheral_resistance);
  CHECK(tau == Approx(200.0).epsilon(1e-4)); // R_max >> R_p
  for (const double t : {50.0, 200.0, 500.0, 1000.0})
    {
      const auto events = integrator.advance(t);
      CHECK(events.empty());
      const double exact = p0 * std::exp(-t / tau);
      CHECK(integrator.state()[1] == Approx(exact).epsilon(1e-8));
    }
}

TEST_CASE("The 2-, 3- and 4-element Windkessels driven by a sinusoidal "
          "pressure follow the published law's impedance",
          "[circulation][analytic]")
{
  // Cavity pressure P0 + A sin(omega t) with the aortic valve open
  // throughout: the Windkessel and the valve's R_min in series are a linear
  // system, whose periodic solution is Q = Q0 + Im(Q1 exp(i omega t)) with
  // Q0 = P0 / (R_min + Z(0)), Q1 = A / (R_min + Z(i omega)), Z the input
  // impedance of the law, and distal pressure p_ar = Im-part of R_p / (1 +
  // i omega R_p C) times Q (the compliance parallel to R_p). Started on it,
  // the integration must stay on it.
  const double P0    = Units::mmHg_to_kPa(100.0);
  const double A     = Units::mmHg_to_kPa(5.0);
  const double omega = 2 * M_PI / 800.0;
  for (unsigned int n = 2; n <= 4; ++n)
    {
      INFO(n << "-element Windkessel");
      const auto            w = windkessel_parameters(n);
      const WindkesselModel model(w);
      const double          R_min = w.aortic_valve.open_resistance;
      const double          Q0    = P0 / (R_min + law_impedance(w, 0.0).real());
      const std::complex<double> Q1 = A / (R_min + law_impedance(w, omega));
      const std::complex<double> distal =
        w.peripheral_resistance /
        (1.0 + std::complex<double>(0, omega) * w.peripheral_resistance *
                 w.compliance);
      const std::complex<double> P1_distal  = distal * Q1;
      const auto                 exact_flow = [&](const double t) {
        return Q0 +
               std::imag(Q1 * std::exp(std::complex<double>(0, omega * t)));
      };
      const auto exact_distal = [&](const double t) {
        return w.peripheral_resistance * Q0 +
               std::imag(P1_distal *
                         std::exp(std::complex<double>(0, omega * t)));
      };
      // Root pressure of the law: p = Z Q.
      const auto exact_root = [&](const double t) {
        return law_impedance(w, 0.0).real() * Q0 +
               std::imag(law_impedance(w, omega) * Q1 *
                         std::exp(std::complex<double>(0, omega * t)));
      };

      Vector y;
      model.initial_state(y);
      y[1] = exact_distal(0.0);
      if (n == 4)
        y[2] = exact_flow(0.0);
      Integrator::Settings settings;
      settings.relative_tolerance        = 1e-10;
      settings.absolute_volume_tolerance = 1e-9;
      settings.max_step                  = 5.0;
      Integrator integrator(model, settings, 0.0, y, [&](double t, Vector &p) {
        p[0] = P0 + A * std::sin(omega * t);
      });
      REQUIRE(integrator.valves_open()[1]);
      Vector p(1), outputs;
      for (double t = 25; t <= 1600; t += 25)
        {
          integrator.advance(t);
          p[0] = P0 + A * std::sin(omega * t);
          model.evaluate_outputs({t, integrator.state(), p}, outputs);
          const double q = outputs[4], root = outputs[2];
          CHECK(q == Approx(exact_flow(t)).epsilon(1e-7));
          CHECK(integrator.state()[1] == Approx(exact_distal(t)).epsilon(1e-7));
          CHECK(root == Approx(exact_root(t)).epsilon(1e-7));
        }
      CHECK(integrator.valves_open()[1]); // no aortic closure
    }
}

TEST_CASE("The closed loop's valves open and close once per beat, each "
          "event located on its indicator's zero",
          "[circulation][events]")
{
  const ClosedLoop model{ClosedLoop::Parameters()};
  Vector           y;
  model.initial_state(y);
  Integrator::Settings settings;
  settings.relative_tolerance = 1e-8;
  Integrator                     integrator(model, settings, 0.0, y);
  std::vector<Integrator::Event> events;
  for (double t = 20; t <= 1600; t += 20)
    for (const auto &e : integrator.advance(t))
      events.push_back(e);
  // Beat 2 (800-1600 ms): every valve closes once and opens once.
  std::vector<int>                           opened(4, 0), closed(4, 0);
  std::vector<std::pair<unsigned int, bool>> lv_sequence;
  const Vector                               p_ext(2);
  for (const auto &e : events)
    {
      Vector g;
      model.valve_indicators({e.time, e.state, p_ext}, g);
      // Located on the zero: the pressure drop is tiny against the valve's
      // pressures (about 10 ... 120 mmHg).
      CHECK(std::abs(Units::kPa_to_mmHg(g[e.valve])) < 1e-6);
      if (e.time <= 800)
        continue;
      (e.opens ? opened : closed)[e.valve] += 1;
      if (e.valve == ClosedLoop::mitral || e.valve == ClosedLoop::aortic)
        lv_sequence.emplace_back(e.valve, e.opens);
    }
  CHECK(opened == std::vector<int>{1, 1, 1, 1});
  CHECK(closed == std::vector<int>{1, 1, 1, 1});
  // The left ventricle's cycle: mitral closes, aortic opens, aortic closes,
  // mitral opens.
  const std::vector<std::pair<unsigned int, bool>> expected = {
    {ClosedLoop::mitral, false},
    {ClosedLoop::aortic, true},
    {ClosedLoop::aortic, false},
    {ClosedLoop::mitral, true}};
  CHECK(lv_sequence == expected);
}

namespace
{
  dealii::ParameterHandler &
  declared(dealii::ParameterHandler &prm)
  {
    Circulation::Parameters::declare(prm);
    declare_model_parameters(prm);
    return prm;
  }

  std::string
  create_error(const std::string &lines)
  {
    dealii::ParameterHandler prm;
    declared(prm);
    try
      {
        prm.parse_input_from_string("subsection Circulation\n" + lines +
                                    "end\n");
        create_model(prm);
      }
    catch (const std::exception &e)
      {
        return e.what();
      }
    return "";
  }
} // namespace

TEST_CASE("The circulation model table builds every model from the "
          "parameter file, defaults as in physiology.md",
          "[circulation]")
{
  CHECK(models().names() == std::vector<std::string>{"2-element Windkessel",
                                                     "3-element Windkessel",
                                                     "4-element Windkessel",
                                                     "closed loop"});
  for (const auto &name : models().names())
    {
      dealii::ParameterHandler prm;
      declared(prm);
      prm.parse_input_from_string(
        "subsection Circulation\n  set Model = " + name + "\nend\n");
      const auto model = create_model(prm);
      CHECK(model->name() == name);
    }

  dealii::ParameterHandler prm;
  declared(prm);
  prm.parse_input_from_string("");
  const auto                   model = create_model(prm);
  const auto                  &loop  = dynamic_cast<const ClosedLoop &>(*model);
  const ClosedLoop::Parameters built;
  const auto                  &parsed = loop.parameters();
  CHECK(parsed.period == 800.0);
  CHECK(parsed.systemic_arteries.compliance ==
        built.systemic_arteries.compliance);
  CHECK(parsed.pulmonary_veins.inductance == built.pulmonary_veins.inductance);
  CHECK(parsed.left_atrium.contraction_onset == 700.0);
  CHECK(parsed.left_ventricle.active_elastance ==
        built.left_ventricle.active_elastance);
  CHECK(parsed.right_ventricle.initial_volume == 166177.0);
  CHECK(parsed.valve.closed_resistance == built.valve.closed_resistance);
  // Unit conversions at the parameter edge: 4.482 mmHg/mL in kPa/mm^3,
  // 0.005 mmHg s^2/mL in kPa ms^2/mm^3, 71.104 mL/s in mm^3/ms.
  CHECK(parsed.left_ventricle.active_elastance ==
        Approx(4.482 * 0.133322387415 / 1000).epsilon(1e-14));
  CHECK(parsed.systemic_arteries.inductance ==
        Approx(0.005 * 133.322387415).epsilon(1e-14));
  CHECK(parsed.systemic_arteries.initial_flow == Approx(71.104));
  CHECK(parsed.systemic_arteries.initial_pressure ==
        Approx(87.675 * 0.133322387415).epsilon(1e-14));

  // Blood volume of the initial state: 458.713 mL in the chambers plus C p.
  Vector y;
  model->initial_state(y);
  const double expected = 87.183 + 118.520 + 86.833 + 166.177 + 1.372 * 87.675 +
                          11.363 * 35.898 + 20.0 * 19.545 + 16.0 * 15.004;
  CHECK(Units::mm3_to_mL(model->total_blood_volume(y)) ==
        Approx(expected).epsilon(1e-12));
}

TEST_CASE("Invalid circulation model parameters give errors naming the entry",
          "[circulation]")
{
  CHECK_THAT(create_error("  subsection Closed loop\n"
                          "    subsection Systemic arteries\n"
                          "      set Compliance = 0\n    end\n  end\n"),
             Catch::Contains(
               "Circulation / Closed loop / Systemic arteries / Compliance"));
  CHECK_THAT(create_error("  subsection Left ventricle\n"
                          "    set Relaxation duration = 600\n  end\n"),
             Catch::Contains("Circulation / Left ventricle / Relaxation "
                             "duration") &&
               Catch::Contains("must not exceed"));
  CHECK_THAT(create_error("  subsection Closed loop\n"
                          "    set Closed valve resistance = 0.001\n  end\n"),
             Catch::Contains("Circulation / Closed loop / Closed valve "
                             "resistance"));
  CHECK_THAT(create_error("  set Model = 4-element Windkessel\n"
                          "  subsection 4-element Windkessel\n"
                          "    set Inductance = 0\n  end\n"),
             Catch::Contains("4-element Windkessel / Inductance"));
  CHECK_THAT(create_error("  set Model = 3-element Windkessel\n"
                          "  set Characteristic impedance = 0\n"),
             Catch::Contains("Circulation / Characteristic impedance"));
  // The 2-element model does not use Z_c.
  CHECK(create_error("  set Model = 2-element Windkessel\n"
                     "  set Characteristic impedance = 0\n") == "");
  CHECK_THAT(create_error("  set Model = 5-element Windkessel\n"),
             Catch::Contains("Model"));
}
