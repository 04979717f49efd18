// The Land et al. 2017 cross-bridge model: its isometric steady state
// against the closed form of the ODEs' fixed point (force-calcium relation,
// Hill coefficient, length dependence), and dT/dλ of one implicit step
// against central differences.
#include "materials/land.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <vector>

using namespace systole;
using State = std::array<double, Materials::Land::n_state_values>;

namespace
{
  /// Isometric steady tension at calcium @p ca [µM] and stretch @p lambda:
  /// implicit steps of 10 ms from rest for 200 s (the backward Euler fixed
  /// point is the ODEs' fixed point).
  double
  integrated_steady_tension(const Materials::Land &land,
                            const double           ca,
                            const double           lambda)
  {
    State s, next;
    land.initial_state(s.data());
    Materials::TensionInput in;
    in.time_step        = 10;
    in.calcium          = ca;
    in.stretch          = lambda;
    in.previous_stretch = lambda;
    Materials::TensionOutput out;
    for (unsigned int k = 0; k < 20000; ++k)
      {
        land.step(s.data(), in, next.data(), out);
        s = next;
      }
    return out.tension;
  }

  /// The calcium of half the maximal steady tension [µM] (bisection in log
  /// Ca of the integrated steady states) and the Hill coefficient there,
  /// d ln(T/(T_max - T))/d ln Ca (central difference, 1 % in Ca).
  std::pair<double, double>
  half_activation(const Materials::Land &land, const double lambda)
  {
    const double T_max = integrated_steady_tension(land, 1e4, lambda);
    double       low = 0.01, high = 10.0;
    for (unsigned int k = 0; k < 40; ++k)
      {
        const double mid = std::sqrt(low * high);
        (integrated_steady_tension(land, mid, lambda) < 0.5 * T_max ? low
                                                                    : high) =
          mid;
      }
    const double ca50  = std::sqrt(low * high);
    const auto   logit = [&](const double ca) {
      const double T = integrated_steady_tension(land, ca, lambda);
      return std::log(T / (T_max - T));
    };
    const double d = 0.01;
    return {ca50,
            (logit(ca50 * (1 + d)) - logit(ca50 * (1 - d))) /
              std::log((1 + d) / (1 - d))};
  }

  /// The closed form of the steady state (derived from the fixed point, not
  /// from the code): T/T_ref = 1/(1 + (TRPN50/CaTRPN)^nTM) h(lambda), CaTRPN
  /// = x/(1 + x), x = (Ca/Ca50)^nTRPN. Half of T_max (CaTRPN -> 1) at
  /// CaTRPN_50 = TRPN50 (1 + 2 TRPN50^nTM)^(-1/nTM); the Hill coefficient
  /// there nTM nTRPN (1 - CaTRPN_50) (1 + 2 u1)/(1 + u1), u1 = TRPN50^nTM.
  struct ClosedForm
  {
    double ca50, hill, T_max;
  };

  ClosedForm
  closed_form(const Materials::Land::Parameters &p, const double lambda)
  {
    const double u1   = std::pow(p.TRPN_50, p.n_TM);
    const double c50  = p.TRPN_50 * std::pow(1 + 2 * u1, -1 / p.n_TM);
    const double l    = std::min(lambda, 1.2);
    const double h    = 1 + p.beta_0 * (l + std::min(l, 0.87) - 1.87);
    const double ca50 = (p.Ca50_ref + p.beta_1 * (l - 1)) *
                        std::pow(c50 / (1 - c50), 1 / p.n_TRPN);
    const double hill = p.n_TM * p.n_TRPN * (1 - c50) * (1 + 2 * u1) / (1 + u1);
    return {ca50, hill, h * p.T_ref / (1 + u1)};
  }

  /// Calcium levels from 0.05 to 20 µM, 60 per decade.
  std::vector<double>
  calcium_levels()
  {
    std::vector<double> ca;
    for (double e = std::log10(0.05); e < std::log10(20.0); e += 1.0 / 60)
      ca.push_back(std::pow(10.0, e));
    return ca;
  }
} // namespace

