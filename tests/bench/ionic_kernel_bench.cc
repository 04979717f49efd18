// Micro-benchmark of the ionic kernels (not a test: run by hand, not by
// ctest): the cost per node of the ten Tusscher-Panfilov (and
// Mitchell-Schaeffer) right-hand side and Rush-Larsen gate update through the
// per-point interface (a virtual call per node, the IonicModel defaults) and
// through the batched one, on n nodes in the monodomain's interleaved
// layout, with states sampled over a paced action potential (every branch of
// the model is taken); the explicit right-hand side evaluations per ARKode
// step of the monodomain's integrator; a STREAM triad for the memory
// bandwidth; and an experiment: the gates' voltage-only rates from lookup
// tables (linear interpolation, as openCARP), their cost and their error on
// a gate step and on the APD90 of a paced cell. docs/verification.md
// ("Electrophysiology: the ionic kernels") has the numbers.
//
//   build/tests/systole-ionic-bench [n_nodes [seconds_per_measure]]

#include <deal.II/base/mpi.h>

#include "electrophysiology/action_potential.h"
#include "electrophysiology/arkode_adapter.h"
#include "electrophysiology/mitchell_schaeffer.h"
#include "electrophysiology/simd_math.h"
#include "electrophysiology/single_cell.h"
#include "electrophysiology/ten_tusscher_panfilov.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <utility>
#include <vector>

using namespace systole;
using namespace systole::Electrophysiology;

namespace
{
  using Clock = std::chrono::steady_clock;

  /// Best (least) seconds per call of @p f over repetitions filling about
  /// @p budget seconds.
  double
  best_time(const std::function<void()> &f, const double budget)
  {
    double     best  = 1e30;
    const auto start = Clock::now();
    unsigned   reps  = 0;
    do
      {
        const auto t0 = Clock::now();
        f();
        best =
          std::min(best,
                   std::chrono::duration<double>(Clock::now() - t0).count());
        ++reps;
    } while (reps < 3 ||
             std::chrono::duration<double>(Clock::now() - start).count() <
               budget);
    return best;
  }

  /// STREAM triad a = b + 3 c over @p n doubles: GB/s counting 24 bytes per
  /// element (STREAM's convention; the write-allocate read not counted).
  double
  triad(const std::size_t n, const double budget)
  {
    std::vector<double> a(n, 1.0), b(n, 2.0), c(n, 0.5);
    const double        t = best_time(
      [&] {
        double *__restrict pa       = a.data();
        const double *__restrict pb = b.data();
        const double *__restrict pc = c.data();
        for (std::size_t i = 0; i < n; ++i)
          pa[i] = pb[i] + 3.0 * pc[i];
      },
      budget);
    return 24.0 * n / t / 1e9;
  }

  /// States (v, then the model's states) sampled every @p every ms over
  /// the first 500 ms of a cell paced at 10 ms.
  std::vector<std::vector<double>>
  sampled_states(const IonicModel &model, const double every)
  {
    SingleCell::Settings settings;
    settings.time_step = 0.02;
    SingleCell                       cell(model, settings, {}, 0.0);
    std::vector<std::vector<double>> states;
    double                           next = 0;
    cell.advance(500.0, [&](const double t, const double v, const double *s) {
      if (t >= next)
        {
          std::vector<double> y{v};
          y.insert(y.end(), s, s + model.n_states());
          states.push_back(y);
          next += every;
        }
    });
    return states;
  }

  /// The explicit right-hand side evaluations per step of the monodomain's
  /// integrator (ARK 3, fixed steps, a Rush-Larsen post-step that changes
  /// the state) on one point.
  double
  explicit_evaluations_per_step()
  {
    const TenTusscherPanfilov model{TenTusscherPanfilov::Parameters()};
    const unsigned int        n = 1 + model.n_states();
    LA::MPI::Vector           y(dealii::complete_index_set(n), MPI_COMM_SELF);
    std::vector<double>       y0(n);
    y0[0] = model.resting_potential();
    model.resting_state(y0.data() + 1);
    for (unsigned int i = 0; i < n; ++i)
      y[i] = y0[i];
    y.compress(dealii::VectorOperation::insert);
    ImexIntegrator::Settings  settings; // order 3, fixed steps
    ImexIntegrator::Callbacks callbacks;
    callbacks.explicit_rhs =
      [&](const double, const LA::MPI::Vector &z, LA::MPI::Vector &f) {
        for (unsigned int i = 0; i < n; ++i)
          f[i] = 0;
        f[0] = -1e-3 * z[0];
        f.compress(dealii::VectorOperation::insert);
      };
    callbacks.implicit_rhs = [](const LA::MPI::Vector &, LA::MPI::Vector &f) {
      f = 0;
    };
    callbacks.solve =
      [](const double, const LA::MPI::Vector &b, LA::MPI::Vector &x) { x = b; };
    callbacks.after_step = [&](const double, const double, LA::MPI::Vector &z) {
      z[1] = 0.5 * z[1];
      z.compress(dealii::VectorOperation::insert);
    };
    ImexIntegrator     integrator(settings, callbacks, 0.0, MPI_COMM_SELF);
    const unsigned int steps = 100;
    for (unsigned int k = 1; k <= steps; ++k)
      integrator.evolve(y, 0.05 * k);
    return double(integrator.n_explicit_evaluations()) / integrator.n_steps();
  }

