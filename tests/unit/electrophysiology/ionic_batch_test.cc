// The batched ionic kernels against the per-point models: SimdMath's exp
// and log against glibc, the batched ten Tusscher-Panfilov right-hand side,
// ionic current and Rush-Larsen gates against the per-point functions on
// random states (round-off), a point's result independent of its place in
// a batch, and the other models' batches equal to their per-point
// functions.
#include "electrophysiology/aliev_panfilov.h"
#include "electrophysiology/mitchell_schaeffer.h"
#include "electrophysiology/rush_larsen.h"
#include "electrophysiology/simd_math.h"
#include "electrophysiology/single_cell.h"
#include "electrophysiology/ten_tusscher_panfilov.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace systole;
using namespace systole::Electrophysiology;

using TTP = TenTusscherPanfilov;

namespace
{
  /// |a - b| in units in the last place of b.
  double
  ulps(const double a, const double b)
  {
    if (a == b)
      return 0;
    return std::abs(a - b) /
           (std::nextafter(std::abs(b),
                           std::numeric_limits<double>::infinity()) -
            std::abs(b));
  }

  /// Random states of @p model (v, then the states, point after point):
  /// snapshots of a paced cell over an action potential, each with v
  /// redrawn uniformly in [-100, 60] mV for half of them and every state
  /// scaled by a random factor in [0.8, 1.2] (gates kept in [0, 1]).
  std::vector<double>
  random_states(const IonicModel &model, const unsigned int n_points)
  {
    const unsigned int               stride = 1 + model.n_states();
    std::vector<std::vector<double>> snapshots;
    SingleCell::Settings             settings;
    settings.time_step = 0.05;
    SingleCell cell(model, settings, {}, 0.0);
    cell.advance(400.0, [&](const double, const double v, const double *s) {
      std::vector<double> y{v};
      y.insert(y.end(), s, s + model.n_states());
      snapshots.push_back(y);
    });
    std::mt19937                           random(2024);
    std::uniform_real_distribution<double> V(-100, 60), scale(0.8, 1.2);
    std::vector<double>                    y(std::size_t(n_points) * stride);
    for (unsigned int i = 0; i < n_points; ++i)
      {
        std::vector<double> p = snapshots[random() % snapshots.size()];
        if (i % 2 == 1)
          p[0] = model.from_mV(V(random));
        for (unsigned int k = 1; k < stride; ++k)
          {
            p[k] *= scale(random);
            if (k <= model.n_gates())
              p[k] = std::min(p[k], 1.0);
          }
        std::copy(p.begin(), p.end(), y.begin() + std::size_t(i) * stride);
      }
    return y;
  }

  /// Largest |a_k - b_k| / (rel |b_k| + floor_k) over the points, with
  /// floor_k = abs of the largest |b_k| of component k: the error in units
  /// of the tolerance (pass: <= 1).
  double
  scaled_error(const std::vector<double> &a,
               const std::vector<double> &b,
               const unsigned int         stride,
               const double               rel,
               const double               abs)
  {
    std::vector<double> largest(stride, 0.0);
    for (std::size_t i = 0; i < b.size(); ++i)
      largest[i % stride] = std::max(largest[i % stride], std::abs(b[i]));
    double worst = 0;
    for (std::size_t i = 0; i < b.size(); ++i)
      {
        const double tol = rel * std::abs(b[i]) + abs * largest[i % stride];
        if (a[i] != b[i])
          worst = std::max(worst, std::abs(a[i] - b[i]) / tol);
      }
    return worst;
  }
} // namespace


