#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/vector.h>

#include "simulation/heartbeat_stepper.h"

#include <vector>

namespace systole
{
  class ElectricalActivation;
  class Logger;
  namespace Materials
  {
    class TensionModel;
  }
  namespace Mechanics
  {
    class Problem;
  }

  /// The 3D ventricle(s) as the heartbeat stepper sees them: the mechanics
  /// with its cavity volumes constrained (Mechanics::Problem::
  /// solve_cavities), under the active tension of the time, of one of two
  /// kinds of tension model (Materials::TensionModel):
  /// - driven by activation times (Bestel): the tension of each quadrature
  ///   point starts at its activation time, prescribed or the latest
  ///   upstroke at or before t of the electrophysiology (@p ep not null);
  /// - driven by calcium (Land): coupled two-way with the mechanics
  ///   (Mechanics::Problem::set_tension_model), its states stepped from the
  ///   accepted time to t with the calcium of the electrophysiology at t
  ///   (linear in time between EP's samples) and the fibre stretch of each
  ///   Newton iterate; accept() commits them.
  class MechanicsVentricles : public CoupledVentricles
  {
  public:
    /// @p contraction_onset: the earliest time in a beat at which a point's
    /// tension starts to rise [ms].
    MechanicsVentricles(Mechanics::Problem              &problem,
                        const Materials::TensionModel   &tension_model,
                        std::vector<std::vector<double>> activation_times,
                        ElectricalActivation            *ep,
                        const double                     contraction_onset,
                        const bool                       inertia,
                        Logger                          &logger);

    std::vector<double>
    breakpoints_in_beat() const override;

    void
    set_time(const double t) override;

    void
    predict(const std::array<double, 3> &weights) override;

    unsigned int
    solve(const CavityVolumeTarget &target, dealii::Vector<double> &p) override;

    unsigned int
    last_tangent_iterations() const override;

    double
    predictor_error() const override;

    void
    accept() override;

    void
    reject() override;

    /// The supports referred to end-diastole take the accepted displacement
    /// (Mechanics::Problem::refer_supports_to_end_diastole()).
    void
    end_diastole() override;

    /// The accepted time (checkpoints).
    template <class Archive>
    void
    serialize(Archive &archive)
    {
      archive &accepted_time &tension &dynamics_started;
    }

    /// Mean of the active tension over the quadrature points [kPa] (of the
    /// last set_time(); collective).
    double
    mean_tension(const MPI_Comm comm) const;

    /// The activation time of every quadrature point in the beat that
    /// started at @p beat_start [ms] (NaN: not activated in it), as of the
    /// last set_time().
    std::vector<std::vector<double>>
    activation_in_beat(const double beat_start) const;

    /// Wall times [s]: the mechanics solves, the electrophysiology
    /// (advancing, reading).
    double mechanics_seconds = 0, ep_seconds = 0;
    /// The heartbeat's sections (none: not timed).
    dealii::TimerOutput *timer = nullptr;
    /// Krylov iterations of the mechanics solves (0 with the direct
    /// solver).
    unsigned long linear_iterations = 0;
    /// Of the Newton iterations solve() returns in this process (as the
    /// wall times, not kept by a checkpoint), those with a new tangent (and
    /// factorization); the others are chord iterations on a held one.
    unsigned long tangent_iterations = 0;

  private:
    /// Of the last solve(): its iterations with a new tangent, and its
    /// predictor's miss [mm] (computed once: a reduction over the ranks).
    unsigned int n_last_tangent_iterations = 0;
    double       last_predictor_error      = 0;

    /// The tension of a model driven by activation times alone at time.
    void
    set_activation_driven_tension();

    Mechanics::Problem              &problem;
    const Materials::TensionModel   &tension_model;
    const bool                       calcium_driven;
    std::vector<std::vector<double>> activation_times;
    ElectricalActivation            *ep;
    std::vector<std::vector<double>> tension;
    /// The calcium at the points at time [µM] (calcium-driven models).
    std::vector<std::vector<double>> calcium;
    const double                     contraction_onset;
    /// Mechanics / Inertia: every solve after the first accepted step is a
    /// generalized-alpha step.
    const bool inertia;
    bool       dynamics_started = false;
    /// The cavity pressures of the last solve [kPa] (accept_time_step()).
    dealii::Vector<double> solved_pressures;
    Logger                &logger;
    double                 time = 0, accepted_time = 0;
  };
} // namespace systole
