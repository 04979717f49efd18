#pragma once

// The equations of ten Tusscher-Panfilov 2006, written once for the
// per-point model (ten_tusscher_panfilov.cc) and its batched kernel
// (ten_tusscher_panfilov_batch.cc): the 12 membrane currents, the rates of R'
// and the concentrations, and the steady states and time constants of the 12
// gates, each the .ode's expression of the same name. They are templates on
// the Math that evaluates exp, log and sqrt (std's per point, SimdMath's in
// the batch) and on how the values of a point are read and written (an array
// per point, or a lane of a chunk of points). Internal: not part of the
// model's interface.

#include "electrophysiology/ten_tusscher_panfilov.h"
#include "electrophysiology/ten_tusscher_panfilov_constants.h"

#include <cmath>

#define SYSTOLE_TTP_INLINE inline __attribute__((always_inline))

namespace systole::Electrophysiology::TenTusscherPanfilovEquations
{
  using namespace TenTusscherPanfilovConstants;
  using TTP = TenTusscherPanfilov;

  /// The Math of the per-point model: the C library's functions.
  struct LibmMath
  {
    static double
    exp(const double x)
    {
      return std::exp(x);
    }

    static double
    log(const double x)
    {
      return std::log(x);
    }

    static double
    sqrt(const double x)
    {
      return std::sqrt(x);
    }

    /// x/(e^x - 1), finite at x = 0 (@p exp_x = e^x is not needed).
    static double
    x_over_expm1(const double x, const double /*exp_x*/)
    {
      return std::abs(x) < 1e-8 ? 1 - 0.5 * x : x / std::expm1(x);
    }
  };

  SYSTOLE_TTP_INLINE double
  sq(const double x)
  {
    return x * x;
  }

  /// The 12 currents [pA/pF] and their sum.
  struct Currents
  {
    double i_K1, i_to, i_Kr, i_Ks, i_CaL, i_NaK, i_Na, i_b_Na, i_NaCa, i_b_Ca,
      i_p_K, i_p_Ca, total;
  };