TEST_CASE("SimdMath's exp and log are within 1 ulp of glibc's",
          "[ep][ionic][batch]")
{
  std::mt19937                           random(1);
  std::uniform_real_distribution<double> wide(-745, 709), narrow(-40, 40);
  std::uniform_real_distribution<double> exponent(-300, 300), unit(1, 2);
  double                                 worst_exp = 0, worst_log = 0;
  for (unsigned int i = 0; i < 200000; ++i)
    {
      const double x = i % 2 ? wide(random) : narrow(random);
      const double e = std::exp(x);
      if (e >= std::numeric_limits<double>::min()) // normal results
        worst_exp = std::max(worst_exp, ulps(SimdMath::exp(x), e));
      const double y =
        unit(random) * std::pow(2.0, std::round(exponent(random)));
      worst_log = std::max(worst_log, ulps(SimdMath::log(y), std::log(y)));
    }
  INFO("exp " << worst_exp << " ulp, log " << worst_log << " ulp");
  // glibc's own are correctly rounded in most cases: the two differ by at
  // most one rounding each.
  CHECK(worst_exp <= 2);
  CHECK(worst_log <= 2);
  // Near 1 (log(1 + tiny)) and at the reductions' edges.
  for (const double y : {1.0,
                         1.0 + 1e-15,
                         1.0 - 1e-15,
                         0.7071067811865476,
                         1.4142135623730951,
                         2.0,
                         0.5,
                         1e-300,
                         5e-324,
                         std::numeric_limits<double>::max()})
    CHECK(ulps(SimdMath::log(y), std::log(y)) <= 2);
  for (const double x : {0.0,
                         1e-300,
                         -1e-300,
                         0.34657359027997264,
                         -0.34657359027997264,
                         709.7,
                         -708.3,
                         1.0,
                         -1.0})
    CHECK(ulps(SimdMath::exp(x), std::exp(x)) <= 2);

  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(SimdMath::exp(710.0) == inf);
  CHECK(SimdMath::exp(1e300) == inf);
  CHECK(SimdMath::exp(inf) == inf);
  CHECK(SimdMath::exp(-746.0) == 0.0);
  CHECK(SimdMath::exp(-inf) == 0.0);
  CHECK(std::isnan(SimdMath::exp(nan)));
  // A subnormal result, as glibc's to a few of its ulps.
  CHECK(SimdMath::exp(-740.0) == Approx(std::exp(-740.0)).epsilon(1e-8));
  CHECK(SimdMath::log(0.0) == -inf);
  CHECK(std::isnan(SimdMath::log(-1.0)));
  CHECK(std::isnan(SimdMath::log(nan)));
  CHECK(SimdMath::log(inf) == inf);

  // x/(e^x - 1): the series branch and the other agree with glibc's expm1.
  double worst = 0;
  for (double x = -3; x <= 3; x += 1.0 / 1024 + 1e-7)
    if (x != 0)
      worst = std::max(worst,
                       ulps(SimdMath::x_over_expm1(x, SimdMath::exp(x)),
                            x / std::expm1(x)));
  INFO("x/expm1(x): " << worst << " ulp");
  CHECK(worst <= 4);
  CHECK(SimdMath::x_over_expm1(0.0, 1.0) == 1.0);
}


TEST_CASE("The batched ten Tusscher-Panfilov kernel equals the per-point "
          "model to round-off on random states",
          "[ep][ionic][ttp][batch]")
{
  // 1037 points: whole chunks and a partial last one.
  const unsigned int n_points = 1037;
  for (const auto type : {TTP::CellType::endocardial,
                          TTP::CellType::mid_myocardial,
                          TTP::CellType::epicardial})
    {
      TTP::Parameters p;
      p.cell_type = type;
      const TTP model(p);
      INFO(TTP::cell_type_name(type));
      const unsigned int        stride = 1 + model.n_states();
      const std::vector<double> y      = random_states(model, n_points);

      // Right-hand side: the potential's and the concentrations'. The
      // currents cancel in sums (V - E_X near reversal, I_ion near rest):
      // the tolerance is relative to the largest value of a component over
      // the points, 1e-13, besides 1e-12 of the value itself (measured: 4e-4
      // of that tolerance).
      std::vector<double> f(y.size()), reference(y.size());
      model.rhs_batch(n_points, stride, y.data(), f.data());
      model.IonicModel::rhs_batch(n_points, stride, y.data(), reference.data());
      const double rhs_error = scaled_error(f, reference, stride, 1e-12, 1e-13);
      INFO("right-hand side: " << rhs_error << " of the tolerance");
      CHECK(rhs_error <= 1);
      for (unsigned int i = 0; i < n_points; ++i)
        for (unsigned int g = 0; g < model.n_gates(); ++g)
          CHECK(f[std::size_t(i) * stride + 1 + g] == 0.0);

      // The current at v + dv (explicit_stiffness' central difference).
      for (const double dv : {0.0, 1e-4, -1e-4})
        {
          std::vector<double> I(n_points), I_reference(n_points);
          model.ionic_current_batch(n_points, stride, y.data(), dv, I.data());
          model.IonicModel::ionic_current_batch(n_points,
                                                stride,
                                                y.data(),
                                                dv,
                                                I_reference.data());
          const double error = scaled_error(I, I_reference, 1, 1e-12, 1e-13);
          INFO("I_ion at dv = " << dv << ": " << error << " of the tolerance");
          CHECK(error <= 1);
          if (dv == 0)
            {
              // The right-hand side's current (the two loops round alike
              // up to the compiler's contractions).
              std::vector<double> minus_f(n_points);
              for (unsigned int i = 0; i < n_points; ++i)
                minus_f[i] = -f[std::size_t(i) * stride];
              CHECK(scaled_error(I, minus_f, 1, 1e-12, 1e-13) <= 1);
            }
        }

      // A Rush-Larsen step: the gates to 1e-14 (absolute, they lie in
      // [0, 1]; measured: 6e-16); the other values untouched.
      for (const double dt : {0.005, 0.05, 0.5, 50.0})
        {
          std::vector<double> a = y, b = y;
          model.advance_gates_batch(dt, n_points, stride, a.data());
          model.IonicModel::advance_gates_batch(dt, n_points, stride, b.data());
          double worst = 0;
          for (std::size_t k = 0; k < a.size(); ++k)
            {
              const unsigned int c = k % stride;
              if (c >= 1 && c <= model.n_gates())
                worst = std::max(worst, std::abs(a[k] - b[k]));
              else
                REQUIRE(a[k] == y[k]);
            }
          INFO("gates, dt = " << dt << ": " << worst);
          CHECK(worst <= 1e-14);
        }
    }
}