  struct Costs
  {
    double rhs_ns, gates_ns;
  };

  /// ns per node of one right-hand side and one gate update through the
  /// per-point interface (@p batched false) or the batched one.
  Costs
  measure(const IonicModel                       &model,
          const std::vector<std::vector<double>> &pool,
          const unsigned int                      n_nodes,
          const bool                              batched,
          const double                            budget)
  {
    const unsigned int  stride = 1 + model.n_states();
    std::vector<double> y(std::size_t(n_nodes) * stride), f(y.size());
    std::mt19937        random(7);
    for (unsigned int i = 0; i < n_nodes; ++i)
      {
        const auto &s = pool[random() % pool.size()];
        std::copy(s.begin(), s.end(), y.begin() + std::size_t(i) * stride);
      }
    const std::vector<double> y0  = y;
    const double              rhs = best_time(
      [&] {
        if (batched)
          model.rhs_batch(n_nodes, stride, y.data(), f.data());
        else
          model.IonicModel::rhs_batch(n_nodes, stride, y.data(), f.data());
      },
      budget);
    double gates = 0;
    if (model.n_gates() > 0)
      gates = best_time(
        [&] {
          // A step of 0.05 ms from the sampled states each time.
          std::copy(y0.begin(), y0.end(), y.begin());
          if (batched)
            model.advance_gates_batch(0.05, n_nodes, stride, y.data());
          else
            model.IonicModel::advance_gates_batch(0.05,
                                                  n_nodes,
                                                  stride,
                                                  y.data());
        },
        budget);
    // The copy of the state inside the gate measure, on its own.
    const double copy =
      model.n_gates() == 0
        ? 0
        : best_time([&] { std::copy(y0.begin(), y0.end(), y.begin()); },
                    budget);
    return {1e9 * rhs / n_nodes, 1e9 * std::max(0.0, gates - copy) / n_nodes};
  }

  /// ns per node of the copies into and out of the chunks (structure of
  /// arrays) that the batched ten Tusscher-Panfilov kernel does around its
  /// arithmetic, for a right-hand side (19 values in and out).
  double
  transpose_cost(const unsigned int n_nodes, const double budget)
  {
    constexpr unsigned int width = 16, n = 19;
    std::vector<double>    y(std::size_t(n_nodes) * n, 1.0), f(y.size());
    alignas(64) double     c[n][width];
    const double           t = best_time(
      [&] {
        for (unsigned int start = 0; start < n_nodes; start += width)
          {
            const unsigned int count = std::min(width, n_nodes - start);
            for (unsigned int i = 0; i < width; ++i)
              for (unsigned int k = 0; k < n; ++k)
                c[k][i] =
                  y[(std::size_t(start) + std::min(i, count - 1)) * n + k];
            asm volatile("" : : "r"(&c[0][0]) : "memory");
            for (unsigned int i = 0; i < count; ++i)
              for (unsigned int k = 0; k < n; ++k)
                f[(std::size_t(start) + i) * n + k] = c[k][i];
          }
      },
      budget);
    return 1e9 * t / n_nodes;
  }

  /// f(0), ..., f(n - 1), unrolled.
  template <std::size_t... i, typename F>
  inline __attribute__((always_inline)) void
  unrolled(std::index_sequence<i...>, const F &f)
  {
    (f(i), ...);
  }

