// The ionic models on their own: resting state, upstroke, threshold,
// recovery, and the factory.
#include "electrophysiology/aliev_panfilov.h"
#include "electrophysiology/ionic_factory.h"
#include "electrophysiology/mitchell_schaeffer.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <vector>

using namespace systole;
using namespace systole::Electrophysiology;

namespace
{
  /// The membrane ODE of one cell (no diffusion), from v0 and the resting
  /// states, integrated with classical RK4 (step @p dt ms) to @p end_time.
  /// Calls @p observe(t, v, states) after every step.
  void
  integrate_cell(
    const IonicModel &model,
    const double      v0,
    const double      end_time,
    const double      dt,
    const std::function<void(double, double, const std::vector<double> &)>
      &observe)
  {
    const unsigned int  n = 1 + model.n_states();
    std::vector<double> y(n);
    y[0] = v0;
    model.resting_state(y.data() + 1);
    const auto rhs = [&](const std::vector<double> &z) {
      std::vector<double> f(n);
      f[0] = -model.ionic_current(z[0], z.data() + 1);
      model.state_rhs(z[0], z.data() + 1, f.data() + 1);
      return f;
    };
    const auto axpy = [](const std::vector<double> &a,
                         const double               s,
                         const std::vector<double> &b) {
      std::vector<double> c(a);
      for (unsigned int i = 0; i < a.size(); ++i)
        c[i] += s * b[i];
      return c;
    };
    for (double t = 0; t < end_time - 1e-12; t += dt)
      {
        const auto k1 = rhs(y);
        const auto k2 = rhs(axpy(y, dt / 2, k1));
        const auto k3 = rhs(axpy(y, dt / 2, k2));
        const auto k4 = rhs(axpy(y, dt, k3));
        for (unsigned int i = 0; i < n; ++i)
          y[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
        observe(t + dt, y[0], std::vector<double>(y.begin() + 1, y.end()));
      }
  }

  struct Trace
  {
    double peak     = -1e300; ///< max v
    double max_rate = -1e300; ///< max dv/dt [1/ms]
    double duration = 0;      ///< time until v < 0.1 after the upstroke [ms]
    double final_v  = 0;
    /// The first state variable at t = 50 and t = 150 ms.
    double s_50 = 0, s_150 = 0;
  };

  Trace
  trace(const IonicModel &model, const double v0, const double end_time)
  {
    Trace  r;
    bool   up = false, down = false;
    double last_v = v0, last_t = 0;
    integrate_cell(model,
                   v0,
                   end_time,
                   0.005,
                   [&](const double t, const double v, const auto &s) {
                     r.peak = std::max(r.peak, v);
                     r.max_rate =
                       std::max(r.max_rate, (v - last_v) / (t - last_t));
                     last_v = v;
                     last_t = t;
                     if (std::abs(t - 50) < 1e-9)
                       r.s_50 = s[0];
                     if (std::abs(t - 150) < 1e-9)
                       r.s_150 = s[0];
                     if (v > 0.5)
                       up = true;
                     if (up && !down && v < 0.1)
                       {
                         down       = true;
                         r.duration = t;
                       }
                     r.final_v = v;
                   });
    return r;
  }
} // namespace

TEST_CASE("The phenomenological ionic models rest at their resting state",
          "[ep][ionic]")
{
  // (ten Tusscher-Panfilov starts from a paced state close to rest, see
  // ten_tusscher_panfilov_test.cc.)
  for (const std::string name : {"Aliev-Panfilov", "Mitchell-Schaeffer"})
    {
      const auto          model = create_ionic_model(name);
      std::vector<double> s(model->n_states()), ds(model->n_states());
      model->resting_state(s.data());
      const double v = model->resting_potential();
      INFO(name);
      CHECK(model->ionic_current(v, s.data()) == Approx(0.0).margin(1e-14));
      model->state_rhs(v, s.data(), ds.data());
      for (const double d : ds)
        CHECK(d == Approx(0.0).margin(1e-14));
      CHECK(model->to_mV(v) == Approx(-80.0));
      CHECK(model->from_mV(model->to_mV(0.37)) == Approx(0.37));
      // Stable: a small depolarisation decays back to rest.
      const auto sub = trace(*model, 0.02, 200);
      CHECK(sub.peak <= 0.02 + 1e-12);
      CHECK(std::abs(sub.final_v) < 1e-3);
    }
}

TEST_CASE("Aliev-Panfilov fires above its threshold a and recovers",
          "[ep][ionic]")
{
  const AlievPanfilov::Parameters p; // physiology.md values
  const AlievPanfilov             model(p);
  // Below a the cubic pulls u back to rest, above it fires.
  const auto below = trace(model, 0.9 * p.a, 100);
  CHECK(below.peak <= 0.9 * p.a + 1e-12);
  CHECK(below.final_v < 1e-3);
  const auto above = trace(model, 1.2 * p.a, 600);
  // Upstroke to the upper root u = 1 of the cubic (w is still small) at
  // the peak rate of the cubic, max k u (u - a)(1 - u) / T, reached at
  // u = (1 + a + sqrt((1 + a)^2 - 3a)) / 3.
  CHECK(above.peak == Approx(1.0).margin(0.03));
  const double u_max =
    (1 + p.a + std::sqrt((1 + p.a) * (1 + p.a) - 3 * p.a)) / 3;
  CHECK(above.max_rate ==
        Approx(p.k * u_max * (u_max - p.a) * (1 - u_max) / p.time_unit)
          .epsilon(0.03));
  // Then recovery through w: the action potential lasts a few hundred ms
  // with T = 12.9 ms and returns to rest.
  CHECK(above.duration > 150);
  CHECK(above.duration < 400);
  CHECK(std::abs(above.final_v) < 0.01);
}

TEST_CASE("Mitchell-Schaeffer fires, and its action potential lasts "
          "tau_close ln(tau_out / (4 tau_in))",
          "[ep][ionic]")
{
  const MitchellSchaeffer::Parameters p;
  const MitchellSchaeffer             model(p);
  // Threshold: the lower non-zero root of v (1 - v) / tau_in = 1 / tau_out
  // with h = 1, v_th = (1 - sqrt(1 - 4 tau_in / tau_out)) / 2.
  const double v_th  = 0.5 * (1 - std::sqrt(1 - 4 * p.tau_in / p.tau_out));
  const auto   below = trace(model, 0.8 * v_th, 100);
  CHECK(below.peak <= 0.8 * v_th + 1e-12);
  const auto above = trace(model, 1.5 * v_th, 600);
  // Upstroke to the upper root (1 + sqrt(1 - 4 tau_in/tau_out))/2 at the
  // peak rate of v^2 (1 - v)/tau_in - v/tau_out (h ~ 1), 0.385 / ms, at
  // v = (2 + sqrt(4 - 12 tau_in/tau_out)) / 6.
  CHECK(
    above.peak ==
    Approx(0.5 * (1 + std::sqrt(1 - 4 * p.tau_in / p.tau_out))).margin(0.01));
  const double v_max = (2 + std::sqrt(4 - 12 * p.tau_in / p.tau_out)) / 6;
  CHECK(above.max_rate ==
        Approx(v_max * v_max * (1 - v_max) / p.tau_in - v_max / p.tau_out)
          .epsilon(0.05));
  // While depolarised the gate closes as exp(-t / tau_close).
  CHECK(above.s_150 / above.s_50 ==
        Approx(std::exp(-100 / p.tau_close)).epsilon(1e-6));
  // Repolarisation once the gate passes the fold h = 4 tau_in / tau_out
  // (Mitchell and Schaeffer 2003: APD ~ tau_close ln(tau_out/(4 tau_in)),
  // 241 ms), delayed by the slow passage through the fold.
  const double apd = p.tau_close * std::log(p.tau_out / (4 * p.tau_in));
  CHECK(above.duration > apd);
  CHECK(above.duration < 1.25 * apd);
}

TEST_CASE("The ionic model factory knows every model and rejects others",
          "[ep][ionic]")
{
  CHECK(ionic_models().names() ==
        std::vector<std::string>{"Aliev-Panfilov",
                                 "Mitchell-Schaeffer",
                                 "ten Tusscher-Panfilov"});
  for (const auto &name : ionic_models().names())
    CHECK(create_ionic_model(name)->name() == name);
  CHECK_THROWS_WITH(create_ionic_model("FitzHugh"),
                    Catch::Contains("Ionic model = \"FitzHugh\" is unknown"));

  MitchellSchaeffer::Parameters bad;
  bad.tau_out = 1.0; // < 4 tau_in: not excitable
  CHECK_THROWS_WITH(MitchellSchaeffer{bad}, Catch::Contains("excitable"));
  AlievPanfilov::Parameters wrong;
  wrong.a = 0.6;
  CHECK_THROWS_WITH(AlievPanfilov{wrong}, Catch::Contains("(0, 0.5)"));
}
