#include "simulation/load_curves.h"

#include <deal.II/base/function_parser.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>

namespace systole
{
  void
  LoadCurve::accept(const double)
  {}

  std::vector<double>
  LoadCurve::state() const
  {
    return {};
  }

  void
  LoadCurve::set_state(const std::vector<double> &state)
  {
    AssertThrow(state.empty(),
                dealii::ExcMessage("The checkpoint holds the state of an ODE "
                                   "load curve for a function of time."));
  }

  double
  ArosticaActivation::operator()(const double t) const
  {
    const double f = 0.25 * (1.0 + std::tanh((t - t_sys) / gamma)) *
                     (1.0 - std::tanh((t - t_dias) / gamma));
    return a_max * f + a_min * (1.0 - f);
  }

  double
  ArosticaActivation::relaxed(const double t) const
  {
    return 0.5 * (1.0 - std::tanh((t - t_dias) / gamma));
  }

  double
  ScalarOdeCurve::integrate(const double t0,
                            const double y0,
                            const double t1) const
  {
    if (!(t1 > t0))
      return y0;
    const auto   n = static_cast<unsigned int>(std::ceil((t1 - t0) / max_step));
    const double h = (t1 - t0) / n;
    double       y = y0;
    for (unsigned int i = 0; i < n; ++i)
      {
        const double t  = t0 + i * h;
        const double k1 = rhs(t, y);
        const double k2 = rhs(t + 0.5 * h, y + 0.5 * h * k1);
        const double k3 = rhs(t + 0.5 * h, y + 0.5 * h * k2);
        const double k4 = rhs(t + h, y + h * k3);
        y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      }
    return y;
  }

  double
  ScalarOdeCurve::value(const double time) const
  {
    AssertThrow(time >= accepted_time - 1e-12,
                dealii::ExcMessage(
                  "A load ODE was asked for t = " + std::to_string(time) +
                  " ms before its accepted time " +
                  std::to_string(accepted_time) + " ms."));
    return integrate(accepted_time, accepted_value, time);
  }

  void
  ScalarOdeCurve::accept(const double time)
  {
    accepted_value = value(time);
    accepted_time  = std::max(time, accepted_time);
  }

  std::vector<double>
  ScalarOdeCurve::state() const
  {
    return {accepted_time, accepted_value};
  }

  void
  ScalarOdeCurve::set_state(const std::vector<double> &state)
  {
    AssertThrow(state.size() == 2,
                dealii::ExcMessage("The checkpoint's state of an ODE load "
                                   "curve has " +
                                   std::to_string(state.size()) +
                                   " values, not 2."));
    accepted_time  = state[0];
    accepted_value = state[1];
  }

  ArosticaActiveStress::ArosticaActiveStress(
    const double              sigma_0,
    const ArosticaActivation &activation)
    : sigma_0(sigma_0)
    , activation(activation)
  {}

  double
  ArosticaActiveStress::rhs(const double t, const double tau) const
  {
    const double a = activation(t);
    return -std::abs(a) * tau + sigma_0 * std::max(a, 0.0);
  }

  ArosticaPressure::ArosticaPressure(const double              sigma_mid,
                                     const double              sigma_pre,
                                     const double              alpha_pre,
                                     const double              alpha_mid,
                                     const ArosticaActivation &activation)
    : sigma_mid(sigma_mid)
    , sigma_pre(sigma_pre)
    , alpha_pre(alpha_pre)
    , alpha_mid(alpha_mid)
    , activation(activation)
  {}

  double
  ArosticaPressure::rhs(const double t, const double p) const
  {
    const double g_pre = activation.relaxed(t);
    const double b     = activation(t) + alpha_pre * g_pre + alpha_mid;
    return -std::abs(b) * p + sigma_mid * std::max(b, 0.0) +
           sigma_pre * std::max(g_pre, 0.0);
  }

  namespace
  {
    /// A deal.II function expression of t [ms].
    class FunctionCurve : public LoadCurve
    {
    public:
      FunctionCurve(const std::string &expression, const std::string &entry)
      {
        // muparser reports a syntax error on std::cerr before deal.II
        // throws; the one-line message below says it instead.
        std::ostringstream quiet;
        std::streambuf    *cerr = std::cerr.rdbuf(quiet.rdbuf());
        try
          {
            function.initialize("t",
                                expression,
                                std::map<std::string, double>{{"pi", M_PI}});
            function.value(dealii::Point<1>(0.0));
            std::cerr.rdbuf(cerr);
          }
        catch (...)
          {
            std::cerr.rdbuf(cerr);
            AssertThrow(false,
                        dealii::ExcMessage(
                          entry + ": '" + expression +
                          "' is not a function expression of t [ms] "
                          "(muparser syntax, e.g. 2 * sin(pi * t / 300)^2)."));
          }
      }

      double
      value(const double time) const override
      {
        return function.value(dealii::Point<1>(time));
      }

