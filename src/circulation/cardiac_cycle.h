#pragma once

#include "circulation/beat_summary.h"
#include "circulation/cycle_records.h"
#include "circulation/parameters.h"
#include "circulation/ventricle.h"

#include <memory>

namespace systole::Circulation
{
  /// The closed-loop cardiac cycle of one ventricle: a volume-driven
  /// Ventricle, the mitral valve fed by a constant atrial pressure, and the
  /// aortic valve into a Windkessel. The ODE system, integrated by SUNDIALS
  /// ARKode (explicit adaptive Bogacki-Shampine 3(2), ERKStep), has the
  /// state y = (V, p_ar, int Q_ao dt, int Q_mv dt):
  /// @f[ \frac{dV}{dt} = Q_{mv} - Q_{ao},\quad
  ///     C\frac{dp_{ar}}{dt} = Q_{ao} - \frac{p_{ar} - p_{ven}}{R_p},\quad
  ///     Q_{mv} = \frac{p_{at} - p}{R_{mv}}\ \text{(filling)},\quad
  ///     Q_{ao} = \frac{p - p_{ar}}{R_s}\ \text{(ejection)}, @f]
  /// with p = P(t, V) from the ventricle at every right-hand-side
  /// evaluation. In the isovolumetric phases both flows are zero, so V stays
  /// exactly constant.
  ///
  /// Valve events are roots located by ARKode (each one ends a step; the
  /// integrator restarts there with the new phase):
  /// - filling -> isovolumetric contraction: p - p_at crosses 0 upwards;
  ///   armed from the contraction onset of the beat until the mitral valve
  ///   has closed once (no chattering in diastasis);
  /// - isovolumetric contraction -> ejection: p - p_ar crosses 0 upwards;
  /// - isovolumetric contraction -> filling: p - p_at crosses 0 downwards
  ///   (the aortic valve did not open this beat);
  /// - ejection -> isovolumetric relaxation: p - p_ar, so Q_ao, crosses 0
  ///   downwards;
  /// - isovolumetric relaxation -> filling: p - p_at crosses 0 downwards.
  ///
  /// If p >= p_at when the mitral closure is armed, the valve closes at that
  /// instant; if p > p_ar on entering the isovolumetric contraction (or
  /// p < p_at on entering the relaxation) the next event follows at once.
  ///
  /// Beat k covers [k T, (k+1) T); steps end at beat boundaries and at the
  /// contraction onset. Every rank of an MPI run integrates the same system
  /// redundantly: the sequence of Ventricle calls is the same everywhere.
  ///
  /// Cost: each right-hand side evaluation calls Ventricle::pressure() unless
  /// the same (t, V) was evaluated recently (a small cache, so the root
  /// functions at step ends and the restarts after events cost nothing):
  /// 3 calls per accepted step (the method is FSAL), plus about 10 per valve
  /// event for ARKode's root finder, which iterates to round-off (SUNDIALS
  /// 6.4 has no option for a looser event-time tolerance). The elastance
  /// surrogate with the default parameters takes about 95 steps and 325
  /// calls per beat, most steps at the maximum step size.
  ///
  /// Failures of the ventricle: ERKStep of SUNDIALS 6.4 cannot recover from a
  /// recoverable right-hand-side failure (a positive return gives
  /// ARK_UNREC_RHSFUNC_ERR), so CardiacCycle cuts the step itself: when
  /// pressure() throws ExcNewtonDidNotConverge or ExcInvertedElement, the
  /// integrator restarts from the last accepted state with the maximum step
  /// halved (up to Parameters::max_step_cuts times in a row; the full
  /// maximum step returns after 5 accepted steps). Beyond that, and for any
  /// other exception, run() throws an ExcMessage naming the time, with the
  /// ventricle's message; other exceptions propagate unchanged.
  class CardiacCycle
  {
  public:
    /// Receives the results as they are computed. All callbacks default to
    /// doing nothing.
    class Observer
    {
    public:
      virtual ~Observer() = default;
      /// Once for the initial state (step_size 0) and once per accepted
      /// step, in order; the record at a valve event comes before the
      /// transition.
      virtual void
      on_step(const StepRecord &record)
      {
        (void)record;
      }
      /// Once per valve event.
      virtual void
      on_transition(const Transition &transition)
      {
        (void)transition;
      }
      /// At the end of every beat.
      virtual void
      on_beat(const BeatSummary &summary)
      {
        (void)summary;
      }
      /// Asked after every accepted step: true ends run() there (the beat
      /// is then not summarised). Collective for a 3D model (use
      /// systole::interrupted(comm)).
      virtual bool
      stop_requested()
      {
        return false;
      }
    };

    /// What run() did.
    struct Statistics
    {
      unsigned int  n_beats     = 0;     ///< completed beats
      bool          periodic    = false; ///< stopped by the periodicity test
      bool          interrupted = false; ///< stopped by stop_requested()
      unsigned long n_steps     = 0;     ///< accepted steps
      unsigned long n_error_test_failures = 0;
      unsigned long n_rhs_evaluations     = 0;
      unsigned long n_ventricle_calls     = 0; ///< Ventricle::pressure() calls
      unsigned int  n_transitions         = 0;
      unsigned int  n_step_cuts           = 0; ///< after ventricle failures
      double        end_time              = 0; ///< [ms]
    };

    /// @param[in] parameters validated settings (internal units)
    /// @param[in] ventricle referenced, must outlive this object
    /// @param[in] initial_volume cavity volume at t = 0 [mm^3] (the
    ///   unloaded ventricle); the cycle starts in filling
    /// @param[in] contraction_onset time within each beat [ms] from which the
    ///   mitral valve may close (0 <= onset < period)
    CardiacCycle(const Parameters &parameters,
                 Ventricle        &ventricle,
                 const double      initial_volume,
                 const double      contraction_onset);

    ~CardiacCycle();

    CardiacCycle(const CardiacCycle &) = delete;
    CardiacCycle &
    operator=(const CardiacCycle &) = delete;

    /// Integrates beat after beat from t = 0 until the beats are periodic
    /// (Parameters::periodicity_tolerance, from the second beat on), the
    /// maximum number of beats is reached, or the observer asks to stop.
    /// Call once.
    Statistics
    run(Observer &observer);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Circulation
