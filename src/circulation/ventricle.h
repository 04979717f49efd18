#pragma once

/// @file
/// The ventricle as the circulation sees it: a volume-driven pressure.

namespace systole::Circulation
{
  /// A volume-driven ventricle: given the time and the cavity volume it
  /// returns the cavity pressure, p = P(t, V). The circulation (CardiacCycle)
  /// calls it from inside the ODE right-hand side, so it must be
  /// deterministic and, for a distributed 3D model, be called identically on
  /// every rank (CardiacCycle guarantees the same sequence of calls on every
  /// rank, since every rank integrates the same 0D system).
  ///
  /// How to add one: derive from this class, implement pressure() (and
  /// accept_step() if the model has state to commit), pass an instance to
  /// CardiacCycle. The 0D surrogate ElastanceVentricle is the example.
  class Ventricle
  {
  public:
    virtual ~Ventricle() = default;

    /// Cavity pressure [kPa] at time @p t [ms] when the cavity holds
    /// @p volume [mm^3]. Collective over the ranks of a distributed model.
    /// May throw ExcNewtonDidNotConverge or ExcInvertedElement
    /// (base/errors.h): CardiacCycle then retries with a smaller time step.
    /// Any other exception ends the run (it propagates out of
    /// CardiacCycle::run()).
    ///
    /// The states at which it is called are stage points of the explicit
    /// Runge-Kutta method and, near valve events, points of the root finder;
    /// they need not be accepted states (see accept_step()).
    virtual double
    pressure(const double t, const double volume) = 0;

    /// Called once per accepted integrator step, at valve events and at the
    /// start, with the accepted state (t [ms], volume [mm^3]). pressure() has
    /// been called before with exactly these arguments (not necessarily as
    /// the latest call: after a valve event the root finder evaluates other
    /// points in between), so a model that keeps only its latest solution may
    /// have to re-solve here. A 3D model commits its state here (history
    /// variables, warm start, field output).
    virtual void
    accept_step(const double t, const double volume)
    {
      (void)t;
      (void)volume;
    }
  };
} // namespace systole::Circulation
