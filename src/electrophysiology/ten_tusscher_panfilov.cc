// ten Tusscher-Panfilov 2006, written once from
// src/electrophysiology/ode/tentusscher_panfilov_2006_{epi,endo,M}_cell.ode
// (fenicsx-beat 0.7.2, MIT; the variants from myokit/models, BSD 3-clause).
// Every expression below follows the .ode's expression of the same name, in
// the .ode's units (mV, ms, mM, pA/pF, nS/pF, um^3, pF); the order of the
// sections is the .ode's.

#include "electrophysiology/ten_tusscher_panfilov.h"

#include "electrophysiology/ten_tusscher_panfilov_constants.h"

#include <cmath>

namespace systole::Electrophysiology
{
  namespace
  {
    using namespace TenTusscherPanfilovConstants;

    // Initial values of the .ode (states(...) entries).
    constexpr double initial_V = -85.23;

    double
    square(const double x)
    {
      return x * x;
    }

    /// Whether the h and j gates take their V < -40 mV branch.
    bool
    below_minus_40(const double V)
    {
      return V < -40;
    }
  } // namespace


  struct TenTusscherPanfilov::Currents
  {
    double i_K1, i_to, i_Kr, i_Ks, i_CaL, i_NaK, i_Na, i_b_Na, i_NaCa, i_b_Ca,
      i_p_K, i_p_Ca;
  };


  void
  TenTusscherPanfilov::Parameters::declare(dealii::ParameterHandler &prm)
  {
    prm.declare_entry(
      "Cell type",
      "epicardial",
      dealii::Patterns::Selection("endocardial|mid-myocardial|epicardial"),
      "Variant of the ten Tusscher-Panfilov 2006 cell: they differ in the "
      "transient outward current (G_to 0.073 nS/pF and slower s-gate "
      "recovery endocardially, 0.294 nS/pF otherwise) and the slow delayed "
      "rectifier (G_Ks 0.098 nS/pF mid-myocardially, 0.392 nS/pF "
      "otherwise). Units: -. Source: ten Tusscher and Panfilov 2006; the "
      "Niederer et al. 2011 benchmark uses the epicardial cell.");
  }


