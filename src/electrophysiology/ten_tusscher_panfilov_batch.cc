// The batched ten Tusscher-Panfilov 2006 kernel: the expressions of
// ten_tusscher_panfilov.cc (the per-point model, the .ode's expressions one
// by one), over chunks of points the compiler turns into SIMD code.
//
// How. The points of a batch are copied a chunk of `width` points at a time
// from the solvers' interleaved layout (v and the 18 states of a point side by
// side) into arrays of one quantity each (structure of arrays), evaluated in
// one `#pragma omp simd` loop over the chunk, and copied back. Inside the
// loop every branch of the model is a select (both sides evaluated) and exp
// and log are SimdMath's (simd_math.h), so the whole loop vectorizes; the
// loop is compiled for AVX-512, AVX2 and baseline x86-64 (GCC's
// target_clones, chosen when the library is loaded). A partial last chunk is
// padded with copies of its last point, so that every point goes through the
// same vector code, wherever it falls in a batch: the results do not depend
// on the partition of the nodes over the ranks.
//
// The differences from the per-point model are round-off: SimdMath's exp and
// log (within 1 ulp, glibc's are within 1 ulp too), x/expm1(x) of I_CaL by a
// series for |x| < 0.5, 1/(alpha + beta) time constants as rates (e^{-dt
// (alpha + beta)}), and the compiler's multiply-add contraction on targets
// with FMA. tests/unit/electrophysiology/ionic_batch_test.cc compares the two
// on random states.

#include "electrophysiology/simd_math.h"
#include "electrophysiology/ten_tusscher_panfilov.h"
#include "electrophysiology/ten_tusscher_panfilov_constants.h"

#include <algorithm>
#include <cstddef>

// Multi-versioned for the SIMD widths of x86-64 (resolved once, at load
// time); one version elsewhere.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
  defined(__linux__)
