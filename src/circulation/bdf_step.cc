#include "circulation/bdf_step.h"

#include <deal.II/base/exceptions.h>

#include "base/errors.h"

#include <algorithm>
#include <cmath>

namespace systole::Circulation
{
  BdfStep::BdfStep(const Model                  &model,
                   const Settings               &settings,
                   const double                  t0,
                   const dealii::Vector<double> &y0,
                   const dealii::Vector<double> &p0)
    : model(model)
    , settings(settings)
  {
    AssertThrow(y0.size() == model.n_states() &&
                  p0.size() == model.n_cavities(),
                dealii::ExcMessage("BdfStep: the initial state or the cavity "
                                   "pressures have the wrong size."));
    for (unsigned int c = 0; c < model.n_cavities(); ++c)
      if (model.cavities()[c].kind == CavityKind::external)
        external.push_back(c);
    history.push_back({t0, y0, p0});
  }


  unsigned int
  BdfStep::order() const
  {
    return first_order || history.size() < 2 ? 1 : 2;
  }


  void
  BdfStep::begin(const double t)
  {
    const Point &last = history.back();
    AssertThrow(t > last.t,
                dealii::ExcMessage("BdfStep::begin: the step must end after "
                                   "the last accepted time."));
    t_new           = t;
    h               = t - last.t;
    solved          = false;
    step_iterations = 0;

    // The derivative at the last state: the first-order predictor and the
    // Hermite predictor of BDF2 need it.
    dealii::Vector<double> f;
    model.rhs({last.t, last.y, last.p}, f);
    y_predicted = last.y;
    if (order() == 1)
      {
        a0 = a1 = 1.0;
        a2      = 0.0;
        // Explicit Euler predictor: P - y = -h^2 y''/2, BDF1: y_num - y =
        // h^2 y''/2, so LTE = (y_num - P) / 2.
        y_predicted.add(h, f);
        error_constant = 0.5;
        known          = last.y;
      }
    else
      {
        const Point &before = history[history.size() - 2];
        const double h_prev = last.t - before.t;
        const double omega  = h / h_prev;
        a0                  = (1 + 2 * omega) / (1 + omega);
        a1                  = 1 + omega;
        a2                  = omega * omega / (1 + omega);
        // The quadratic P with P(t_n) = y_n, P'(t_n) = f_n, P(t_n-1) =
        // y_n-1: P(t_n + h) = y_n + h f_n + (h / h_prev)^2 (y_n-1 - y_n +
        // h_prev f_n). Its error P - y = -(h + h_prev) h^2 y'''/6; BDF2's
        // y_num - y = c h^3 y''' with c = (1 + omega)^2 / (6 omega (1 + 2
        // omega)) (2/9 for equal steps).
        y_predicted.add(h, f);
        dealii::Vector<double> curvature = before.y;
        curvature -= last.y;
        curvature.add(h_prev, f);
        y_predicted.add(omega * omega, curvature);
        const double c_corrector =
          (1 + omega) * (1 + omega) / (6 * omega * (1 + 2 * omega));
        const double c_predictor = (1 + 1 / omega) / 6;
        error_constant           = c_corrector / (c_corrector + c_predictor);
        known                    = last.y;
        known *= a1;
        known.add(-a2, before.y);
      }
  }


  dealii::Vector<double>
  BdfStep::predicted_pressures() const
  {
    dealii::Vector<double> p(external.size());
    const Point           &last = history.back();
    for (unsigned int k = 0; k < external.size(); ++k)
      {
        p[k] = last.p[external[k]];
        if (history.size() == 2)
          {
            const Point &before = history.front();
            p[k] += h / (last.t - before.t) *
                    (last.p[external[k]] - before.p[external[k]]);
          }
      }
    return p;
  }


  dealii::Vector<double>
  BdfStep::start_pressures() const
  {
    if (!first_order)
      return predicted_pressures();
    dealii::Vector<double> p(external.size());
    for (unsigned int k = 0; k < external.size(); ++k)
      p[k] = history.back().p[external[k]];
    return p;
  }