TEST_CASE("Land tension is zero at rest and its rest state is a fixed point",
          "[materials][active]")
{
  const Materials::Land land(Materials::Land::Parameters{});
  State                 s, next;
  land.initial_state(s.data());
  CHECK(land.tension_of_state(s.data(), 1.0) == 0.0);
  Materials::TensionInput in;
  in.time_step = 5;
  in.calcium   = 0;
  Materials::TensionOutput out;
  land.step(s.data(), in, next.data(), out);
  CHECK(out.tension == Approx(0.0).margin(1e-12));
  for (unsigned int i = 0; i < s.size(); ++i)
    CHECK(next[i] == Approx(s[i]).margin(1e-12));
}

TEST_CASE("Land isometric steady state: the force-calcium relation at "
          "stretch 1 against the closed form of the fixed point",
          "[materials][active]")
{
  const Materials::Land::Parameters p;
  const Materials::Land             land(p);
  // The integrated fixed point equals the algebraic one of the code.
  for (const double c : calcium_levels())
    CHECK(integrated_steady_tension(land, c, 1.0) ==
          Approx(land.steady_state_tension(c, 1.0)).epsilon(1e-6).margin(1e-9));
  const ClosedForm expected = closed_form(p, 1.0);
  const double     T_max    = integrated_steady_tension(land, 1e4, 1.0);
  const auto [ca50, hill]   = half_activation(land, 1.0);
  INFO("T_max " << T_max << " kPa (closed form " << expected.T_max << "), Ca50 "
                << ca50 << " µM (closed form " << expected.ca50
                << "), Hill coefficient " << hill << " (closed form "
                << expected.hill << ")");
  CHECK(T_max == Approx(expected.T_max).epsilon(1e-6));
  CHECK(ca50 == Approx(expected.ca50).epsilon(1e-6));
  CHECK(hill == Approx(expected.hill).epsilon(1e-3));
  // The numbers (docs/verification.md): 111.06 kPa, 0.5636 µM, 3.461.
  CHECK(T_max == Approx(111.06).epsilon(1e-4));
  CHECK(ca50 == Approx(0.5636).epsilon(1e-3));
  CHECK(hill == Approx(3.461).epsilon(1e-3));
}

TEST_CASE("Land length dependence: the steady force grows with stretch and "
          "Ca50 shifts by beta1",
          "[materials][active]")
{
  const Materials::Land::Parameters p;
  const Materials::Land             land(p);
  const double ca50_at_1      = half_activation(land, 1.0).first;
  double       previous_force = 0, previous_ca50 = 1e9;
  for (const double lambda : {0.9, 1.0, 1.1, 1.2})
    {
      const ClosedForm expected = closed_form(p, lambda);
      const auto [ca50, hill]   = half_activation(land, lambda);
      const double force        = integrated_steady_tension(land, 0.6, lambda);
      INFO("lambda " << lambda << ": Ca50 " << ca50 << " µM (closed form "
                     << expected.ca50 << "), Hill " << hill << ", T(0.6 µM) "
                     << force << " kPa, T_max " << expected.T_max << " kPa");
      CHECK(ca50 == Approx(expected.ca50).epsilon(1e-6));
      CHECK(hill == Approx(expected.hill).epsilon(1e-3));
      // beta1 shifts Ca50 linearly: by beta1 (lambda - 1) times the ratio of
      // the force's Ca50 to the troponin's at lambda = 1.
      CHECK(
        ca50 - ca50_at_1 ==
        Approx(p.beta_1 * (lambda - 1) * ca50_at_1 / p.Ca50_ref).margin(1e-6));
      CHECK(force > previous_force);
      CHECK(ca50 < previous_ca50);
      previous_force = force;
      previous_ca50  = ca50;
    }
}

namespace
{
  /// A state in mid-twitch with distortions: 150 ms of steps of 1 ms under a
  /// calcium transient while the stretch oscillates.
  State
  twitch_state(const Materials::Land &land)
  {
    State s, next;
    land.initial_state(s.data());
    Materials::TensionInput in;
    in.time_step  = 1;
    double lambda = 1.0;
    for (unsigned int k = 1; k <= 150; ++k)
      {
        const double t = k;
        in.time        = t;
        in.calcium = 0.1 + 0.9 * (t / 20) * std::exp(1 - t / 20); // peak 1 µM
        in.previous_stretch = lambda;
        lambda              = 1.0 + 0.05 * std::sin(t / 30);
        in.stretch          = lambda;
        Materials::TensionOutput out;
        land.step(s.data(), in, next.data(), out);
        s = next;
      }
    return s;
  }
} // namespace