  /// The currents at the point whose value k (0: V [mV], 1 + j: state j) is
  /// in(k), with the variant's conductances @p g_to and @p g_Ks [nS/pF].
  template <class Math, typename In>
  SYSTOLE_TTP_INLINE Currents
  currents(const In &in, const double g_to, const double g_Ks)
  {
    const double V     = in(0);
    const double y_m   = in(1 + TTP::m);
    const double y_h   = in(1 + TTP::h);
    const double y_j   = in(1 + TTP::j);
    const double y_xr1 = in(1 + TTP::x_r1);
    const double y_xr2 = in(1 + TTP::x_r2);
    const double y_xs  = in(1 + TTP::x_s);
    const double y_r   = in(1 + TTP::r);
    const double y_s   = in(1 + TTP::s);
    const double y_d   = in(1 + TTP::d);
    const double y_f   = in(1 + TTP::f);
    const double y_f2  = in(1 + TTP::f2);
    const double y_fcs = in(1 + TTP::f_cass);
    const double Ca_i  = in(1 + TTP::ca_i);
    const double Ca_ss = in(1 + TTP::ca_ss);
    const double Na_i  = in(1 + TTP::na_i);
    const double K_i   = in(1 + TTP::k_i);

    Currents c;
    // Reversal potentials
    const double E_Na = RTF * Math::log(Na_o / Na_i);
    const double E_K  = RTF * Math::log(K_o / K_i);
    const double E_Ks =
      RTF * Math::log((K_o + P_kna * Na_o) / (K_i + P_kna * Na_i));
    const double E_Ca = 0.5 * RTF * Math::log(Ca_o / Ca_i);

    // Inward rectifier potassium current (the .ode's factor sqrt(K_o/5.4)
    // is 1, here and in I_Kr)
    static_assert(K_o == 5.4, "sqrt(K_o/5.4) is taken as 1");
    const double alpha_K1 = 0.1 / (1 + Math::exp(0.06 * (V - E_K - 200)));
    const double beta_K1  = (3 * Math::exp(0.0002 * (V - E_K + 100)) +
                            Math::exp(0.1 * (V - E_K - 10))) /
                           (1 + Math::exp(-0.5 * (V - E_K)));
    const double xK1_inf = alpha_K1 / (alpha_K1 + beta_K1);
    c.i_K1               = g_K1 * xK1_inf * (V - E_K);

    // Rapid time dependent potassium current
    c.i_Kr = g_Kr * y_xr1 * y_xr2 * (V - E_K);

    // Slow time dependent potassium current
    c.i_Ks = g_Ks * sq(y_xs) * (V - E_Ks);

    // Fast sodium current
    c.i_Na = g_Na * y_m * y_m * y_m * y_h * y_j * (V - E_Na);

    // Sodium background current
    c.i_b_Na = g_bna * (V - E_Na);

    // L_type Ca current: g_CaL d f f2 fCass 4 (V - 15) F^2/(R T)
    // (0.25 Ca_ss e^x - Ca_o)/(e^x - 1) with x = 2 (V - 15) F/(R T), i.e.
    // 2 F g_CaL d f f2 fCass (0.25 Ca_ss e^x - Ca_o) x/(e^x - 1): the same
    // expression, finite at V = 15 mV.
    const double x     = 2 * (V - 15) / RTF;
    const double exp_x = Math::exp(x);
    c.i_CaL            = g_CaL * y_d * y_f * y_f2 * y_fcs * 2 * F *
              (0.25 * Ca_ss * exp_x - Ca_o) * Math::x_over_expm1(x, exp_x);

    // Calcium background current
    c.i_b_Ca = g_bca * (V - E_Ca);

    // Transient outward current
    c.i_to = g_to * y_r * y_s * (V - E_K);

    // Sodium potassium pump current
    c.i_NaK =
      P_NaK * K_o / (K_o + K_mk) * Na_i / (Na_i + K_mNa) /
      (1 + 0.1245 * Math::exp(-0.1 * V / RTF) + 0.0353 * Math::exp(-V / RTF));

    // Sodium calcium exchanger current
    const double exp_gamma   = Math::exp(gamma * V / RTF);
    const double exp_gamma_1 = Math::exp((gamma - 1) * V / RTF);
    c.i_NaCa                 = K_NaCa *
               (exp_gamma * Na_i * Na_i * Na_i * Ca_o -
                exp_gamma_1 * Na_o * Na_o * Na_o * Ca_i * alpha) /
               ((Km_Nai * Km_Nai * Km_Nai + Na_o * Na_o * Na_o) *
                (Km_Ca + Ca_o) * (1 + K_sat * exp_gamma_1));

    // Calcium pump current
    c.i_p_Ca = g_pCa * Ca_i / (Ca_i + K_pCa);

    // Potassium pump current
    c.i_p_K = g_pK * (V - E_K) / (1 + Math::exp((25 - V) / 5.98));

    c.total = c.i_K1 + c.i_to + c.i_Kr + c.i_Ks + c.i_CaL + c.i_NaK + c.i_Na +
              c.i_b_Na + c.i_NaCa + c.i_b_Ca + c.i_p_K + c.i_p_Ca;
    return c;
  }