TEST_CASE("A point's batched result does not depend on its place in the "
          "batch",
          "[ep][ionic][ttp][batch]")
{
  const TTP                 model{TTP::Parameters()};
  const unsigned int        stride = 1 + model.n_states();
  const unsigned int        n      = 37; // two chunks and 5 points
  const std::vector<double> y      = random_states(model, n);
  std::vector<double>       f(y.size()), g = y;
  model.rhs_batch(n, stride, y.data(), f.data());
  model.advance_gates_batch(0.05, n, stride, g.data());
  for (const unsigned int i : {0u, 15u, 16u, 31u, 32u, 36u})
    {
      const double       *yi = y.data() + std::size_t(i) * stride;
      std::vector<double> fi(stride), gi(yi, yi + stride);
      model.rhs_batch(1, stride, yi, fi.data());
      model.advance_gates_batch(0.05, 1, stride, gi.data());
      for (unsigned int k = 0; k < stride; ++k)
        {
          CHECK(fi[k] == f[std::size_t(i) * stride + k]);
          CHECK(gi[k] == g[std::size_t(i) * stride + k]);
        }
    }
  // A batch of none touches nothing.
  model.rhs_batch(0, stride, nullptr, nullptr);
  model.advance_gates_batch(0.05, 0, stride, nullptr);
}


TEST_CASE("The batches of Mitchell-Schaeffer and Aliev-Panfilov (their own "
          "loops and the IonicModel defaults) are the per-point functions, "
          "point by point",
          "[ep][ionic][batch]")
{
  const MitchellSchaeffer ms{MitchellSchaeffer::Parameters()};
  const AlievPanfilov     ap{AlievPanfilov::Parameters()};
  for (const IonicModel *model : {static_cast<const IonicModel *>(&ms),
                                  static_cast<const IonicModel *>(&ap)})
    {
      INFO(model->name());
      // A stride larger than the point: the values past it are not read.
      const unsigned int  n = 11, stride = 3;
      std::vector<double> y(n * stride), f(n * stride, -7);
      for (unsigned int i = 0; i < n; ++i)
        {
          y[i * stride]     = 0.1 * i;
          y[i * stride + 1] = 0.05 * i;
          y[i * stride + 2] = std::numeric_limits<double>::quiet_NaN();
        }
      model->rhs_batch(n, stride, y.data(), f.data());
      std::vector<double> f_default(n * stride, -7);
      model->IonicModel::rhs_batch(n, stride, y.data(), f_default.data());
      CHECK(f == f_default);
      std::vector<double> I(n);
      model->ionic_current_batch(n, stride, y.data(), 0.01, I.data());
      for (unsigned int i = 0; i < n; ++i)
        {
          double       ds;
          const double I_i =
            model->ionic_current_and_state_rhs(0.1 * i,
                                               &y[i * stride + 1],
                                               &ds);
          CHECK(f[i * stride] == -I_i);
          CHECK(f[i * stride + 1] == ds);
          CHECK(f[i * stride + 2] == -7);
          CHECK(I[i] ==
                model->ionic_current(0.1 * i + 0.01, &y[i * stride + 1]));
        }
      // No gates: the gate step changes nothing.
      std::vector<double> z = y;
      model->advance_gates_batch(0.1, n, stride, z.data());
      for (unsigned int k = 0; k < z.size(); ++k)
        CHECK((z[k] == y[k] || (std::isnan(z[k]) && std::isnan(y[k]))));
    }
}