#  define SYSTOLE_TTP_TARGETS \
    __attribute__((           \
      target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#  define SYSTOLE_TTP_TARGETS
#endif

#define SYSTOLE_TTP_INLINE inline __attribute__((always_inline))

namespace systole::Electrophysiology
{
  namespace
  {
    using namespace TenTusscherPanfilovConstants;
    using TTP    = TenTusscherPanfilov;
    namespace sm = SimdMath;

    /// Points per chunk: a multiple of the widest SIMD register (8 doubles).
    constexpr unsigned int width = 16;

    /// Number of values of a point: v and the states.
    constexpr unsigned int n_values = 1 + TTP::n_all_states;

    /// A chunk of points, one array per value (v first, then the states).
    struct alignas(64) Chunk
    {
      double v[n_values][width];
    };

    SYSTOLE_TTP_INLINE double
    sq(const double x)
    {
      return x * x;
    }

    /// Copy the @p count points from @p y (stride @p stride) into @p c,
    /// padding the chunk with the last one; only the values [first, last).
    SYSTOLE_TTP_INLINE void
    gather(const double      *y,
           const unsigned int stride,
           const unsigned int count,
           const unsigned int first,
           const unsigned int last,
           Chunk             &c)
    {
      for (unsigned int i = 0; i < width; ++i)
        {
          const double *p = y + std::size_t(std::min(i, count - 1)) * stride;
          for (unsigned int k = first; k < last; ++k)
            c.v[k][i] = p[k];
        }
    }

    /// The 12 currents of the per-point model and their sum, at one point.
    struct Currents
    {
      double i_K1, i_to, i_Kr, i_Ks, i_CaL, i_NaK, i_Na, i_b_Na, i_NaCa, i_b_Ca,
        i_p_K, i_p_Ca, total;
    };

    /// TenTusscherPanfilov::currents(), value k of the point (0: V, 1 + j:
    /// state j) from in(k).
    template <typename In>
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
      const double E_Na = RTF * sm::log(Na_o / Na_i);
      const double E_K  = RTF * sm::log(K_o / K_i);
      const double E_Ks =
        RTF * sm::log((K_o + P_kna * Na_o) / (K_i + P_kna * Na_i));
      const double E_Ca = 0.5 * RTF * sm::log(Ca_o / Ca_i);

      // Inward rectifier potassium current (sqrt(K_o/5.4) = 1)
      const double alpha_K1 = 0.1 / (1 + sm::exp(0.06 * (V - E_K - 200)));
      const double beta_K1  = (3 * sm::exp(0.0002 * (V - E_K + 100)) +
                              sm::exp(0.1 * (V - E_K - 10))) /
                             (1 + sm::exp(-0.5 * (V - E_K)));
      const double xK1_inf = alpha_K1 / (alpha_K1 + beta_K1);
      static_assert(K_o == 5.4, "sqrt(K_o/5.4) is taken as 1");
      c.i_K1 = g_K1 * xK1_inf * (V - E_K);

      // Rapid time dependent potassium current
      c.i_Kr = g_Kr * y_xr1 * y_xr2 * (V - E_K);

      // Slow time dependent potassium current
      c.i_Ks = g_Ks * sq(y_xs) * (V - E_Ks);

      // Fast sodium current
      c.i_Na = g_Na * y_m * y_m * y_m * y_h * y_j * (V - E_Na);

      // Sodium background current
      c.i_b_Na = g_bna * (V - E_Na);

      // L_type Ca current (the per-point model's form, finite at 15 mV)
      const double x     = 2 * (V - 15) / RTF;
      const double exp_x = sm::exp(x);
      c.i_CaL            = g_CaL * y_d * y_f * y_f2 * y_fcs * 2 * F *
                (0.25 * Ca_ss * exp_x - Ca_o) * sm::x_over_expm1(x, exp_x);

      // Calcium background current
      c.i_b_Ca = g_bca * (V - E_Ca);

      // Transient outward current
      c.i_to = g_to * y_r * y_s * (V - E_K);

      // Sodium potassium pump current
      c.i_NaK =
        P_NaK * K_o / (K_o + K_mk) * Na_i / (Na_i + K_mNa) /
        (1 + 0.1245 * sm::exp(-0.1 * V / RTF) + 0.0353 * sm::exp(-V / RTF));

      // Sodium calcium exchanger current
      const double exp_gamma   = sm::exp(gamma * V / RTF);
      const double exp_gamma_1 = sm::exp((gamma - 1) * V / RTF);
      c.i_NaCa                 = K_NaCa *
                 (exp_gamma * Na_i * Na_i * Na_i * Ca_o -
                  exp_gamma_1 * Na_o * Na_o * Na_o * Ca_i * alpha) /
                 ((Km_Nai * Km_Nai * Km_Nai + Na_o * Na_o * Na_o) *
                  (Km_Ca + Ca_o) * (1 + K_sat * exp_gamma_1));

      // Calcium pump current
      c.i_p_Ca = g_pCa * Ca_i / (Ca_i + K_pCa);

      // Potassium pump current
      c.i_p_K = g_pK * (V - E_K) / (1 + sm::exp((25 - V) / 5.98));

      c.total = c.i_K1 + c.i_to + c.i_Kr + c.i_Ks + c.i_CaL + c.i_NaK + c.i_Na +
                c.i_b_Na + c.i_NaCa + c.i_b_Ca + c.i_p_K + c.i_p_Ca;
      return c;
    }


    /// TenTusscherPanfilov::ionic_current_and_state_rhs() over a chunk:
    /// out.v[0] = -I_ion, out.v[1 + k] the rates of the non-gates.
    SYSTOLE_TTP_INLINE void
    rhs_chunk(const Chunk &in, Chunk &out, const double g_to, const double g_Ks)
    {
#pragma omp simd
      for (unsigned int i = 0; i < width; ++i)
        {
          const auto value = [&](const unsigned int k) { return in.v[k][i]; };
          const Currents c = currents(value, g_to, g_Ks);

          // Calcium dynamics
          const double Ca_i   = value(1 + TTP::ca_i);
          const double Ca_SR  = value(1 + TTP::ca_sr);
          const double Ca_ss  = value(1 + TTP::ca_ss);
          const double R_p    = value(1 + TTP::r_prime);
          const double i_up   = Vmax_up / (1 + K_up * K_up / (Ca_i * Ca_i));
          const double i_leak = V_leak * (Ca_SR - Ca_i);
          const double i_xfer = V_xfer * (Ca_ss - Ca_i);
          const double kcasr =
            max_sr - (max_sr - min_sr) / (1 + sq(EC / Ca_SR));
          const double ddt_Ca_i_total =
            -(c.i_b_Ca + c.i_p_Ca - 2 * c.i_NaCa) * Cm / (2 * V_c * F) +
            (i_leak - i_up) * V_sr / V_c + i_xfer;
          const double f_JCa_i_free =
            1 / (1 + Buf_c * K_buf_c / sq(Ca_i + K_buf_c));
          const double f_JCa_sr_free =
            1 / (1 + Buf_sr * K_buf_sr / sq(Ca_SR + K_buf_sr));
          const double f_JCa_ss_free =
            1 / (1 + Buf_ss * K_buf_ss / sq(Ca_ss + K_buf_ss));
          const double k1 = k1_prime / kcasr;
          const double k2 = k2_prime * kcasr;
          const double O = k1 * Ca_ss * Ca_ss * R_p / (k3 + k1 * Ca_ss * Ca_ss);
          const double i_rel           = V_rel * O * (Ca_SR - Ca_ss);
          const double ddt_Ca_sr_total = i_up - (i_rel + i_leak);
          const double ddt_Ca_ss_total = -c.i_CaL * Cm / (2 * V_ss * F) +
                                         i_rel * V_sr / V_ss -
                                         i_xfer * V_c / V_ss;
          out.v[0][i]                = -c.total;
          out.v[1 + TTP::r_prime][i] = -k2 * Ca_ss * R_p + k4 * (1 - R_p);
          out.v[1 + TTP::ca_i][i]    = ddt_Ca_i_total * f_JCa_i_free;
          out.v[1 + TTP::ca_sr][i]   = ddt_Ca_sr_total * f_JCa_sr_free;
          out.v[1 + TTP::ca_ss][i]   = ddt_Ca_ss_total * f_JCa_ss_free;

          // Sodium dynamics
          out.v[1 + TTP::na_i][i] =
            -(c.i_Na + c.i_b_Na + 3 * c.i_NaK + 3 * c.i_NaCa) / (V_c * F) * Cm;

          // Potassium dynamics (without the stimulus)
          out.v[1 + TTP::k_i][i] =
            -(c.i_K1 + c.i_to + c.i_Kr + c.i_Ks + c.i_p_K - 2 * c.i_NaK) /
            (V_c * F) * Cm;
        }
    }


    /// I_ion at v + dv over a chunk, into current[].
    SYSTOLE_TTP_INLINE void
    current_chunk(const Chunk &in,
                  const double dv,
                  double      *current,
                  const double g_to,
                  const double g_Ks)
    {
#pragma omp simd
      for (unsigned int i = 0; i < width; ++i)
        {
          const auto value = [&](const unsigned int k) {
            return k == 0 ? in.v[0][i] + dv : in.v[k][i];
          };
          current[i] = currents(value, g_to, g_Ks).total;
        }
    }


    /// The Rush-Larsen update of the gates of point @p i of a chunk:
    /// s <- s_inf + (s - s_inf) e^{-dt/tau}, or e^{-dt rate}.
    struct GateUpdate
    {
      const Chunk       &c;
      Chunk             &out;
      const unsigned int i;
      const double       dt;

      SYSTOLE_TTP_INLINE void
      relax(const unsigned int gate, const double steady, const double a) const
      {
        out.v[1 + gate][i] = steady + (c.v[1 + gate][i] - steady) * a;
      }

      SYSTOLE_TTP_INLINE double
      decay(const double tau) const
      {
        return sm::exp(-dt / tau);
      }
    };


    /// The Rush-Larsen step of the six gates of the potassium and sodium
    /// channels (Xr1, Xr2, Xs, m, h, j) of a chunk: gate_rates() and
    /// rush_larsen().
    SYSTOLE_TTP_INLINE void
    channel_gates_chunk(const Chunk &c, Chunk &out, const double dt)
    {
#pragma omp simd
      for (unsigned int i = 0; i < width; ++i)
        {
          const double     V = c.v[0][i];
          const GateUpdate g{c, out, i, dt};

          // Xr1 gate
          {
            const double steady = 1 / (1 + sm::exp((-26 - V) / 7));
            const double alpha  = 450 / (1 + sm::exp((-45 - V) / 10));
            const double beta   = 6 / (1 + sm::exp((V + 30) / 11.5));
            g.relax(TTP::x_r1, steady, g.decay(alpha * beta));
          }
          // Xr2 gate
          {
            const double steady = 1 / (1 + sm::exp((V + 88) / 24));
            const double alpha  = 3 / (1 + sm::exp((-60 - V) / 20));
            const double beta   = 1.12 / (1 + sm::exp((V - 60) / 20));
            g.relax(TTP::x_r2, steady, g.decay(alpha * beta));
          }
          // Xs gate
          {
            const double steady = 1 / (1 + sm::exp((-5 - V) / 14));
            const double alpha =
              1400 / __builtin_sqrt(1 + sm::exp((5 - V) / 6));
            const double beta = 1 / (1 + sm::exp((V - 35) / 15));
            g.relax(TTP::x_s, steady, g.decay(alpha * beta + 80));
          }
          // m gate
          {
            const double steady = 1 / sq(1 + sm::exp((-56.86 - V) / 9.03));
            const double alpha  = 1 / (1 + sm::exp((-60 - V) / 5));
            const double beta   = 0.1 / (1 + sm::exp((V + 35) / 5)) +
                                0.1 / (1 + sm::exp((V - 50) / 200));
            g.relax(TTP::m, steady, g.decay(alpha * beta));
          }
          // h and j gates: both branches, selected by V < -40 mV
          const bool   low       = V < -40;
          const double steady_hj = 1 / sq(1 + sm::exp((V + 71.55) / 7.43));
          {
            const double alpha = low ? 0.057 * sm::exp(-(V + 80) / 6.8) : 0;
            const double beta =
              low ? 2.7 * sm::exp(0.079 * V) + 310000 * sm::exp(0.3485 * V)
                  : 0.77 / (0.13 * (1 + sm::exp((V + 10.66) / -11.1)));
            g.relax(TTP::h, steady_hj, sm::exp(-dt * (alpha + beta)));
          }
          {
            const double alpha = low ? (-25428 * sm::exp(0.2444 * V) -
                                        6.948e-6 * sm::exp(-0.04391 * V)) *
                                         (V + 37.78) /
                                         (1 + sm::exp(0.311 * (V + 79.23)))
                                     : 0;
            const double beta =
              low ? 0.02424 * sm::exp(-0.01052 * V) /
                      (1 + sm::exp(-0.1378 * (V + 40.14)))
                  : 0.6 * sm::exp(0.057 * V) / (1 + sm::exp(-0.1 * (V + 32)));
            g.relax(TTP::j, steady_hj, sm::exp(-dt * (alpha + beta)));
          }
        }
    }


    /// The Rush-Larsen step of the six gates of the L-type calcium and
    /// transient outward currents (d, f, F2, FCass, s, r) of a chunk.
    template <bool endocardial>
    SYSTOLE_TTP_INLINE void
    calcium_gates_chunk(const Chunk &c, Chunk &out, const double dt)
    {
#pragma omp simd
      for (unsigned int i = 0; i < width; ++i)
        {
          const double     V = c.v[0][i];
          const GateUpdate g{c, out, i, dt};

          // d gate
          {
            const double steady  = 1 / (1 + sm::exp((-8 - V) / 7.5));
            const double alpha   = 1.4 / (1 + sm::exp((-35 - V) / 13)) + 0.25;
            const double beta    = 1.4 / (1 + sm::exp((V + 5) / 5));
            const double gamma_d = 1 / (1 + sm::exp((50 - V) / 20));
            g.relax(TTP::d, steady, g.decay(alpha * beta + gamma_d));
          }
          // f gate
          {
            const double steady = 1 / (1 + sm::exp((V + 20) / 7));
            const double tau    = 1102.5 * sm::exp(-sq(V + 27) / 225) +
                               200 / (1 + sm::exp((13 - V) / 10)) +
                               180 / (1 + sm::exp((V + 30) / 10)) + 20;
            g.relax(TTP::f, steady, g.decay(tau));
          }
          // F2 gate
          {
            const double steady = 0.67 / (1 + sm::exp((V + 35) / 7)) + 0.33;
            const double tau    = 562 * sm::exp(-sq(V + 27) / 240) +
                               31 / (1 + sm::exp((25 - V) / 10)) +
                               80 / (1 + sm::exp((V + 30) / 10));
            g.relax(TTP::f2, steady, g.decay(tau));
          }
          // FCass gate
          {
            const double ca_ratio = sq(c.v[1 + TTP::ca_ss][i] / 0.05);
            const double steady   = 0.6 / (1 + ca_ratio) + 0.4;
            const double tau      = 80 / (1 + ca_ratio) + 2;
            g.relax(TTP::f_cass, steady, g.decay(tau));
          }
          // s gate (the variant's)
          if constexpr (endocardial)
            {
              const double steady = 1 / (1 + sm::exp((V + 28) / 5));
              const double tau    = 1000 * sm::exp(-sq(V + 67) / 1000) + 8;
              g.relax(TTP::s, steady, g.decay(tau));
            }
          else
            {
              const double steady = 1 / (1 + sm::exp((V + 20) / 5));
              const double tau    = 85 * sm::exp(-sq(V + 45) / 320) +
                                 5 / (1 + sm::exp((V - 20) / 5)) + 3;
              g.relax(TTP::s, steady, g.decay(tau));
            }
          // r gate
          {
            const double steady = 1 / (1 + sm::exp((20 - V) / 6));
            const double tau    = 9.5 * sm::exp(-sq(V + 40) / 1800) + 0.8;
            g.relax(TTP::r, steady, g.decay(tau));
          }
        }
    }


    /// The Rush-Larsen step of the 12 gates of a chunk in place:
    /// TenTusscherPanfilov::gate_rates() and rush_larsen(), in two
    /// vectorized loops over the chunk (each gate reads the potential and
    /// its own state only).
    template <bool endocardial>
    SYSTOLE_TTP_INLINE void
    gates_chunk(const Chunk &c, Chunk &out, const double dt)
    {
      channel_gates_chunk(c, out, dt);
      calcium_gates_chunk<endocardial>(c, out, dt);
    }


    SYSTOLE_TTP_TARGETS void
    rhs_batch_kernel(const unsigned int n_points,
                     const unsigned int stride,
                     const double      *y,
                     double            *f,
                     const double       g_to,
                     const double       g_Ks)
    {
      Chunk in, out;
      for (unsigned int start = 0; start < n_points; start += width)
        {
          const unsigned int count = std::min(width, n_points - start);
          const double      *y0    = y + std::size_t(start) * stride;
          gather(y0, stride, count, 0, n_values, in);
          rhs_chunk(in, out, g_to, g_Ks);
          double *f0 = f + std::size_t(start) * stride;
          for (unsigned int i = 0; i < count; ++i)
            {
              double *p = f0 + std::size_t(i) * stride;
              p[0]      = out.v[0][i];
              for (unsigned int k = 1; k <= TTP::n_gate_states; ++k)
                p[k] = 0;
              for (unsigned int k = 1 + TTP::n_gate_states; k < n_values; ++k)
                p[k] = out.v[k][i];
            }
        }
    }


    SYSTOLE_TTP_TARGETS void
    current_batch_kernel(const unsigned int n_points,
                         const unsigned int stride,
                         const double      *y,
                         const double       dv,
                         double            *current,
                         const double       g_to,
                         const double       g_Ks)
    {
      Chunk  in;
      double out[width];
      for (unsigned int start = 0; start < n_points; start += width)
        {
          const unsigned int count = std::min(width, n_points - start);
          gather(y + std::size_t(start) * stride,
                 stride,
                 count,
                 0,
                 n_values,
                 in);
          current_chunk(in, dv, out, g_to, g_Ks);
          std::copy(out, out + count, current + start);
        }
    }


    SYSTOLE_TTP_TARGETS void
    gates_batch_kernel(const double       dt,
                       const unsigned int n_points,
                       const unsigned int stride,
                       double            *y,
                       const bool         endocardial)
    {
      Chunk c, out;
      for (unsigned int start = 0; start < n_points; start += width)
        {
          const unsigned int count = std::min(width, n_points - start);
          double            *y0    = y + std::size_t(start) * stride;
          // v, the gates and Ca_ss.
          gather(y0, stride, count, 0, 1 + TTP::n_gate_states, c);
          gather(y0, stride, count, 1 + TTP::ca_ss, 2 + TTP::ca_ss, c);
          if (endocardial)
            gates_chunk<true>(c, out, dt);
          else
            gates_chunk<false>(c, out, dt);
          for (unsigned int i = 0; i < count; ++i)
            {
              double *p = y0 + std::size_t(i) * stride;
              for (unsigned int k = 1; k <= TTP::n_gate_states; ++k)
                p[k] = out.v[k][i];
            }
        }
    }
  } // namespace


  void
  TenTusscherPanfilov::rhs_batch(const unsigned int n_points,
                                 const unsigned int stride,
                                 const double      *y,
                                 double            *f) const
  {
    rhs_batch_kernel(n_points, stride, y, f, g_to, g_Ks);
  }


  void
  TenTusscherPanfilov::ionic_current_batch(const unsigned int n_points,
                                           const unsigned int stride,
                                           const double      *y,
                                           const double       dv,
                                           double            *current) const
  {
    current_batch_kernel(n_points, stride, y, dv, current, g_to, g_Ks);
  }


  void
  TenTusscherPanfilov::advance_gates_batch(const double       dt,
                                           const unsigned int n_points,
                                           const unsigned int stride,
                                           double            *y) const
  {
    gates_batch_kernel(dt,
                       n_points,
                       stride,
                       y,
                       params.cell_type == CellType::endocardial);
  }
} // namespace systole::Electrophysiology