  /// The rates of R' and the concentrations at the point read by @p in (as
  /// for currents()) with its currents @p c: out(state, rate) for each.
  template <typename In, typename Out>
  SYSTOLE_TTP_INLINE void
  concentration_rates(const In &in, const Currents &c, const Out &out)
  {
    // Calcium dynamics
    const double Ca_i   = in(1 + TTP::ca_i);
    const double Ca_SR  = in(1 + TTP::ca_sr);
    const double Ca_ss  = in(1 + TTP::ca_ss);
    const double R_p    = in(1 + TTP::r_prime);
    const double i_up   = Vmax_up / (1 + K_up * K_up / (Ca_i * Ca_i));
    const double i_leak = V_leak * (Ca_SR - Ca_i);
    const double i_xfer = V_xfer * (Ca_ss - Ca_i);
    const double kcasr  = max_sr - (max_sr - min_sr) / (1 + sq(EC / Ca_SR));
    const double ddt_Ca_i_total =
      -(c.i_b_Ca + c.i_p_Ca - 2 * c.i_NaCa) * Cm / (2 * V_c * F) +
      (i_leak - i_up) * V_sr / V_c + i_xfer;
    const double f_JCa_i_free = 1 / (1 + Buf_c * K_buf_c / sq(Ca_i + K_buf_c));
    const double f_JCa_sr_free =
      1 / (1 + Buf_sr * K_buf_sr / sq(Ca_SR + K_buf_sr));
    const double f_JCa_ss_free =
      1 / (1 + Buf_ss * K_buf_ss / sq(Ca_ss + K_buf_ss));
    const double k1    = k1_prime / kcasr;
    const double k2    = k2_prime * kcasr;
    const double O     = k1 * Ca_ss * Ca_ss * R_p / (k3 + k1 * Ca_ss * Ca_ss);
    const double i_rel = V_rel * O * (Ca_SR - Ca_ss);
    const double ddt_Ca_sr_total = i_up - (i_rel + i_leak);
    const double ddt_Ca_ss_total = -c.i_CaL * Cm / (2 * V_ss * F) +
                                   i_rel * V_sr / V_ss - i_xfer * V_c / V_ss;
    out(TTP::r_prime, -k2 * Ca_ss * R_p + k4 * (1 - R_p));
    out(TTP::ca_i, ddt_Ca_i_total * f_JCa_i_free);
    out(TTP::ca_sr, ddt_Ca_sr_total * f_JCa_sr_free);
    out(TTP::ca_ss, ddt_Ca_ss_total * f_JCa_ss_free);

    // Sodium dynamics
    out(TTP::na_i,
        -(c.i_Na + c.i_b_Na + 3 * c.i_NaK + 3 * c.i_NaCa) / (V_c * F) * Cm);

    // Potassium dynamics (without the stimulus: see the class comment)
    out(TTP::k_i,
        -(c.i_K1 + c.i_to + c.i_Kr + c.i_Ks + c.i_p_K - 2 * c.i_NaK) /
          (V_c * F) * Cm);
  }


  /// The six gates of the potassium and sodium channels (Xr1, Xr2, Xs, m, h,
  /// j) at the potential @p V [mV]: g.time_constant(gate, steady state, tau
  /// [ms]) or g.rate(gate, steady state, 1/tau [1/ms]) for each.
  template <class Math, typename Gates>
  SYSTOLE_TTP_INLINE void
  channel_gates(const double V, const Gates &g)
  {
    // Rapid time dependent potassium current, Xr1 gate
    {
      const double steady = 1 / (1 + Math::exp((-26 - V) / 7));
      const double alpha  = 450 / (1 + Math::exp((-45 - V) / 10));
      const double beta   = 6 / (1 + Math::exp((V + 30) / 11.5));
      g.time_constant(TTP::x_r1, steady, alpha * beta);
    }
    // Xr2 gate
    {
      const double steady = 1 / (1 + Math::exp((V + 88) / 24));
      const double alpha  = 3 / (1 + Math::exp((-60 - V) / 20));
      const double beta   = 1.12 / (1 + Math::exp((V - 60) / 20));
      g.time_constant(TTP::x_r2, steady, alpha * beta);
    }
    // Slow time dependent potassium current, Xs gate
    {
      const double steady = 1 / (1 + Math::exp((-5 - V) / 14));
      const double alpha  = 1400 / Math::sqrt(1 + Math::exp((5 - V) / 6));
      const double beta   = 1 / (1 + Math::exp((V - 35) / 15));
      g.time_constant(TTP::x_s, steady, alpha * beta + 80);
    }
    // Fast sodium current, m gate
    {
      const double steady = 1 / sq(1 + Math::exp((-56.86 - V) / 9.03));
      const double alpha  = 1 / (1 + Math::exp((-60 - V) / 5));
      const double beta   = 0.1 / (1 + Math::exp((V + 35) / 5)) +
                          0.1 / (1 + Math::exp((V - 50) / 200));
      g.time_constant(TTP::m, steady, alpha * beta);
    }
    // h and j gates: both branches, selected by V < -40 mV
    const bool   low       = V < -40;
    const double steady_hj = 1 / sq(1 + Math::exp((V + 71.55) / 7.43));
    {
      const double alpha = low ? 0.057 * Math::exp(-(V + 80) / 6.8) : 0;
      const double beta =
        low ? 2.7 * Math::exp(0.079 * V) + 310000 * Math::exp(0.3485 * V)
            : 0.77 / (0.13 * (1 + Math::exp((V + 10.66) / -11.1)));
      g.rate(TTP::h, steady_hj, alpha + beta);
    }
    {
      const double alpha = low ? (-25428 * Math::exp(0.2444 * V) -
                                  6.948e-6 * Math::exp(-0.04391 * V)) *
                                   (V + 37.78) /
                                   (1 + Math::exp(0.311 * (V + 79.23)))
                               : 0;
      const double beta =
        low ? 0.02424 * Math::exp(-0.01052 * V) /
                (1 + Math::exp(-0.1378 * (V + 40.14)))
            : 0.6 * Math::exp(0.057 * V) / (1 + Math::exp(-0.1 * (V + 32)));
      g.rate(TTP::j, steady_hj, alpha + beta);
    }
  }


