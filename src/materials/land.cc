#include "materials/land.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include "base/parameter_table.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace systole::Materials
{
  namespace
  {
    /// The entries of "Active tension / Land": name, member, pattern
    /// (beta_1 may be negative), help.
    const std::vector<RealEntry<Land::Parameters>> &
    entries()
    {
      using P = Land::Parameters;
      using dealii::Patterns::Double;
      const auto table1 = [](const char *help) {
        return std::string(help) +
               " (Land et al. 2017, J. Mol. Cell. Cardiol. 106:68, Table 1.)";
      };
      static const std::vector<RealEntry<P>> entries = {
        {"Reference tension",
         &P::T_ref,
         Double(0.0),
         table1("T_ref: the tension of a fully activated, isometric cell at "
                "stretch 1. Units: kPa.")},
        {"TRPN50",
         &P::TRPN_50,
         Double(0.0),
         table1("TRPN_50: troponin occupancy of half activation of the "
                "tropomyosin. Units: -.")},
        {"nTRPN",
         &P::n_TRPN,
         Double(0.0),
         table1("n_TRPN: Hill coefficient of calcium binding to troponin C. "
                "Units: -.")},
        {"kTRPN",
         &P::k_TRPN,
         Double(0.0),
         table1("k_TRPN: rate of calcium binding to troponin C. Units: 1/ms.")},
        {"nTM",
         &P::n_TM,
         Double(0.0),
         table1(
           "n_TM: cooperativity of the tropomyosin unblocking. Units: -.")},
        {"ku",
         &P::k_u,
         Double(0.0),
         table1("k_u: rate of the tropomyosin unblocking. Units: 1/ms.")},
        {"kuw",
         &P::k_uw,
         Double(0.0),
         table1("k_uw: rate of the unbound-to-weak cross-bridge transition. "
                "Units: 1/ms.")},
        {"kws",
         &P::k_ws,
         Double(0.0),
         table1("k_ws: rate of the weak-to-strong cross-bridge transition. "
                "Units: 1/ms.")},
        {"rw",
         &P::r_w,
         Double(0.0),
         table1("r_w: steady-state fraction of weakly bound cross-bridges (of "
                "the unblocked ones), in (0, 1). Units: -.")},
        {"rs",
         &P::r_s,
         Double(0.0),
         table1(
           "r_s: steady-state fraction of strongly bound cross-bridges, in "
           "(0, 1). Units: -.")},
        {"gammas",
         &P::gamma_s,
         Double(0.0),
         table1("gamma_s: detachment of distorted strong cross-bridges. Units: "
                "-.")},
        {"gammaw",
         &P::gamma_w,
         Double(0.0),
         table1(
           "gamma_w: detachment of distorted weak cross-bridges. Units: -.")},
        {"phi",
         &P::phi,
         Double(0.0),
         table1(
           "phi: scale of the distortion decay rates c_s, c_w. Units: -.")},
        {"Aeff",
         &P::A_eff,
         Double(0.0),
         table1("A_eff: distortion per unit stretch (the velocity dependence). "
                "Units: -.")},
        {"beta0",
         &P::beta_0,
         Double(0.0),
         table1("beta_0: length dependence of the maximal tension, h(lambda). "
                "Units: -.")},
        {"beta1",
         &P::beta_1,
         Double(),
         table1("beta_1: length dependence of the calcium sensitivity, Ca50 = "
                "Ca50ref + beta_1 (min(lambda, 1.2) - 1). Units: µM.")},
        {"Ca50ref",
         &P::Ca50_ref,
         Double(0.0),
         table1("Ca50ref: calcium of half troponin occupancy at stretch 1. "
                "Units: µM.")}};
      return entries;
    }

    /// Solves the 3x3 system M x = r (Cramer's rule; M is well conditioned:
    /// the identity plus a small multiple of the rate matrix).
    std::array<double, 3>
    solve3(const double M[3][3], const std::array<double, 3> &r)
    {
      const auto det = [](const double a[3][3]) {
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
               a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
      };
      const double          d = det(M);
      std::array<double, 3> x;
      for (unsigned int k = 0; k < 3; ++k)
        {
          double Mk[3][3];
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int j = 0; j < 3; ++j)
              Mk[i][j] = j == k ? r[i] : M[i][j];
          x[k] = det(Mk) / d;
        }
      return x;
    }
  } // namespace

  void
  Land::Parameters::declare(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Active tension");
    prm.enter_subsection("Land");
    declare_entries(prm, entries());
    prm.leave_subsection();
    prm.leave_subsection();
  }

  Land::Parameters
  Land::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    Parameters p;
    parse_entries(prm, {"Active tension", "Land"}, entries(), p);
    const auto in_unit_interval = [](const double v, const char *name) {
      AssertThrow(v > 0.0 && v < 1.0,
                  dealii::ExcMessage(std::string("Active tension / Land / ") +
                                     name + " (" +
                                     dealii::Utilities::to_string(v) +
                                     ") must lie strictly between 0 and 1."));
    };
    in_unit_interval(p.r_w, "rw");
    in_unit_interval(p.r_s, "rs");
    AssertThrow(p.Ca50_ref + 0.2 * std::min(p.beta_1, 0.0) -
                    0.2 * std::max(p.beta_1, 0.0) >
                  0.0,
                dealii::ExcMessage(
                  "Active tension / Land: Ca50ref + beta1 (lambda - 1) must "
                  "stay positive for stretches 0.8 to 1.2; reduce |beta1| "
                  "or raise Ca50ref."));
    AssertThrow(p.k_uw * (1.0 / p.r_w - 1.0) - p.k_ws > 0.0,
                dealii::ExcMessage(
                  "Active tension / Land: kuw (1/rw - 1) must exceed kws "
                  "(the weak-to-unbound rate k_wu would be negative)."));
    return p;
  }

  Land::Land(const Parameters &params)
    : TensionModel(model_name, TensionDrive::calcium, n_state_values)
    , p(params)
  {
    k_wu = p.k_uw * (1.0 / p.r_w - 1.0) - p.k_ws;
    k_su = p.k_ws * p.r_w * (1.0 / p.r_s - 1.0);
    k_b  = p.k_u * std::pow(p.TRPN_50, p.n_TM) /
          (1.0 - p.r_s - (1.0 - p.r_s) * p.r_w);
    A   = p.A_eff * p.r_s / ((1.0 - p.r_s) * p.r_w + p.r_s);
    c_w = p.phi * p.k_uw * (1.0 - p.r_w) / p.r_w;
    c_s = p.phi * p.k_ws * p.r_w * (1.0 - p.r_s) / p.r_s;
  }

  void
  Land::initial_state(double *state) const
  {
    std::fill(state, state + n_state_values, 0.0);
    state[TmBlocked] = 1.0;
  }

  double
  Land::ca50(const double stretch) const
  {
    return p.Ca50_ref + p.beta_1 * (std::min(stretch, 1.2) - 1.0);
  }

  double
  Land::length_factor(const double stretch, double *derivative) const
  {
    const double l = std::min(stretch, 1.2);
    const double h = 1.0 + p.beta_0 * (l + std::min(l, 0.87) - 1.87);
    if (derivative != nullptr)
      *derivative = h <= 0.0 || stretch >= 1.2 ? 0.0
                    : l < 0.87                 ? 2.0 * p.beta_0
                                               : p.beta_0;
    return std::max(h, 0.0);
  }

  double
  Land::tension_of_state(const double *s, const double stretch) const
  {
    return length_factor(stretch) * p.T_ref / p.r_s *
           ((s[zeta_s] + 1.0) * std::max(s[XS], 0.0) +
            s[zeta_w] * std::max(s[XW], 0.0));
  }

  void
  Land::rhs(const double *s,
            const double  ca,
            const double  stretch,
            const double  rate,
            double       *ds) const
  {
    const double xs = std::max(s[XS], 0.0), xw = std::max(s[XW], 0.0);
    const double trpn     = std::max(s[CaTRPN], 0.0);
    const double xu       = 1.0 - s[TmBlocked] - xs - xw;
    const double gamma_wu = p.gamma_w * std::abs(s[zeta_w]);
    const double gamma_su =
      p.gamma_s * std::max({s[zeta_s], -1.0 - s[zeta_s], 0.0});
    ds[XS] = p.k_ws * xw - k_su * xs - gamma_su * xs;
    ds[XW] = p.k_uw * xu - k_wu * xw - p.k_ws * xw - gamma_wu * xw;
    ds[CaTRPN] =
      p.k_TRPN *
      (std::pow(std::max(ca, 0.0) / ca50(stretch), p.n_TRPN) * (1.0 - trpn) -
       trpn);
    const double up = std::min(std::pow(trpn, -p.n_TM / 2.0), 100.0);
    ds[TmBlocked] =
      k_b * up * xu - p.k_u * std::pow(trpn, p.n_TM / 2.0) * s[TmBlocked];
    ds[zeta_s] = A * rate - c_s * s[zeta_s];
    ds[zeta_w] = A * rate - c_w * s[zeta_w];
  }

  void
  Land::step(const double       *old,
             const TensionInput &in,
             double             *s,
             TensionOutput      &out) const
  {
    const double dt = in.time_step;
    AssertThrow(dt > 0.0,
                dealii::ExcMessage("Land tension: the time step must be "
                                   "positive."));
    const double lambda = in.stretch;
    // Distortions: linear, backward Euler with dλ/dt = (λ - λ_n)/Δt.
    const double dz_s = A / (1.0 + c_s * dt), dz_w = A / (1.0 + c_w * dt);
    s[zeta_s] =
      (old[zeta_s] + A * (lambda - in.previous_stretch)) / (1.0 + c_s * dt);
    s[zeta_w] =
      (old[zeta_w] + A * (lambda - in.previous_stretch)) / (1.0 + c_w * dt);

    // Troponin: linear in CaTRPN at the new calcium.
    const double c50   = ca50(lambda);
    const double dc50  = lambda < 1.2 ? p.beta_1 : 0.0;
    const double x     = std::pow(std::max(in.calcium, 0.0) / c50, p.n_TRPN);
    const double dx    = -p.n_TRPN * x / c50 * dc50;
    const double den   = 1.0 + dt * p.k_TRPN * (1.0 + x);
    s[CaTRPN]          = (old[CaTRPN] + dt * p.k_TRPN * x) / den;
    const double dtrpn = dt * p.k_TRPN * (1.0 - s[CaTRPN]) / den * dx;
    const double trpn  = s[CaTRPN];
    const double half  = p.n_TM / 2.0;
    const double pw    = trpn > 0.0 ? std::pow(trpn, -half) : 100.0;
    const double up    = std::min(pw, 100.0);
    const double dup   = pw < 100.0 ? -half * pw / trpn * dtrpn : 0.0;
    const double down  = std::pow(trpn, half);
    const double ddown = trpn > 0.0 ? half * down / trpn * dtrpn : 0.0;

    // Cross-bridges and tropomyosin: linear at the new ζ and CaTRPN.
    const auto gamma_su = [&](const double z, double *dg) {
      if (z > 0.0)
        {
          *dg = p.gamma_s;
          return p.gamma_s * z;
        }
      if (z < -1.0)
        {
          *dg = -p.gamma_s;
          return p.gamma_s * (-1.0 - z);
        }
      *dg = 0.0;
      return 0.0;
    };
    double       dgs_dz;
    const double gs      = gamma_su(s[zeta_s], &dgs_dz);
    const double gw      = p.gamma_w * std::abs(s[zeta_w]);
    const double dgs     = dgs_dz * dz_s;
    const double dgw     = p.gamma_w * (s[zeta_w] >= 0.0 ? 1.0 : -1.0) * dz_w;
    const double M[3][3] = {
      {1.0 + dt * (k_su + gs), -dt * p.k_ws, 0.0},
      {dt * p.k_uw, 1.0 + dt * (p.k_uw + k_wu + p.k_ws + gw), dt * p.k_uw},
      {dt * k_b * up, dt * k_b * up, 1.0 + dt * k_b * up + dt * p.k_u * down}};
    const std::array<double, 3> r = {
      {old[XS], old[XW] + dt * p.k_uw, old[TmBlocked] + dt * k_b * up}};
    const std::array<double, 3> y = solve3(M, r);
    s[XS]                         = y[0];
    s[XW]                         = y[1];
    s[TmBlocked]                  = y[2];

    // dy/dλ = M^-1 (dr/dλ - dM/dλ y).
    const std::array<double, 3> rhs_d = {
      {-dt * dgs * y[0],
       -dt * dgw * y[1],
       dt * k_b * dup - dt * k_b * dup * (y[0] + y[1] + y[2]) -
         dt * p.k_u * ddown * y[2]}};
    const std::array<double, 3> dy = solve3(M, rhs_d);

    double       dh;
    const double h  = length_factor(lambda, &dh);
    const double xs = std::max(y[0], 0.0), xw = std::max(y[1], 0.0);
    const double dxs = y[0] > 0.0 ? dy[0] : 0.0;
    const double dxw = y[1] > 0.0 ? dy[1] : 0.0;
    const double mix = (s[zeta_s] + 1.0) * xs + s[zeta_w] * xw;
    const double dmix =
      dz_s * xs + (s[zeta_s] + 1.0) * dxs + dz_w * xw + s[zeta_w] * dxw;
    const double scale    = p.T_ref / p.r_s;
    out.tension           = h * scale * mix;
    out.dtension_dstretch = scale * (dh * mix + h * dmix);
  }

  double
  Land::steady_state_tension(const double ca, const double stretch) const
  {
    // The fixed point with ζ = 0: XW = a XU, XS = b XU, TmB = c XU with
    // XU = 1/(1 + a + b + c).
    const double x    = std::pow(ca / ca50(stretch), p.n_TRPN);
    const double trpn = x / (1.0 + x);
    const double a    = p.k_uw / (k_wu + p.k_ws);
    const double b    = a * p.k_ws / k_su;
    const double c    = k_b * std::min(std::pow(trpn, -p.n_TM / 2.0), 100.0) /
                     (p.k_u * std::pow(trpn, p.n_TM / 2.0));
    return length_factor(stretch) * p.T_ref / p.r_s * b / (1.0 + a + b + c);
  }

  const Land::Parameters &
  Land::parameters() const
  {
    return p;
  }
} // namespace systole::Materials