TEST_CASE("Land dT/dlambda of one implicit step passes a central difference "
          "check with order 2",
          "[materials][active][fd]")
{
  const Materials::Land land(Materials::Land::Parameters{});
  const State           s = twitch_state(land);
  CHECK(land.tension_of_state(s.data(), 1.0) > 5.0);
  CHECK(std::abs(s[Materials::Land::zeta_w]) > 1e-4);

  for (const double dt : {0.5, 5.0})
    for (const double lambda : {0.95, 1.07})
      {
        Materials::TensionInput in;
        in.time_step = dt;
        in.calcium   = 0.7;
        // (lambda - lambda_n stays positive: |zeta_w| has a kink at 0.)
        in.previous_stretch = lambda - 0.01;
        const auto tension  = [&](const double l, double *derivative) {
          in.stretch = l;
          State                    next;
          Materials::TensionOutput out;
          land.step(s.data(), in, next.data(), out);
          if (derivative != nullptr)
            *derivative = out.dtension_dstretch;
          return out.tension;
        };
        double       exact;
        const double T = tension(lambda, &exact);
        CHECK(T > 0.0);
        std::vector<double> errors;
        for (const double h : {2e-3, 1e-3, 5e-4})
          errors.push_back(std::abs(
            (tension(lambda + h, nullptr) - tension(lambda - h, nullptr)) /
              (2 * h) -
            exact));
        INFO("dt " << dt << ", lambda " << lambda << ": dT/dlambda " << exact
                   << " kPa, FD errors " << errors[0] << " " << errors[1] << " "
                   << errors[2]);
        CHECK(std::abs(exact) > 10.0);
        CHECK(errors[2] < 1e-4 * std::abs(exact));
        CHECK(std::log2(errors[0] / errors[1]) == Approx(2.0).margin(0.15));
        CHECK(std::log2(errors[1] / errors[2]) == Approx(2.0).margin(0.15));
      }

  // The length factor h(λ) alone.
  for (const double lambda : {0.8, 1.0, 1.15})
    {
      double       dh;
      const double h0 = land.length_factor(lambda, &dh);
      CHECK(h0 > 0.0);
      const double fd = (land.length_factor(lambda + 1e-4) -
                         land.length_factor(lambda - 1e-4)) /
                        2e-4;
      CHECK(fd == Approx(dh).epsilon(1e-8));
    }
}

TEST_CASE("Land implicit steps are stable and first order at mechanics time "
          "steps",
          "[materials][active]")
{
  const Materials::Land land(Materials::Land::Parameters{});
  // Peak twitch tension under an analytic calcium transient at fixed
  // stretch, for steps from 0.05 to 10 ms.
  const auto peak = [&](const double dt) {
    State s, next;
    land.initial_state(s.data());
    Materials::TensionInput in;
    in.time_step     = dt;
    double       max = 0;
    bool         ok  = true;
    const double end = 800;
    for (double t = dt; t <= end + 1e-9; t += dt)
      {
        in.time    = t;
        in.calcium = 0.1 + 0.9 * (t / 20) * std::exp(1 - t / 20);
        Materials::TensionOutput out;
        land.step(s.data(), in, next.data(), out);
        s   = next;
        max = std::max(max, out.tension);
        ok  = ok && out.tension >= -1e-12 && out.tension <= 120.0;
      }
    CHECK(ok);
    return max;
  };
  const double reference = peak(0.05);
  const double e1        = std::abs(peak(1.0) - reference);
  const double e2        = std::abs(peak(2.0) - reference);
  INFO("peak " << reference << " kPa; errors at 1 ms " << e1 << ", 2 ms " << e2
               << ", 10 ms " << std::abs(peak(10.0) - reference));
  CHECK(reference > 5.0);
  CHECK(e1 < 0.05 * reference);
  CHECK(e2 / e1 == Approx(2.0).margin(0.3));
  CHECK(std::abs(peak(10.0) - reference) < 0.3 * reference);
}
