#pragma once

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "base/archive_fwd.h"
#include "circulation/model.h"
#include "circulation/model_summary.h"
#include "circulation/parameters.h"
#include "circulation/phase.h"

#include <array>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace systole
{
  /// Thrown by HeartbeatStepper::run() when a coupled step fails at the
  /// minimum step or after the most cuts. The state (mechanics, 0D model,
  /// observers) is still that of the last accepted step, which a checkpoint
  /// can save.
  struct ExcStepFailed : std::runtime_error
  {
    ExcStepFailed(const std::string &message, const unsigned int last_step)
      : std::runtime_error(message)
      , last_step(last_step)
    {}
    /// Index of the last accepted step.
    unsigned int last_step;
  };

  /// The weights w of the displacement predictor u(@p t_new) = w_0 u_0 +
  /// w_1 u_1 + w_2 u_2 from the accepted states u_i at @p times[i] (latest
  /// first, one to three of them, none before the last valve event):
  /// - three: the quadratic through them (its miss is O(h^3)), unless a
  ///   weight exceeds 16 in size (it would magnify the states' algebraic
  ///   errors; equal steps give 3, -3, 1; a step twice the last, which
  ///   was twice the one before, 7, -14, 8);
  /// - else the secant from u_0 and u_1, or u_2 if the last step is shorter
  ///   than half the new one (after an event-located sliver), extrapolated
  ///   by at most twice its base;
  /// - one: the state itself.
  std::array<double, 3>
  predictor_weights(const double t_new, const std::vector<double> &times);

  /// Where a valve indicator g changes sign between the accepted state (g0
  /// at time @p t[1]) and an attempt (g1 at @p t[2]), as the fraction of
  /// that step: the root of the quadratic through the three points if an
  /// earlier accepted state (g at @p t[0] < t[1]; NaN if there is none)
  /// is given and that root lies in the step, else the secant's g0 / (g0 -
  /// g1). An indicator that bends toward zero (the aortic valve closing as
  /// the ventricle relaxes) puts the secant's estimate too early, and each
  /// redo then lands short of the crossing.
  double
  crossing_fraction(const std::array<double, 3> &t,
                    const std::array<double, 3> &g);

  /// The volumes W(p) [mm^3] the cavities must hold at their pressures p
  /// [kPa], and dW/dp (the signature of Mechanics::Problem::VolumeTarget).
  using CavityVolumeTarget =
    std::function<void(const dealii::Vector<double> &p,
                       dealii::Vector<double>       &W,
                       dealii::FullMatrix<double>   &dW_dp)>;

  /// The 3D ventricles of a heartbeat as the stepper sees them: k cavities
  /// whose pressures are the Lagrange multipliers of volume constraints. The
  /// 3D model (MechanicsVentricles in heartbeat.cc) or, in tests, a 0D
  /// surrogate. Every call is collective over the ranks of a distributed
  /// model and called in the same order on every rank.
  class CoupledVentricles
  {
  public:
    virtual ~CoupledVentricles() = default;

    /// Bring the model to time @p t [ms]: advance the electrophysiology
    /// (it may run ahead and be asked for an earlier time after a rejected
    /// step) and set the active tension of @p t.
    virtual void
    set_time(const double t) = 0;

    /// Start the next solve from the extrapolation of the last accepted
    /// states, u = w_0 u_0 + w_1 u_1 + w_2 u_2 (u_0 the latest; the weights
    /// of predictor_weights(), 0 for the states it does not use).
    virtual void
    predict(const std::array<double, 3> &weights) = 0;

    /// Equilibrium at the time of set_time() with the cavity volumes equal
    /// to @p target (p): the pressures @p p [kPa] are the guess on entry and
    /// the solution on exit. Returns the Newton iterations. Throws
    /// ExcNewtonDidNotConverge or ExcInvertedElement when it fails (the
    /// stepper then reject()s and retries with a shorter step).
    virtual unsigned int
    solve(const CavityVolumeTarget &target, dealii::Vector<double> &p) = 0;

    /// After a converged solve(): how many of its iterations assembled and
    /// factorized a new tangent (0: not counted; then the step-size control
    /// leaves it out).
    virtual unsigned int
    last_tangent_iterations() const
    {
      return 0;
    }

    /// After a converged solve(): the largest nodal displacement [mm] by
    /// which its solution differs from its start, the predict()ion (0: not
    /// measured; then the step-size control leaves it out).
    virtual double
    predictor_error() const
    {
      return 0.0;
    }

    /// The solution of the last solve() becomes the accepted state.
    virtual void
    accept() = 0;

    /// Back to the last accepted state.
    virtual void
    reject() = 0;

    /// End-diastole: the accepted step ended the filling of the first
    /// external cavity (its inlet valve closed). Called after accept().
    virtual void
    end_diastole()
    {}

    /// Times within a beat [ms from its start] where the loads change
    /// abruptly (the onset of the active tension): steps end there and
    /// continue with Settings::initial_step, as after a valve event.
    virtual std::vector<double>
    breakpoints_in_beat() const
    {
      return {};
    }
  };

  /// The heartbeat's clock: steps the 3D ventricles and the 0D circulation
  /// together, one implicit coupled step per time step. Per step:
  /// @code
  ///   ventricles.set_time(t_new);          // electrophysiology, tension
  ///   solve_coupled(t_new);                // mechanics + BDF step of the 0D
  ///   if (valve event inside) aim at it;   // located to Settings tolerance
  ///   else if (error too large) shorten;
  ///   else accept, record, output;
  /// @endcode
  /// The coupled step: the 0D states advance by variable-step BDF2
  /// (Circulation::BdfStep) with the cavity pressures p as inputs; the 3D
  /// mechanics is solved with its cavity volumes equal to the 0D volume
  /// states at the end of the step, V(u) = W(p), the pressures the Lagrange
  /// multipliers. Newton on the bordered system uses dW/dp, so the coupled
  /// step converges like one mechanics solve (Mechanics::Problem::
  /// solve_cavities: a k x k Schur complement beside the mechanics block
  /// solve).
  ///
  /// Steps: adaptive by the BDF local error of the 0D states, the
  /// curvature of the cavity pressures (small in the upstroke and around
  /// valve events, up to Settings::max_step in diastasis) and the error of
  /// the displacement predictor (Settings::displacement_tolerance: where the
  /// motion accelerates, as at the contraction onset, the next step is one
  /// whose secant predictor is expected to miss by at most that, so Newton
  /// starts in its quadratic range), the Newton iterations with a new
  /// tangent of the last solve (Settings::newton_iterations_target: a solve
  /// that needed N more shortens the next step to sqrt(target / N) of it),
  /// ending at every
  /// beat's end, at the ventricles' breakpoints (the contraction onset) and
  /// at every valve event (located: the step that crosses a
  /// sign change of a valve's indicator is redone to end within
  /// Settings::event_time_tolerance after the crossing), after which the BDF
  /// restarts with order 1 and Settings::initial_step. A failed solve
  /// (Newton, an inverted element) halves the step, and the steps after it
  /// stay below 3/4 of the failed one, growing by 10 % per accepted step.
  ///
  /// Phases: per cavity, from its own valves (Circulation::CavityPhases).
  class HeartbeatStepper
  {
  public:
    /// The step control of subsection Circulation and the shortest step.
    struct Settings : Circulation::StepControl
    {
      Settings() = default;
      explicit Settings(const Circulation::StepControl &steps)
        : StepControl(steps)
      {}

      double min_step = 1e-3; ///< [ms]
    };

    /// One accepted step.
    struct Step
    {
      unsigned int                           index; ///< 0: the initial state
      double                                 time;  ///< [ms]
      double                                 step_size;
      unsigned int                           beat;
      const dealii::Vector<double>          &state;     ///< 0D state y
      const dealii::Vector<double>          &pressures; ///< every cavity [kPa]
      const std::vector<Circulation::Phase> &phases;
      unsigned int newton_iterations; ///< mechanics, this step's attempts
      unsigned int mechanics_solves;  ///< this step's attempts
      unsigned int rejected;          ///< attempts redone (error, events)
      unsigned int order;             ///< BDF order of the step
    };

    /// Receives the results as they are computed.
    class Observer
    {
    public:
      virtual ~Observer() = default;
      /// The initial state, then every accepted step (a step ending at a
      /// valve event comes before its on_event()).
      virtual void
      on_step(const Step &step) = 0;
      /// A valve of the model opened or closed at the end of the last step.
      virtual void
      on_event(const unsigned int valve, const bool opens, const Step &step)
      {
        (void)valve;
        (void)opens;
        (void)step;
      }
      /// The coupled solve from @p t_from to @p t_to [ms] failed (Newton did
      /// not converge or an element inverted; @p why: the message in one
      /// line); the step is halved and redone.
      virtual void
      on_failure(const double t_from, const double t_to, const std::string &why)
      {
        (void)t_from;
        (void)t_to;
        (void)why;
      }
      /// A beat ended; @p summary from Circulation::ModelBeatRecorder.
      virtual void
      on_beat(const unsigned int                             beat,
              const std::vector<Circulation::SummaryColumn> &summary)
      {
        (void)beat;
        (void)summary;
      }
      /// After every accepted step with its events and, at a beat's end, its
      /// on_beat(), unless the run ends there: the state of the stepper and
      /// of the ventricles is complete here (checkpoints are written here).
      /// Collective.
      virtual void
      on_step_complete(const unsigned int step_index)
      {
        (void)step_index;
      }
      /// Asked after every accepted step; true ends run(). Collective.
      virtual bool
      stop_requested()
      {
        return false;
      }
    };

    struct Statistics
    {
      unsigned int  n_beats             = 0;
      bool          periodic            = false;
      bool          interrupted         = false;
      unsigned long n_steps             = 0; ///< accepted
      unsigned long n_solves            = 0; ///< coupled solves, all attempts
      unsigned long n_newton_iterations = 0;
      unsigned long n_error_rejections  = 0;
      unsigned long n_event_rejections  = 0;
      unsigned long n_failures          = 0; ///< failed solves, step cut
      unsigned long n_events            = 0;
      double        end_time            = 0;
    };

    /// @p model: its external cavities are the ventricles' cavities, in
    /// order; @p y0 its initial state (the external cavities' volumes those
    /// of the 3D model at @p p0), @p p0 the initial pressures of every
    /// cavity [kPa]. The references must outlive this object.
    HeartbeatStepper(const Circulation::Model     &model,
                     CoupledVentricles            &ventricles,
                     const Settings               &settings,
                     const dealii::Vector<double> &y0,
                     const dealii::Vector<double> &p0);
    ~HeartbeatStepper();

    /// Beats from t = 0 until periodic (the summary's periodicity below the
    /// tolerance, from the second beat on: the largest relative change of a
    /// cavity's EDV from the last beat and, with both ventricles of a closed
    /// loop external, the relative difference of their stroke volumes; see
    /// Circulation::ModelBeatRecorder), n_max_beats, or the observer's
    /// stop. Call once; after
    /// load(), run() continues from the loaded state (without reporting it
    /// again).
    Statistics
    run(Observer &observer);

    /// Write everything the next steps depend on, between two steps (in
    /// Observer::on_step_complete()): the BDF history, the valve states and
    /// phases, the beat recorder, the step size and its cap, the event
    /// bracket, the counters and statistics.
    void
    save(boost::archive::text_oarchive &archive) const;

    /// Read what save() wrote (of a stepper built with the same model and
    /// settings); run() then continues from there.
    void
    load(boost::archive::text_iarchive &archive);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole
