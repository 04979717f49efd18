#include "circulation/bdf_step.h"
#include "circulation/closed_loop.h"
#include "circulation/ode_integrator.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace systole::Circulation;

namespace
{
  using Vector = dealii::Vector<double>;

  /// The closed loop integrated with BdfStep in equal steps of @p h [ms] up
  /// to @p t_end, the pressures of external cavities fixed at @p p_ext.
  Vector
  integrate(const Model  &model,
            const double  h,
            const double  t_end,
            const Vector &p_ext,
            double       &largest_volume_change)
  {
    Vector y0;
    model.initial_state(y0);
    Vector            p0(model.n_cavities());
    BdfStep::Settings settings;
    BdfStep           step(model, settings, 0.0, y0, p0);
    const double      volume0 = model.total_blood_volume(y0);
    largest_volume_change     = 0;
    Vector                     W, p(step.external_cavities().size());
    dealii::FullMatrix<double> dW_dp;
    for (unsigned int a = 0; a < p.size(); ++a)
      p[a] = p_ext[step.external_cavities()[a]];
    const unsigned int n = std::lround(t_end / h);
    for (unsigned int i = 1; i <= n; ++i)
      {
        step.begin(i * h);
        step.solve(p, W, dW_dp);
        step.accept();
        largest_volume_change =
          std::max(largest_volume_change,
                   std::abs(model.total_blood_volume(step.state()) - volume0) /
                     volume0);
      }
    return step.state();
  }

  /// The closed loop with both ventricles external (3D in a heartbeat).
  ClosedLoop::Parameters
  two_external_cavities()
  {
    ClosedLoop::Parameters parameters;
    parameters.left_ventricle_kind = parameters.right_ventricle_kind =
      CavityKind::external;
    return parameters;
  }

  /// The pressures of the two external cavities [kPa].
  Vector
  cavity_pressures(const double lv, const double rv)
  {
    Vector p(2);
    p[0] = lv;
    p[1] = rv;
    return p;
  }

  double
  relative_difference(const Vector &a, const Vector &b)
  {
    Vector d = a;
    d -= b;
    return d.l2_norm() / b.l2_norm();
  }
} // namespace

TEST_CASE("BDF2 steps of the closed loop converge to ARKode's solution at "
          "second order and conserve the blood volume to round-off",
          "[circulation][bdf]")
{
  const ClosedLoop model{ClosedLoop::Parameters()};
  Vector           y0;
  model.initial_state(y0);
  Integrator::Settings tight;
  tight.relative_tolerance        = 1e-10;
  tight.absolute_volume_tolerance = 1e-8;
  Integrator reference(model, tight, 0.0, y0);
  // Half a beat: through the isovolumetric contraction and the ejection.
  const double t_end = 400;
  reference.advance(t_end);

  const Vector p_ext(model.n_cavities()); // no external cavities
  double       drift_coarse = 0, drift_fine = 0;
  const double e_coarse =
    relative_difference(integrate(model, 1.0, t_end, p_ext, drift_coarse),
                        reference.state());
  const double e_fine =
    relative_difference(integrate(model, 0.5, t_end, p_ext, drift_fine),
                        reference.state());
  INFO("error h = 1 ms: " << e_coarse << ", h = 0.5 ms: " << e_fine);
  // Second order: 4 for the halved step; the kinks of the diode valves
  // inside steps cost a little.
  CHECK(e_coarse / e_fine > 3.0);
  CHECK(e_fine < 1e-4);
  CHECK(drift_coarse < 1e-13);
  CHECK(drift_fine < 1e-13);
}