  /// The six gates of the L-type calcium and transient outward currents (d,
  /// f, F2, FCass, s, r) at the potential @p V [mV] and subspace calcium
  /// @p Ca_ss [mM], as channel_gates(); the s gate of the endocardial
  /// variant if @p endocardial, of the two others otherwise.
  template <class Math, bool endocardial, typename Gates>
  SYSTOLE_TTP_INLINE void
  calcium_gates(const double V, const double Ca_ss, const Gates &g)
  {
    // L_type Ca current, d gate
    {
      const double steady  = 1 / (1 + Math::exp((-8 - V) / 7.5));
      const double alpha   = 1.4 / (1 + Math::exp((-35 - V) / 13)) + 0.25;
      const double beta    = 1.4 / (1 + Math::exp((V + 5) / 5));
      const double gamma_d = 1 / (1 + Math::exp((50 - V) / 20));
      g.time_constant(TTP::d, steady, alpha * beta + gamma_d);
    }
    // f gate
    {
      const double steady = 1 / (1 + Math::exp((V + 20) / 7));
      const double tau    = 1102.5 * Math::exp(-sq(V + 27) / 225) +
                         200 / (1 + Math::exp((13 - V) / 10)) +
                         180 / (1 + Math::exp((V + 30) / 10)) + 20;
      g.time_constant(TTP::f, steady, tau);
    }
    // F2 gate
    {
      const double steady = 0.67 / (1 + Math::exp((V + 35) / 7)) + 0.33;
      const double tau    = 562 * Math::exp(-sq(V + 27) / 240) +
                         31 / (1 + Math::exp((25 - V) / 10)) +
                         80 / (1 + Math::exp((V + 30) / 10));
      g.time_constant(TTP::f2, steady, tau);
    }
    // FCass gate
    {
      const double ca_ratio = sq(Ca_ss / 0.05);
      const double steady   = 0.6 / (1 + ca_ratio) + 0.4;
      const double tau      = 80 / (1 + ca_ratio) + 2;
      g.time_constant(TTP::f_cass, steady, tau);
    }
    // Transient outward current, s gate (the variant's, see the class
    // comment)
    if constexpr (endocardial)
      {
        const double steady = 1 / (1 + Math::exp((V + 28) / 5));
        const double tau    = 1000 * Math::exp(-sq(V + 67) / 1000) + 8;
        g.time_constant(TTP::s, steady, tau);
      }
    else
      {
        const double steady = 1 / (1 + Math::exp((V + 20) / 5));
        const double tau    = 85 * Math::exp(-sq(V + 45) / 320) +
                           5 / (1 + Math::exp((V - 20) / 5)) + 3;
        g.time_constant(TTP::s, steady, tau);
      }
    // r gate
    {
      const double steady = 1 / (1 + Math::exp((20 - V) / 6));
      const double tau    = 9.5 * Math::exp(-sq(V + 40) / 1800) + 0.8;
      g.time_constant(TTP::r, steady, tau);
    }
  }
} // namespace systole::Electrophysiology::TenTusscherPanfilovEquations