  /// ten Tusscher-Panfilov with the rates of its 11 voltage-only gates
  /// (all but f_CaSS) from tables over V in [v_min, v_max] with step
  /// @p step mV, linearly interpolated (clamped outside): steady state and
  /// rate 1/tau, then e^{-dt rate} by SimdMath::exp. An experiment only.
  class TabulatedTTP : public TenTusscherPanfilov
  {
  public:
    static constexpr unsigned int width = 16, n_v_gates = 11;
    static constexpr double       v_min = -120, v_max = 80;

    explicit TabulatedTTP(const double step)
      : TenTusscherPanfilov(Parameters())
      , step(step)
      , n_rows(static_cast<unsigned int>(std::lround((v_max - v_min) / step)) +
               1)
      , table(std::size_t(n_rows) * 2 * n_v_gates)
    {
      std::vector<double> s(n_states()), steady(n_gates()), tau(n_gates());
      resting_state(s.data());
      for (unsigned int k = 0; k < n_rows; ++k)
        {
          gate_rates(v_min + k * step, s.data(), steady.data(), tau.data());
          static_assert(f_cass == n_v_gates, "f_CaSS is the last gate");
          for (unsigned int g = 0; g < n_v_gates; ++g)
            {
              table[(std::size_t(k) * n_v_gates + g) * 2]     = steady[g];
              table[(std::size_t(k) * n_v_gates + g) * 2 + 1] = 1 / tau[g];
            }
        }
    }

    void
    advance_gates_batch(const double       dt,
                        const unsigned int n_points,
                        const unsigned int stride,
                        double            *y) const override
    {
      tabulated_gates(dt, n_points, stride, y, table.data(), n_rows, step);
    }

    std::size_t
    table_bytes() const
    {
      return table.size() * sizeof(double);
    }

  private:
    using ChunkIn  = double[1 + n_gate_states + 1][width];
    using ChunkOut = double[1 + n_gate_states][width];

    static inline __attribute__((always_inline)) void
    lut_chunk(const ChunkIn &c,
              ChunkOut      &out,
              const double   dt,
              const double *__restrict table,
              const unsigned int n_rows,
              const double       step)
    {
#pragma omp simd
      for (unsigned int i = 0; i < width; ++i)
        {
          const double V   = c[0][i];
          double       x   = (V - v_min) / step;
          x                = x < 0 ? 0 : (x > n_rows - 2 ? n_rows - 2 : x);
          const int    row = static_cast<int>(x);
          const double w   = x - row;
          const int    r0  = row * int(2 * n_v_gates);
          const int    r1  = r0 + int(2 * n_v_gates);
          // The voltage-only gates are the first 11 (f_CaSS is last),
          // unrolled at compile time.
          const auto gate = [&](const unsigned int g)
            __attribute__((always_inline))
          {
            const double s0 = table[r0 + 2 * g], s1 = table[r1 + 2 * g];
            const double k0 = table[r0 + 2 * g + 1], k1 = table[r1 + 2 * g + 1];
            const double steady = s0 + w * (s1 - s0);
            const double rate   = k0 + w * (k1 - k0);
            out[1 + g][i] =
              steady + (c[1 + g][i] - steady) * SimdMath::exp(-dt * rate);
          };
          unrolled(std::make_index_sequence<n_v_gates>(), gate);
          const double r      = c[1 + n_gate_states][i] / 0.05;
          const double steady = 0.6 / (1 + r * r) + 0.4;
          const double rate   = 1 / (80 / (1 + r * r) + 2);
          out[1 + f_cass][i] =
            steady + (c[1 + f_cass][i] - steady) * SimdMath::exp(-dt * rate);
        }
    }