TEST_CASE("BdfStep's volume target dW/dp of two external cavities equals "
          "central differences",
          "[circulation][bdf]")
{
  const ClosedLoop model(two_external_cavities());
  REQUIRE(model.n_cavities() == 2);
  Vector y0;
  model.initial_state(y0);
  // The mitral valve open, the aortic one closed.
  const Vector      p0 = cavity_pressures(1.2, 0.4);
  BdfStep::Settings settings;
  BdfStep           step(model, settings, 0.0, y0, p0);
  REQUIRE(step.external_cavities().size() == 2);
  // Two steps, so the second is BDF2.
  Vector                     W, W_plus, W_minus;
  dealii::FullMatrix<double> dW_dp, unused;
  step.begin(2.0);
  step.solve(p0, W, dW_dp);
  step.accept();
  REQUIRE(step.order() == 2);
  step.begin(5.0);
  Vector p = p0;
  p[0]     = 1.3;
  step.solve(p, W, dW_dp);
  const double delta = 1e-5;
  for (unsigned int b = 0; b < 2; ++b)
    {
      Vector pp = p, pm = p;
      pp[b] += delta;
      pm[b] -= delta;
      step.solve(pp, W_plus, unused);
      step.solve(pm, W_minus, unused);
      for (unsigned int a = 0; a < 2; ++a)
        {
          const double fd = (W_plus[a] - W_minus[a]) / (2 * delta);
          INFO("dW_" << a << "/dp_" << b << " = " << dW_dp(a, b)
                     << ", central difference " << fd);
          CHECK(std::abs(fd - dW_dp(a, b)) <=
                1e-6 * std::max(1.0, std::abs(dW_dp(a, b))));
        }
    }
  // A higher cavity pressure pushes blood out: the volume falls.
  CHECK(dW_dp(0, 0) < 0);
  CHECK(dW_dp(1, 1) < 0);
}

TEST_CASE("BdfStep's start pressures: the linear extrapolation of the last "
          "two, but the last accepted ones right after a restart",
          "[circulation][bdf]")
{
  const ClosedLoop model(two_external_cavities());
  Vector           y0;
  model.initial_state(y0);
  const BdfStep::Settings settings;
  BdfStep step(model, settings, 0.0, y0, cavity_pressures(1.2, 0.4));
  Vector  W;
  dealii::FullMatrix<double> dW_dp;
  // Accepted: 1.2, 0.4 at 0 ms, then 2.0, 0.1 at 1 ms (a steep change, as
  // across the short step that locates a valve event).
  step.begin(1.0);
  const Vector p1 = cavity_pressures(2.0, 0.1);
  step.solve(p1, W, dW_dp);
  step.accept();
  // A step of 3 ms: the extrapolation goes on with the slope of the last
  // step, the start too.
  step.begin(4.0);
  const Vector predicted = step.predicted_pressures();
  CHECK(std::abs(predicted[0] - (2.0 + 3.0 * 0.8)) < 1e-14);
  CHECK(std::abs(predicted[1] - (0.1 - 3.0 * 0.3)) < 1e-14);
  Vector start = step.start_pressures();
  CHECK(std::abs(start[0] - predicted[0]) < 1e-14);
  CHECK(std::abs(start[1] - predicted[1]) < 1e-14);
  // After a restart (a valve switched) the start is the last accepted
  // pressure, and so is the prediction: the point before the event is
  // forgotten (the pressures have a kink at a valve switch, a jump where the
  // base springs are re-referred).
  step.restart();
  step.begin(4.0);
  start = step.start_pressures();
  CHECK(start[0] == 2.0);
  CHECK(start[1] == 0.1);
  CHECK(step.predicted_pressures()[0] == 2.0);
  // The first step after the restart has no pressure error estimate (one
  // point): the jump to 2.6 kPa at 4 ms does not reject it. (Extrapolated
  // from before the event, to 4.4 kPa, the estimate was (4.4 - 2.6) / 8 /
  // (0.01 + 1e-3 x 2.6) = 17.9 times the tolerance.)
  Vector p2 = p1;
  p2[0]     = 2.6;
  step.solve(p2, W, dW_dp);
  CHECK(step.error_norms()[1] == 0.0);
  step.accept();
  step.begin(5.0);
  CHECK(std::abs(step.start_pressures()[0] - 2.8) < 1e-14);
  CHECK(step.order() == 2);
}
