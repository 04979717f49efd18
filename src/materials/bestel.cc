#include "materials/bestel.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <cmath>

namespace systole::Materials
{
  void
  Bestel::Parameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Double;
    const Parameters d;
    prm.enter_subsection("Active tension");
    prm.declare_entry("Contractility",
                      std::to_string(d.contractility),
                      Double(0.0),
                      "sigma_0 of the Bestel law: the tension the fibres "
                      "approach during a long contraction. Units: kPa.");
    prm.declare_entry("Activation rate",
                      std::to_string(d.a_max * 1000.0),
                      Double(0.0),
                      "a_max: rate of the contraction. Units: 1/s.");
    prm.declare_entry("Relaxation rate",
                      std::to_string(-d.a_min * 1000.0),
                      Double(0.0),
                      "-a_min: rate of the relaxation (positive). Units: 1/s.");
    prm.declare_entry("Systole start",
                      std::to_string(d.t_sys),
                      Double(0.0),
                      "t_sys: start of the contraction after the local "
                      "activation. Units: ms.");
    prm.declare_entry("Diastole start",
                      std::to_string(d.t_dias),
                      Double(0.0),
                      "t_dias: start of the relaxation after the local "
                      "activation (> Systole start). Units: ms.");
    prm.declare_entry("Transition width",
                      std::to_string(d.gamma),
                      Double(1e-3),
                      "gamma: width of the tanh switches. Units: ms.");
    prm.declare_entry("Activation map",
                      d.activation_map,
                      dealii::Patterns::Selection(
                        "uniform|apex-to-base|electrophysiology"),
                      "The activation time of each point, which starts its "
                      "contraction in every beat: electrophysiology: the "
                      "latest upstroke of the monodomain model (subsection "
                      "Electrophysiology; the stimulus triggers the beat); "
                      "or prescribed: uniform: 0 everywhere; apex-to-base: "
                      "Activation delay times the height above the apex, "
                      "normalized to 1 at the base. (Bestel only: a "
                      "calcium-driven Model follows the electrophysiology.) "
                      "Units: -.");
    prm.declare_entry("Activation delay",
                      std::to_string(d.activation_delay),
                      Double(0.0),
                      "Activation time at the base for Activation map = "
                      "apex-to-base (the apex activates at 0). Units: ms.");
    prm.leave_subsection();
  }

  Bestel::Parameters
  Bestel::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path = {"Active tension"};
    Parameters                     p;
    p.contractility    = prm.get_double(path, "Contractility");
    p.a_max            = prm.get_double(path, "Activation rate") / 1000.0;
    p.a_min            = -prm.get_double(path, "Relaxation rate") / 1000.0;
    p.t_sys            = prm.get_double(path, "Systole start");
    p.t_dias           = prm.get_double(path, "Diastole start");
    p.gamma            = prm.get_double(path, "Transition width");
    p.activation_map   = prm.get(path, "Activation map");
    p.activation_delay = prm.get_double(path, "Activation delay");
    AssertThrow(p.t_dias > p.t_sys,
                dealii::ExcMessage("Active tension / Diastole start (" +
                                   dealii::Utilities::to_string(p.t_dias) +
                                   " ms) must come after Systole start (" +
                                   dealii::Utilities::to_string(p.t_sys) +
                                   " ms)."));
    return p;
  }

  double
  Bestel::activation(const double t) const
  {
    const double s_plus =
      0.5 * (1.0 + std::tanh((t - params.t_sys) / params.gamma));
    const double s_minus =
      0.5 * (1.0 - std::tanh((t - params.t_dias) / params.gamma));
    const double f = s_plus * s_minus;
    return params.a_max * f + params.a_min * (1.0 - f);
  }

  Bestel::Bestel(const Parameters &params, const double period)
    : params(params)
    , period(period)
    , table_step(0.01)
  {
    AssertThrow(period > params.t_dias,
                dealii::ExcMessage(
                  "The beat period (" + dealii::Utilities::to_string(period) +
                  " ms) must be longer than Active tension / Diastole start (" +
                  dealii::Utilities::to_string(params.t_dias) + " ms)."));
    // a(t) periodic: t mod period.
    const auto rhs = [&](const double t, const double tau) {
      const double a = activation(std::fmod(t, period));
      return -std::abs(a) * tau + params.contractility * std::max(a, 0.0);
    };
    const unsigned int n =
      static_cast<unsigned int>(std::ceil(period / table_step));
    table_step = period / n;
    table.resize(n + 1);
    double       tau = 0, t = 0;
    const double h = table_step;
    for (unsigned int pass = 0; pass < 2; ++pass)
      for (unsigned int i = 0; i <= n; ++i)
        {
          if (pass == 1)
            table[i] = tau;
          if (i == n)
            break;
          const double k1 = rhs(t, tau);
          const double k2 = rhs(t + h / 2, tau + h / 2 * k1);
          const double k3 = rhs(t + h / 2, tau + h / 2 * k2);
          const double k4 = rhs(t + h, tau + h * k3);
          tau += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
          t += h;
        }
  }

  double
  Bestel::tension(const double time, const double activation_time) const
  {
    const double since = time - activation_time;
    if (since < 0.0)
      return 0.0;
    const double local = std::fmod(since, period);
    const double x     = local / table_step;
    const auto   i =
      std::min<std::size_t>(static_cast<std::size_t>(x), table.size() - 2);
    const double w = x - i;
    return (1.0 - w) * table[i] + w * table[i + 1];
  }

  double
  Bestel::onset() const
  {
    // f = a_min / (a_min - a_max) on the rising switch (t_dias far away).
    const double f = params.a_min / (params.a_min - params.a_max);
    return params.t_sys + params.gamma * std::atanh(2.0 * f - 1.0);
  }

  const Bestel::Parameters &
  Bestel::parameters() const
  {
    return params;
  }
} // namespace systole::Materials