    __attribute__((
      target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"))) static void
    tabulated_gates(const double       dt,
                    const unsigned int n_points,
                    const unsigned int stride,
                    double            *y,
                    const double      *table,
                    const unsigned int n_rows,
                    const double       step)
    {
      alignas(64) double c[1 + n_gate_states + 1][width],
        out[1 + n_gate_states][width];
      for (unsigned int start = 0; start < n_points; start += width)
        {
          const unsigned int count = std::min(width, n_points - start);
          double            *y0    = y + std::size_t(start) * stride;
          for (unsigned int i = 0; i < width; ++i)
            {
              const double *p =
                y0 + std::size_t(std::min(i, count - 1)) * stride;
              for (unsigned int k = 0; k <= n_gate_states; ++k)
                c[k][i] = p[k];
              c[1 + n_gate_states][i] = p[1 + ca_ss];
            }
          lut_chunk(c, out, dt, table, n_rows, step);
          for (unsigned int i = 0; i < count; ++i)
            for (unsigned int k = 1; k <= n_gate_states; ++k)
              y0[std::size_t(i) * stride + k] = out[k][i];
        }
    }

    const double        step;
    const unsigned int  n_rows;
    std::vector<double> table;
  };


  /// APD90 [ms] of the second beat of a cell paced at 1 Hz, dt 0.02 ms.
  double
  apd90(const IonicModel &model)
  {
    SingleCell::Settings settings;
    settings.time_step = 0.02;
    SingleCell::Pacing pacing;
    SingleCell         cell(model, settings, pacing, 0.0);
    cell.advance(1000.0 + pacing.start);
    ActionPotentialRecorder recorder;
    recorder.start(1000.0 + pacing.start,
                   model.to_mV(cell.potential()),
                   model.calcium_uM(cell.state().data()));
    cell.advance(2000.0, [&](const double t, const double v, const double *s) {
      recorder.add(t, model.to_mV(v), model.calcium_uM(s));
    });
    return recorder.summary().APD90_ms;
  }
} // namespace


int
main(int argc, char **argv)
{
  // MPI and PETSc (the integrator's vectors).
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const unsigned int n_nodes = argc > 1 ? std::atoi(argv[1]) : 100000;
  const double       budget  = argc > 2 ? std::atof(argv[2]) : 1.0;

  std::printf("STREAM triad: %.1f GB/s (3 x 160 MB), %.1f GB/s (3 x 1.6 MB), "
              "%.1f GB/s (3 x 160 kB)\n",
              triad(20000000, budget),
              triad(200000, budget),
              triad(20000, budget));

  const double evaluations = explicit_evaluations_per_step();
  std::printf("explicit right-hand sides per ARKode step (ARK 3, fixed "
              "steps, Rush-Larsen post-step): %.2f\n",
              evaluations);

  const TenTusscherPanfilov ttp{TenTusscherPanfilov::Parameters()};
  const MitchellSchaeffer   ms{MitchellSchaeffer::Parameters()};
  std::printf("%u nodes, best of repeated calls [ns per node]:\n", n_nodes);
  std::printf("| model | interface | right-hand side | gates | per node-step "
              "(%.2f rhs + gates) |\n",
              evaluations);
  for (const IonicModel *model : {static_cast<const IonicModel *>(&ttp),
                                  static_cast<const IonicModel *>(&ms)})
    {
      const auto pool = sampled_states(*model, 0.5);
      for (const bool batched : {false, true})
        {
          const Costs c = measure(*model, pool, n_nodes, batched, budget);
          std::printf("| %s | %s | %.1f | %.1f | %.1f |\n",
                      model->name().c_str(),
                      batched ? "batched" : "per point",
                      c.rhs_ns,
                      c.gates_ns,
                      evaluations * c.rhs_ns + c.gates_ns);
        }
    }
  std::printf("chunk copies (interleaved <-> arrays) of a right-hand side: "
              "%.1f ns per node\n",
              transpose_cost(n_nodes, budget));

  // Lookup tables for the gates: cost and error against the exact batch.
  const auto          pool   = sampled_states(ttp, 0.5);
  const unsigned int  stride = 1 + ttp.n_states();
  std::vector<double> y(std::size_t(n_nodes) * stride);
  std::mt19937        random(11);
  for (unsigned int i = 0; i < n_nodes; ++i)
    {
      const auto &p = pool[random() % pool.size()];
      std::copy(p.begin(), p.end(), y.begin() + std::size_t(i) * stride);
    }
  const double apd_exact = apd90(ttp);
  for (const double step : {0.1, 0.01})
    {
      const TabulatedTTP  lut(step);
      const Costs         c = measure(lut, pool, n_nodes, true, budget);
      std::vector<double> a = y, b = y;
      lut.advance_gates_batch(0.05, n_nodes, stride, a.data());
      ttp.advance_gates_batch(0.05, n_nodes, stride, b.data());
      double worst = 0;
      for (std::size_t k = 0; k < a.size(); ++k)
        worst = std::max(worst, std::abs(a[k] - b[k]));
      const double apd = apd90(lut);
      std::printf("gates from tables, step %.2f mV (%.1f MB): %.1f ns per "
                  "node (exact: measured above); largest gate difference "
                  "after a 0.05 ms step %.1e; APD90 of the second beat "
                  "%.4f ms (exact %.4f, difference %.1e ms)\n",
                  step,
                  lut.table_bytes() / 1e6,
                  c.gates_ns,
                  worst,
                  apd,
                  apd_exact,
                  apd - apd_exact);
    }
}