  void
  BdfStep::solve(const dealii::Vector<double> &p,
                 dealii::Vector<double>       &W,
                 dealii::FullMatrix<double>   &dW_dp)
  {
    const unsigned int n = model.n_states(), k = external.size();
    AssertThrow(p.size() == k,
                dealii::ExcMessage("BdfStep::solve: one pressure per external "
                                   "cavity expected."));
    // All cavity pressures: the given ones for the external cavities (the
    // model ignores the others).
    p_solution = history.back().p;
    for (unsigned int j = 0; j < k; ++j)
      p_solution[external[j]] = p[j];
    if (!solved)
      y_solution = y_predicted;

    // Newton on G(y) = a0 y - known - h f(t, y, p) = 0, dG/dy = a0 I - h
    // df/dy. f is piecewise linear in the diode valves, so a few iterations
    // reach round-off; the last one also makes G's linear invariants
    // (the blood volume) exact.
    dealii::Vector<double>     f, G(n), dy(n);
    dealii::FullMatrix<double> df_dy, df_dp, J_inverse(n, n);
    // (a0 I - h df/dy)^-1 and df/dp at the current y (n is small: invert).
    const auto invert_jacobian = [&]() {
      model.jacobian({t_new, y_solution, p_solution}, df_dy, df_dp);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j)
          J_inverse(i, j) = (i == j ? a0 : 0.0) - h * df_dy(i, j);
      J_inverse.gauss_jordan();
    };
    constexpr unsigned int max_iterations = 30;
    for (unsigned int it = 0;; ++it)
      {
        model.rhs({t_new, y_solution, p_solution}, f);
        invert_jacobian();
        for (unsigned int i = 0; i < n; ++i)
          G[i] = a0 * y_solution[i] - known[i] - h * f[i];
        J_inverse.vmult(dy, G);
        double size = 0; // weighted size of the update
        for (unsigned int i = 0; i < n; ++i)
          {
            y_solution[i] -= dy[i];
            size =
              std::max(size, std::abs(dy[i]) / tolerance(i, y_solution[i]));
          }
        ++step_iterations;
        // At 1e-8 of the error tolerance: far below the local error, and
        // reached in one or two iterations where f is linear.
        if (size <= 1e-8)
          {
            // dy/dp = (a0 I - h df/dy)^-1 h df/dp, at the solution's side
            // of every valve.
            invert_jacobian();
            W.reinit(k);
            dW_dp.reinit(k, k);
            for (unsigned int a = 0; a < k; ++a)
              {
                const unsigned int row =
                  model.cavities()[external[a]].volume_state;
                W[a] = y_solution[row];
              }
            for (unsigned int b = 0; b < k; ++b)
              {
                dealii::Vector<double> column(n), dy_dp(n);
                for (unsigned int i = 0; i < n; ++i)
                  column[i] = h * df_dp(i, external[b]);
                J_inverse.vmult(dy_dp, column);
                for (unsigned int a = 0; a < k; ++a)
                  dW_dp(a, b) =
                    dy_dp[model.cavities()[external[a]].volume_state];
              }
            // The pressures of the elastance cavities at the solution.
            dealii::Vector<double> all;
            model.cavity_pressures({t_new, y_solution, p_solution}, all);
            p_solution = all;
            solved     = true;
            return;
          }
        AssertThrow(it + 1 < max_iterations && std::isfinite(size),
                    ExcNewtonDidNotConverge("0D circulation step at t = " +
                                              std::to_string(t_new) + " ms",
                                            it + 1,
                                            size));
      }
  }


  double
  BdfStep::tolerance(const unsigned int i, const double value) const
  {
    return settings.absolute_volume_tolerance / model.states()[i].volume_scale +
           settings.relative_tolerance * std::abs(value);
  }


  std::array<double, 2>
  BdfStep::error_norms() const
  {
    AssertThrow(solved,
                dealii::ExcMessage("BdfStep::error_norms before solve()."));
    std::array<double, 2> e = {{0.0, 0.0}};
    for (unsigned int i = 0; i < model.n_states(); ++i)
      {
        e[0] =
          std::max(e[0],
                   error_constant * std::abs(y_solution[i] - y_predicted[i]) /
                     tolerance(i, y_solution[i]));
      }
    if (history.size() == 2)
      {
        const dealii::Vector<double> p_predicted = predicted_pressures();
        for (unsigned int a = 0; a < external.size(); ++a)
          {
            const double p     = p_solution[external[a]];
            const double scale = settings.absolute_pressure_tolerance +
                                 settings.relative_tolerance * std::abs(p);
            e[1] = std::max(e[1], std::abs(p - p_predicted[a]) / 8 / scale);
          }
      }
    return e;
  }


  double
  BdfStep::step_ratio() const
  {
    const auto   e     = error_norms();
    const double q     = order() + 1.0;
    const auto   ratio = [](const double error, const double exponent) {
      return error > 0 ? 0.8 * std::pow(1 / error, exponent) : 2.0;
    };
    return std::clamp(std::min(ratio(e[0], 1 / q), ratio(e[1], 0.5)), 0.2, 2.0);
  }


  void
  BdfStep::accept()
  {
    AssertThrow(solved, dealii::ExcMessage("BdfStep::accept before solve()."));
    history.push_back({t_new, y_solution, p_solution});
    if (history.size() > 2)
      history.erase(history.begin());
    first_order = false;
    solved      = false;
  }


  void
  BdfStep::restart()
  {
    // The point before the event goes too: the pressure error estimate
    // (error_norms()) extrapolated the pressures through it, across the kink
    // of the valve switch (and, at a mitral closure that re-refers the base
    // springs, a jump), and rejected the first step after the event down to
    // the minimum step.
    first_order = true;
    history.erase(history.begin(), history.end() - 1);
  }
} // namespace systole::Circulation
