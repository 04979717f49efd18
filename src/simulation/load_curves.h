#pragma once

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <string>
#include <vector>

namespace systole
{
  /// A scalar load of a time integration as a function of time (the
  /// endocardial pressure, the active stress of Problem = elastodynamics).
  /// Times in ms.
  class LoadCurve
  {
  public:
    virtual ~LoadCurve() = default;

    /// The value at @p time [ms], not before the last accept()ed time (a
    /// retried step asks again from there). Does not change the curve.
    virtual double
    value(const double time) const = 0;

    /// Commit the curve's state at @p time (>= the last accepted time): an
    /// ODE curve integrates from there on.
    virtual void
    accept(const double time);

    /// What a checkpoint keeps of the curve (nothing for a function of
    /// time; the accepted time and value of an ODE curve).
    virtual std::vector<double>
    state() const;

    /// Restore what state() returned; throws on a state of another size.
    virtual void
    set_state(const std::vector<double> &state);
  };

  /// The activation of the benchmark of Aróstica et al. 2025 (CMAME
  /// 435:117485): a(t) = a_max f(t) + a_min (1 - f(t)), f(t) = S+(t -
  /// t_sys) S-(t - t_dias), S±(d) = (1 ± tanh(d / gamma)) / 2.
  struct ArosticaActivation
  {
    double a_max  = 5e-3;  ///< [1/ms]
    double a_min  = -3e-2; ///< [1/ms]
    double t_sys  = 160;   ///< [ms]
    double t_dias = 484;   ///< [ms]
    double gamma  = 5;     ///< switch width [ms]

    /// a(t) [1/ms].
    double
    operator()(const double t) const;
    /// S-(t - t_dias) [-].
    double
    relaxed(const double t) const;
  };

  /// dy/dt = rhs(t, y) for the two benchmark loads; y(0) = 0, integrated by
  /// the classical Runge-Kutta method with steps of at most 0.01 ms (the
  /// switches are 5 ms wide, so the error is far below the benchmark's
  /// digits; tested against SciPy's solve_ivp).
  class ScalarOdeCurve : public LoadCurve
  {
  public:
    double
    value(const double time) const override;

    void
    accept(const double time) override;

    std::vector<double>
    state() const override;

    void
    set_state(const std::vector<double> &state) override;

    /// Right-hand side [unit/ms].
    virtual double
    rhs(const double t, const double y) const = 0;

    /// Integrate from (@p t0, @p y0) to @p t1 >= t0.
    double
    integrate(const double t0, const double y0, const double t1) const;

    /// Largest Runge-Kutta step [ms].
    static constexpr double max_step = 0.01;

  private:
    double accepted_time  = 0.0;
    double accepted_value = 0.0;
  };

  /// The active stress of Aróstica et al. 2025: dtau/dt = -|a(t)| tau +
  /// sigma_0 max(a(t), 0) [kPa].
  class ArosticaActiveStress : public ScalarOdeCurve
  {
  public:
    ArosticaActiveStress(const double              sigma_0,
                         const ArosticaActivation &activation);
    double
    rhs(const double t, const double tau) const override;

  private:
    double             sigma_0;
    ArosticaActivation activation;
  };

  /// The endocardial pressure of Aróstica et al. 2025: dp/dt = -|b(t)| p +
  /// sigma_mid max(b, 0) + sigma_pre max(g_pre, 0), b = a(t) + alpha_pre
  /// g_pre + alpha_mid, g_pre = S-(t - t_dias) [kPa].
  class ArosticaPressure : public ScalarOdeCurve
  {
  public:
    ArosticaPressure(const double              sigma_mid,
                     const double              sigma_pre,
                     const double              alpha_pre,
                     const double              alpha_mid,
                     const ArosticaActivation &activation);
    double
    rhs(const double t, const double p) const override;

  private:
    double             sigma_mid, sigma_pre, alpha_pre, alpha_mid;
    ArosticaActivation activation;
  };

  /// The entries of one load of subsection Elastodynamics: "<Name> model"
  /// (function or Arostica), "<Name> function" and subsection "Arostica
  /// <name>".
  struct LoadCurveParameters
  {
    /// Declares, in the current subsection, the entries of the load
    /// @p name ("Pressure" or "Active stress") in @p unit.
    static void
    declare(dealii::ParameterHandler &prm,
            const std::string        &name,
            const std::string        &unit);

    /// The curve the entries describe (in the current subsection); throws
    /// naming the entry when an expression does not parse.
    static std::unique_ptr<LoadCurve>
    create(const dealii::ParameterHandler &prm, const std::string &name);
  };
} // namespace systole
