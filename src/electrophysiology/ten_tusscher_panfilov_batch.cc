// The batched ten Tusscher-Panfilov 2006 kernel: the expressions of
// ten_tusscher_panfilov_impl.h (those of the per-point model, the .ode's
// one by one), over chunks of points the compiler turns into SIMD code.
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
#include "electrophysiology/ten_tusscher_panfilov_impl.h"

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

namespace systole::Electrophysiology
{
  namespace
  {
    using TTP           = TenTusscherPanfilov;
    namespace Equations = TenTusscherPanfilovEquations;

    /// The equations' Math: SimdMath's exp and log, a sqrt that vectorizes.
    struct VectorMath
    {
      static SYSTOLE_TTP_INLINE double
      exp(const double x)
      {
        return SimdMath::exp(x);
      }

      static SYSTOLE_TTP_INLINE double
      log(const double x)
      {
        return SimdMath::log(x);
      }

      static SYSTOLE_TTP_INLINE double
      sqrt(const double x)
      {
        return __builtin_sqrt(x);
      }

      static SYSTOLE_TTP_INLINE double
      x_over_expm1(const double x, const double exp_x)
      {
        return SimdMath::x_over_expm1(x, exp_x);
      }
    };

    /// Points per chunk: a multiple of the widest SIMD register (8 doubles).
    constexpr unsigned int width = 16;

    /// Number of values of a point: v and the states.
    constexpr unsigned int n_values = 1 + TTP::n_all_states;

    /// A chunk of points, one array per value (v first, then the states).
    struct alignas(64) Chunk
    {
      double v[n_values][width];
    };

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

    /// TenTusscherPanfilov::ionic_current_and_state_rhs() over a chunk:
    /// out.v[0] = -I_ion, out.v[1 + k] the rates of the non-gates.
    SYSTOLE_TTP_INLINE void
    rhs_chunk(const Chunk &in, Chunk &out, const double g_to, const double g_Ks)
    {
#pragma omp simd
      for (unsigned int i = 0; i < width; ++i)
        {
          const auto value = [&](const unsigned int k) { return in.v[k][i]; };
          const Equations::Currents c =
            Equations::currents<VectorMath>(value, g_to, g_Ks);
          out.v[0][i] = -c.total;
          Equations::concentration_rates(value,
                                         c,
                                         [&](const unsigned int state,
                                             const double       rate) {
                                           out.v[1 + state][i] = rate;
                                         });
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
          current[i] = Equations::currents<VectorMath>(value, g_to, g_Ks).total;
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

      SYSTOLE_TTP_INLINE void
      time_constant(const unsigned int gate,
                    const double       steady,
                    const double       tau) const
      {
        relax(gate, steady, SimdMath::exp(-dt / tau));
      }

      SYSTOLE_TTP_INLINE void
      rate(const unsigned int gate,
           const double       steady,
           const double       rate) const
      {
        relax(gate, steady, SimdMath::exp(-dt * rate));
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
        Equations::channel_gates<VectorMath>(c.v[0][i],
                                             GateUpdate{c, out, i, dt});
    }


    /// The Rush-Larsen step of the six gates of the L-type calcium and
    /// transient outward currents (d, f, F2, FCass, s, r) of a chunk.
    template <bool endocardial>
    SYSTOLE_TTP_INLINE void
    calcium_gates_chunk(const Chunk &c, Chunk &out, const double dt)
    {
#pragma omp simd
      for (unsigned int i = 0; i < width; ++i)
        Equations::calcium_gates<VectorMath, endocardial>(
          c.v[0][i],
          c.v[1 + TTP::ca_ss][i],
          GateUpdate{c, out, i, dt});
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
