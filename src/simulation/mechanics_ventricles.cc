#include "simulation/mechanics_ventricles.h"

#include <deal.II/base/timer.h>

#include "base/logger.h"
#include "materials/tension_model.h"
#include "mechanics/problem.h"
#include "simulation/electrical_activation.h"
#include "simulation/timer_section.h"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <limits>

namespace systole
{
  MechanicsVentricles::MechanicsVentricles(
    Mechanics::Problem              &problem,
    const Materials::TensionModel   &tension_model,
    std::vector<std::vector<double>> activation_times,
    ElectricalActivation            *ep,
    const double                     contraction_onset,
    const bool                       inertia,
    Logger                          &logger)
    : problem(problem)
    , tension_model(tension_model)
    , calcium_driven(tension_model.drive() == Materials::TensionDrive::calcium)
    , activation_times(std::move(activation_times))
    , ep(ep)
    , contraction_onset(contraction_onset)
    , inertia(inertia)
    , logger(logger)
  {
    if (calcium_driven)
      {
        AssertThrow(ep != nullptr,
                    dealii::ExcMessage(
                      "A calcium-driven tension model needs the "
                      "electrophysiology of the heartbeat."));
        ep->keep_calcium();
        problem.set_tension_model(&tension_model);
      }
    problem.save();
  }


  std::vector<double>
  MechanicsVentricles::breakpoints_in_beat() const
  {
    return {contraction_onset};
  }


  void
  MechanicsVentricles::set_time(const double t)
  {
    const auto timed = timer_section(timer, "Heartbeat / EP and tension");
    time             = t;
    problem.set_support_time(t);
    // With inertia every solve after the first accepted step is one
    // generalized-alpha step from the accepted state (redone steps start
    // there again).
    if (dynamics_started)
      {
        AssertThrow(t > accepted_time,
                    dealii::ExcMessage(
                      "Problem = heartbeat with Mechanics / Inertia: a "
                      "step must end after the accepted time."));
        problem.set_time_step(t - accepted_time);
      }
    if (ep != nullptr)
      {
        const auto start = std::chrono::steady_clock::now();
        ep->advance_to(t);
        ep->activation_times(t, activation_times);
        if (calcium_driven)
          ep->calcium(t, calcium);
        ep_seconds += std::chrono::duration<double>(
                        std::chrono::steady_clock::now() - start)
                        .count();
      }
    if (calcium_driven)
      {
        // The stepper only steps forward from the accepted time.
        problem.set_calcium(calcium);
        problem.set_tension_step(t, t - accepted_time);
        return;
      }
    set_activation_driven_tension();
  }


  void
  MechanicsVentricles::set_activation_driven_tension()
  {
    // The model has no state and no stretch dependence (it is driven by
    // the activation time alone; run_heartbeat_problem checks).
    Materials::TensionInput  in;
    Materials::TensionOutput out;
    in.time = time;
    tension.resize(activation_times.size());
    for (unsigned int c = 0; c < activation_times.size(); ++c)
      {
        tension[c].resize(activation_times[c].size());
        for (unsigned int q = 0; q < activation_times[c].size(); ++q)
          {
            in.activation_time = activation_times[c][q];
            tension_model.step(nullptr, in, nullptr, out);
            tension[c][q] = out.tension;
          }
      }
    problem.set_active_tension(tension);
  }


  void
  MechanicsVentricles::predict(const std::array<double, 3> &weights)
  {
    const auto timed = timer_section(timer, "Heartbeat / mechanics");
    problem.predict(weights);
  }


  unsigned int
  MechanicsVentricles::solve(const CavityVolumeTarget &target,
                             dealii::Vector<double>   &p)
  {
    const auto timed = timer_section(timer, "Heartbeat / mechanics");
    logger.detail() << "    mechanics at t = " << std::fixed
                    << std::setprecision(3) << time << " ms"
                    << std::defaultfloat << std::endl;
    const auto start  = std::chrono::steady_clock::now();
    const auto report = problem.solve_cavities(target, 0.0, p);
    solved_pressures  = p;
    linear_iterations += report.linear_iterations;
    tangent_iterations += report.iterations;
    n_last_tangent_iterations = report.iterations;
    last_predictor_error      = problem.predictor_error();
    logger.detail() << "      (the prediction missed the solution by "
                    << std::setprecision(3) << last_predictor_error
                    << " mm at most)" << std::defaultfloat << std::endl;
    mechanics_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
    return report.iterations + report.reused_iterations;
  }


  unsigned int
  MechanicsVentricles::last_tangent_iterations() const
  {
    return n_last_tangent_iterations;
  }


  double
  MechanicsVentricles::predictor_error() const
  {
    return last_predictor_error;
  }


  void
  MechanicsVentricles::accept()
  {
    const auto timed = timer_section(timer, "Heartbeat / accept");
    // The dynamic state first: its residual takes the step's tension
    // (before the tension model's state moves on). The first step is
    // quasi-static: the dynamics starts at its end with the velocity of the
    // step, consistent with the inflow (from rest, the inflow of the
    // initial state would need an infinite acceleration).
    if (dynamics_started)
      problem.accept_time_step(solved_pressures, 0.0);
    else if (inertia)
      {
        problem.start_dynamics(solved_pressures, 0.0, time - accepted_time);
        dynamics_started = true;
      }
    if (calcium_driven)
      {
        problem.accept_tension_step();
        ep->forget_calcium_before(time);
        // The accepted tension of every point (for mean_tension()).
        std::vector<std::vector<Mechanics::PointState>> states;
        problem.point_states(states);
        tension.assign(states.size(), {});
        for (unsigned int c = 0; c < states.size(); ++c)
          for (const auto &state : states[c])
            tension[c].push_back(state.active_tension);
      }
    accepted_time = time;
    problem.save();
  }


  void
  MechanicsVentricles::reject()
  {
    const auto timed = timer_section(timer, "Heartbeat / accept");
    problem.restore();
  }


  void
  MechanicsVentricles::end_diastole()
  {
    const auto timed = timer_section(timer, "Heartbeat / accept");
    problem.refer_supports_to_end_diastole(time);
  }


  double
  MechanicsVentricles::mean_tension(const MPI_Comm comm) const
  {
    double       sum = 0;
    unsigned int n   = 0;
    for (const auto &cell : tension)
      for (const double value : cell)
        {
          sum += value;
          ++n;
        }
    return dealii::Utilities::MPI::sum(sum, comm) /
           std::max(1u, dealii::Utilities::MPI::sum(n, comm));
  }


  std::vector<std::vector<double>>
  MechanicsVentricles::activation_in_beat(const double beat_start) const
  {
    auto times = activation_times;
    if (ep != nullptr)
      for (auto &cell : times)
        for (double &t : cell)
          t = t >= beat_start - 1e-9 ? t - beat_start
                                     : std::numeric_limits<double>::quiet_NaN();
    return times;
  }
} // namespace systole