    private:
      dealii::FunctionParser<1> function;
    };

    std::string
    lower(std::string text)
    {
      std::transform(text.begin(), text.end(), text.begin(), [](char c) {
        return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      });
      return text;
    }
  } // namespace

  void
  LoadCurveParameters::declare(dealii::ParameterHandler &prm,
                               const std::string        &name,
                               const std::string        &unit)
  {
    using namespace dealii::Patterns;
    const bool pressure = name == "Pressure";
    prm.declare_entry(
      name + " model",
      "function",
      Selection("function|Arostica"),
      "function: the load is " + name +
        " function (an expression of t); Arostica: "
        "the ODE of the benchmark of Arostica et al. 2025 (subsection "
        "Arostica " +
        lower(name) +
        "), from 0 at t = 0, integrated by RK4 "
        "with steps of at most 0.01 ms. Units: -.");
    prm.declare_entry(name + " function",
                      "0",
                      Anything(),
                      "The " + lower(name) +
                        " as a function expression of the time t [ms] "
                        "(muparser syntax, pi is known), e.g. 2 * sin(pi * "
                        "t / 300)^2 * (t < 300). Units: " +
                        unit + ".");
    prm.enter_subsection("Arostica " + lower(name));
    if (pressure)
      {
        prm.declare_entry("Sigma mid",
                          "16",
                          Double(),
                          "sigma_mid of dp/dt = -|b| p + sigma_mid max(b, 0) "
                          "+ sigma_pre max(g_pre, 0). Units: kPa.");
        prm.declare_entry("Sigma pre",
                          "7",
                          Double(),
                          "sigma_pre (the pre-load, while g_pre = S-(t - "
                          "t_dias) > 0); the benchmark writes 7 kPa, a rate "
                          "per second of its time. Units: kPa/s.");
        prm.declare_entry("Alpha pre",
                          "5",
                          Double(),
                          "alpha_pre of b = a(t) + alpha_pre g_pre + "
                          "alpha_mid. Units: 1/s.");
        prm.declare_entry("Alpha mid",
                          "1",
                          Double(),
                          "alpha_mid of b. Units: 1/s.");
      }
    else
      prm.declare_entry("Sigma 0",
                        "150",
                        Double(),
                        "sigma_0 of dtau/dt = -|a| tau + sigma_0 max(a, 0). "
                        "Units: kPa.");
    prm.declare_entry("Activation rate",
                      "5",
                      Double(),
                      "a_max of a(t) = a_max f(t) + a_min (1 - f(t)), f(t) = "
                      "S+(t - t_sys) S-(t - t_dias), S±(d) = (1 ± tanh(d / "
                      "gamma)) / 2. Units: 1/s.");
    prm.declare_entry("Relaxation rate",
                      "-30",
                      Double(),
                      "a_min of a(t) (negative). Units: 1/s.");
    prm.declare_entry("Systole time",
                      pressure ? "170" : "160",
                      Double(),
                      "t_sys: when f switches on. Units: ms.");
    prm.declare_entry("Diastole time",
                      "484",
                      Double(),
                      "t_dias: when f switches off. Units: ms.");
    prm.declare_entry("Switch width",
                      "5",
                      Double(0.0),
                      "gamma of S±: the width of the switches. Units: ms.");
    prm.leave_subsection();
  }

  std::unique_ptr<LoadCurve>
  LoadCurveParameters::create(const dealii::ParameterHandler &prm,
                              const std::string              &name)
  {
    const std::vector<std::string> path = {"Elastodynamics"};
    if (prm.get(path, name + " model") == "function")
      return std::make_unique<FunctionCurve>(prm.get(path, name + " function"),
                                             "Elastodynamics / " + name +
                                               " function");
    const std::vector<std::string> sub = {"Elastodynamics",
                                          "Arostica " + lower(name)};
    ArosticaActivation             a;
    a.a_max  = 1e-3 * prm.get_double(sub, "Activation rate");
    a.a_min  = 1e-3 * prm.get_double(sub, "Relaxation rate");
    a.t_sys  = prm.get_double(sub, "Systole time");
    a.t_dias = prm.get_double(sub, "Diastole time");
    a.gamma  = prm.get_double(sub, "Switch width");
    AssertThrow(a.gamma > 0.0,
                dealii::ExcMessage("Elastodynamics / Arostica " + lower(name) +
                                   " / Switch width must be positive."));
    if (name == "Pressure")
      return std::make_unique<ArosticaPressure>(
        prm.get_double(sub, "Sigma mid"),
        1e-3 * prm.get_double(sub, "Sigma pre"),
        1e-3 * prm.get_double(sub, "Alpha pre"),
        1e-3 * prm.get_double(sub, "Alpha mid"),
        a);
    return std::make_unique<ArosticaActiveStress>(prm.get_double(sub,
                                                                 "Sigma 0"),
                                                  a);
  }
} // namespace systole