  TenTusscherPanfilov::Parameters
  TenTusscherPanfilov::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::string type =
      prm.get({"Electrophysiology", model_name}, "Cell type");
    Parameters p;
    p.cell_type = type == "endocardial"      ? CellType::endocardial
                  : type == "mid-myocardial" ? CellType::mid_myocardial
                                             : CellType::epicardial;
    return p;
  }


  TenTusscherPanfilov::TenTusscherPanfilov(const Parameters &parameters)
    : params(parameters)
    , g_to(parameters.cell_type == CellType::endocardial ? 0.073 : 0.294)
    , g_Ks(parameters.cell_type == CellType::mid_myocardial ? 0.098 : 0.392)
  {}


  std::string
  TenTusscherPanfilov::cell_type_name(const CellType type)
  {
    switch (type)
      {
        case CellType::endocardial:
          return "endocardial";
        case CellType::mid_myocardial:
          return "mid-myocardial";
        case CellType::epicardial:
          return "epicardial";
      }
    return "";
  }

  std::string
  TenTusscherPanfilov::name() const
  {
    return model_name;
  }

  unsigned int
  TenTusscherPanfilov::n_states() const
  {
    return n_all_states;
  }

  unsigned int
  TenTusscherPanfilov::n_gates() const
  {
    return n_gate_states;
  }

  double
  TenTusscherPanfilov::resting_potential() const
  {
    return initial_V;
  }

  void
  TenTusscherPanfilov::resting_state(double *y) const
  {
    y[x_r1]    = 0.00621;
    y[x_r2]    = 0.4712;
    y[x_s]     = 0.0095;
    y[m]       = 0.00172;
    y[h]       = 0.7444;
    y[j]       = 0.7045;
    y[d]       = 3.373e-5;
    y[f]       = 0.7888;
    y[f2]      = 0.9755;
    y[f_cass]  = 0.9953;
    y[s]       = 0.999998;
    y[r]       = 2.42e-8;
    y[r_prime] = 0.9073;
    y[ca_i]    = 0.000126;
    y[ca_sr]   = 3.64;
    y[ca_ss]   = 0.00036;
    y[na_i]    = 8.604;
    y[k_i]     = 136.89;
  }


  double
  TenTusscherPanfilov::currents(const double  V,
                                const double *y,
                                Currents     &c) const
  {
    // Reversal potentials
    const double E_Na = RTF * std::log(Na_o / y[na_i]);
    const double E_K  = RTF * std::log(K_o / y[k_i]);
    const double E_Ks =
      RTF * std::log((K_o + P_kna * Na_o) / (y[k_i] + P_kna * y[na_i]));
    const double E_Ca = 0.5 * RTF * std::log(Ca_o / y[ca_i]);

    // Inward rectifier potassium current
    const double alpha_K1 = 0.1 / (1 + std::exp(0.06 * (V - E_K - 200)));
    const double beta_K1  = (3 * std::exp(0.0002 * (V - E_K + 100)) +
                            std::exp(0.1 * (V - E_K - 10))) /
                           (1 + std::exp(-0.5 * (V - E_K)));
    const double xK1_inf = alpha_K1 / (alpha_K1 + beta_K1);
    c.i_K1               = g_K1 * xK1_inf * std::sqrt(K_o / 5.4) * (V - E_K);

    // Rapid time dependent potassium current
    c.i_Kr = g_Kr * std::sqrt(K_o / 5.4) * y[x_r1] * y[x_r2] * (V - E_K);

    // Slow time dependent potassium current
    c.i_Ks = g_Ks * square(y[x_s]) * (V - E_Ks);

    // Fast sodium current
    c.i_Na = g_Na * y[m] * y[m] * y[m] * y[h] * y[j] * (V - E_Na);

    // Sodium background current
    c.i_b_Na = g_bna * (V - E_Na);

    // L_type Ca current: g_CaL d f f2 fCass 4 (V - 15) F^2/(R T)
    // (0.25 Ca_ss e^x - Ca_o)/(e^x - 1) with x = 2 (V - 15) F/(R T), i.e.
    // 2 F g_CaL d f f2 fCass (0.25 Ca_ss e^x - Ca_o) x/(e^x - 1): the same
    // expression, finite at V = 15 mV.
    const double x = 2 * (V - 15) / RTF;
    const double x_over_expm1 =
      std::abs(x) < 1e-8 ? 1 - 0.5 * x : x / std::expm1(x);
    c.i_CaL = g_CaL * y[d] * y[f] * y[f2] * y[f_cass] * 2 * F *
              (0.25 * y[ca_ss] * std::exp(x) - Ca_o) * x_over_expm1;

    // Calcium background current
    c.i_b_Ca = g_bca * (V - E_Ca);

    // Transient outward current
    c.i_to = g_to * y[r] * y[s] * (V - E_K);

    // Sodium potassium pump current
    c.i_NaK =
      P_NaK * K_o / (K_o + K_mk) * y[na_i] / (y[na_i] + K_mNa) /
      (1 + 0.1245 * std::exp(-0.1 * V / RTF) + 0.0353 * std::exp(-V / RTF));

    // Sodium calcium exchanger current
    c.i_NaCa =
      K_NaCa *
      (std::exp(gamma * V / RTF) * y[na_i] * y[na_i] * y[na_i] * Ca_o -
       std::exp((gamma - 1) * V / RTF) * Na_o * Na_o * Na_o * y[ca_i] * alpha) /
      ((Km_Nai * Km_Nai * Km_Nai + Na_o * Na_o * Na_o) * (Km_Ca + Ca_o) *
       (1 + K_sat * std::exp((gamma - 1) * V / RTF)));

    // Calcium pump current
    c.i_p_Ca = g_pCa * y[ca_i] / (y[ca_i] + K_pCa);

    // Potassium pump current
    c.i_p_K = g_pK * (V - E_K) / (1 + std::exp((25 - V) / 5.98));

    return c.i_K1 + c.i_to + c.i_Kr + c.i_Ks + c.i_CaL + c.i_NaK + c.i_Na +
           c.i_b_Na + c.i_NaCa + c.i_b_Ca + c.i_p_K + c.i_p_Ca;
  }


  double
  TenTusscherPanfilov::ionic_current(const double v, const double *state) const
  {
    Currents c;
    return currents(v, state, c);
  }


  void
  TenTusscherPanfilov::state_rhs(const double  v,
                                 const double *state,
                                 double       *rhs) const
  {
    ionic_current_and_state_rhs(v, state, rhs);
  }


  double
  TenTusscherPanfilov::ionic_current_and_state_rhs(const double  v,
                                                   const double *y,
                                                   double       *rhs) const
  {
    Currents     c;
    const double total = currents(v, y, c);
    for (unsigned int g = 0; g < n_gate_states; ++g)
      rhs[g] = 0;

    // Calcium dynamics
    const double Ca_i   = y[ca_i];
    const double Ca_SR  = y[ca_sr];
    const double Ca_ss  = y[ca_ss];
    const double i_up   = Vmax_up / (1 + K_up * K_up / (Ca_i * Ca_i));
    const double i_leak = V_leak * (Ca_SR - Ca_i);
    const double i_xfer = V_xfer * (Ca_ss - Ca_i);
    const double kcasr  = max_sr - (max_sr - min_sr) / (1 + square(EC / Ca_SR));
    const double ddt_Ca_i_total =
      -(c.i_b_Ca + c.i_p_Ca - 2 * c.i_NaCa) * Cm / (2 * V_c * F) +
      (i_leak - i_up) * V_sr / V_c + i_xfer;
    const double f_JCa_i_free =
      1 / (1 + Buf_c * K_buf_c / square(Ca_i + K_buf_c));
    const double f_JCa_sr_free =
      1 / (1 + Buf_sr * K_buf_sr / square(Ca_SR + K_buf_sr));
    const double f_JCa_ss_free =
      1 / (1 + Buf_ss * K_buf_ss / square(Ca_ss + K_buf_ss));
    const double k1 = k1_prime / kcasr;
    const double k2 = k2_prime * kcasr;
    const double O =
      k1 * Ca_ss * Ca_ss * y[r_prime] / (k3 + k1 * Ca_ss * Ca_ss);
    const double i_rel           = V_rel * O * (Ca_SR - Ca_ss);
    const double ddt_Ca_sr_total = i_up - (i_rel + i_leak);
    const double ddt_Ca_ss_total = -c.i_CaL * Cm / (2 * V_ss * F) +
                                   i_rel * V_sr / V_ss - i_xfer * V_c / V_ss;
    rhs[r_prime] = -k2 * Ca_ss * y[r_prime] + k4 * (1 - y[r_prime]);
    rhs[ca_i]    = ddt_Ca_i_total * f_JCa_i_free;
    rhs[ca_sr]   = ddt_Ca_sr_total * f_JCa_sr_free;
    rhs[ca_ss]   = ddt_Ca_ss_total * f_JCa_ss_free;

    // Sodium dynamics
    rhs[na_i] =
      -(c.i_Na + c.i_b_Na + 3 * c.i_NaK + 3 * c.i_NaCa) / (V_c * F) * Cm;

    // Potassium dynamics (without the stimulus: see the class comment)
    rhs[k_i] = -(c.i_K1 + c.i_to + c.i_Kr + c.i_Ks + c.i_p_K - 2 * c.i_NaK) /
               (V_c * F) * Cm;
    return total;
  }


  void
  TenTusscherPanfilov::gate_rates(const double  V,
                                  const double *y,
                                  double       *steady,
                                  double       *tau) const
  {
    // Rapid time dependent potassium current, Xr1 gate
    steady[x_r1]           = 1 / (1 + std::exp((-26 - V) / 7));
    const double alpha_xr1 = 450 / (1 + std::exp((-45 - V) / 10));
    const double beta_xr1  = 6 / (1 + std::exp((V + 30) / 11.5));
    tau[x_r1]              = 1 * alpha_xr1 * beta_xr1;

    // Xr2 gate
    steady[x_r2]           = 1 / (1 + std::exp((V + 88) / 24));
    const double alpha_xr2 = 3 / (1 + std::exp((-60 - V) / 20));
    const double beta_xr2  = 1.12 / (1 + std::exp((V - 60) / 20));
    tau[x_r2]              = 1 * alpha_xr2 * beta_xr2;

    // Slow time dependent potassium current, Xs gate
    steady[x_s]           = 1 / (1 + std::exp((-5 - V) / 14));
    const double alpha_xs = 1400 / std::sqrt(1 + std::exp((5 - V) / 6));
    const double beta_xs  = 1 / (1 + std::exp((V - 35) / 15));
    tau[x_s]              = 1 * alpha_xs * beta_xs + 80;

    // Fast sodium current, m gate
    steady[m]            = 1 / square(1 + std::exp((-56.86 - V) / 9.03));
    const double alpha_m = 1 / (1 + std::exp((-60 - V) / 5));
    const double beta_m =
      0.1 / (1 + std::exp((V + 35) / 5)) + 0.1 / (1 + std::exp((V - 50) / 200));
    tau[m] = 1 * alpha_m * beta_m;

    // h gate
    steady[h]            = 1 / square(1 + std::exp((V + 71.55) / 7.43));
    const bool   low     = below_minus_40(V);
    const double alpha_h = low ? 0.057 * std::exp(-(V + 80) / 6.8) : 0;
    const double beta_h =
      low ? 2.7 * std::exp(0.079 * V) + 310000 * std::exp(0.3485 * V)
          : 0.77 / (0.13 * (1 + std::exp((V + 10.66) / -11.1)));
    tau[h] = 1 / (alpha_h + beta_h);

    // j gate
    steady[j] = 1 / square(1 + std::exp((V + 71.55) / 7.43));
    const double alpha_j =
      low
        ? (-25428 * std::exp(0.2444 * V) - 6.948e-6 * std::exp(-0.04391 * V)) *
            (V + 37.78) / 1 / (1 + std::exp(0.311 * (V + 79.23)))
        : 0;
    const double beta_j =
      low ? 0.02424 * std::exp(-0.01052 * V) /
              (1 + std::exp(-0.1378 * (V + 40.14)))
          : 0.6 * std::exp(0.057 * V) / (1 + std::exp(-0.1 * (V + 32)));
    tau[j] = 1 / (alpha_j + beta_j);

    // L_type Ca current, d gate
    steady[d]            = 1 / (1 + std::exp((-8 - V) / 7.5));
    const double alpha_d = 1.4 / (1 + std::exp((-35 - V) / 13)) + 0.25;
    const double beta_d  = 1.4 / (1 + std::exp((V + 5) / 5));
    const double gamma_d = 1 / (1 + std::exp((50 - V) / 20));
    tau[d]               = 1 * alpha_d * beta_d + gamma_d;

    // f gate
    steady[f] = 1 / (1 + std::exp((V + 20) / 7));
    tau[f]    = 1102.5 * std::exp(-square(V + 27) / 225) +
             200 / (1 + std::exp((13 - V) / 10)) +
             180 / (1 + std::exp((V + 30) / 10)) + 20;

    // F2 gate
    steady[f2] = 0.67 / (1 + std::exp((V + 35) / 7)) + 0.33;
    tau[f2]    = 562 * std::exp(-square(V + 27) / 240) +
              31 / (1 + std::exp((25 - V) / 10)) +
              80 / (1 + std::exp((V + 30) / 10));

    // FCass gate
    const double ca_ratio = square(y[ca_ss] / 0.05);
    steady[f_cass]        = 0.6 / (1 + ca_ratio) + 0.4;
    tau[f_cass]           = 80 / (1 + ca_ratio) + 2;

    // Transient outward current, s gate (the variant's, see the header)
    if (params.cell_type == CellType::endocardial)
      {
        steady[s] = 1 / (1 + std::exp((V + 28) / 5));
        tau[s]    = 1000 * std::exp(-square(V + 67) / 1000) + 8;
      }
    else
      {
        steady[s] = 1 / (1 + std::exp((V + 20) / 5));
        tau[s]    = 85 * std::exp(-square(V + 45) / 320) +
                 5 / (1 + std::exp((V - 20) / 5)) + 3;
      }

    // r gate
    steady[r] = 1 / (1 + std::exp((20 - V) / 6));
    tau[r]    = 9.5 * std::exp(-square(V + 40) / 1800) + 0.8;
  }


  bool
  TenTusscherPanfilov::has_calcium() const
  {
    return true;
  }

  double
  TenTusscherPanfilov::calcium_uM(const double *state) const
  {
    return 1000 * state[ca_i];
  }

  double
  TenTusscherPanfilov::potential_scale_mV() const
  {
    return 1.0;
  }

  double
  TenTusscherPanfilov::potential_offset_mV() const
  {
    return 0.0;
  }

  double
  TenTusscherPanfilov::transient_outward_conductance() const
  {
    return g_to;
  }

  double
  TenTusscherPanfilov::slow_delayed_rectifier_conductance() const
  {
    return g_Ks;
  }
} // namespace systole::Electrophysiology
