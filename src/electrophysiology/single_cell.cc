#include "electrophysiology/single_cell.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/petsc_vector.h>

#include "base/parameter_table.h"
#include "electrophysiology/arkode_adapter.h"
#include "electrophysiology/time_steps.h"

#include <algorithm>
#include <cmath>

namespace systole::Electrophysiology
{
  namespace
  {
    /// The entries of subsection "Cell": one table for declare() and
    /// parse().
    const std::vector<RealEntry<SingleCell::Pacing>> &
    pacing_entries()
    {
      using dealii::Patterns::Double;
      using P                                      = SingleCell::Pacing;
      static const std::vector<RealEntry<P>> table = {
        {"Stimulus start",
         &P::start,
         Double(0.0),
         "Problem = cell: onset of the first stimulus; beat k is [k P, (k + "
         "1) P) with its stimulus at start + k P (P the Pacing cycle length). "
         "Units: ms. Source: the ten Tusscher-Panfilov 2006 .ode file, 10 "
         "ms."},
        {"Stimulus duration",
         &P::duration,
         Double(0.0),
         "Problem = cell: duration of each stimulus. Units: ms. Source: the "
         "ten Tusscher-Panfilov 2006 .ode file, 1 ms."},
        {"Stimulus amplitude",
         &P::amplitude,
         Double(0.0),
         "Problem = cell: depolarising stimulus current per membrane "
         "capacitance, dv/dt = -I_ion + amplitude (divided by the model's mV "
         "per unit of potential). Units: µA/µF (= pA/pF = mV/ms). Source: the "
         "ten Tusscher-Panfilov 2006 .ode file, 52 pA/pF (written there as "
         "the inward current -52)."},
        {"Pacing cycle length",
         &P::period,
         Double(0.0),
         "Problem = cell: the stimulus repeats with this period (the beat); "
         "0: one stimulus and one beat up to Time / End time. Units: ms. "
         "Default: 1 Hz."},
        {"Fibre stretch",
         &P::stretch,
         Double(0.5, 1.5),
         "Problem = cell with a calcium-driven Active tension / Model "
         "(Land): the fixed fibre stretch lambda of the isometric cell (its "
         "rate is 0). Units: -."}};
      return table;
    }
  } // namespace


  void
  SingleCell::Pacing::declare(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Cell");
    declare_entries(prm, pacing_entries());
    prm.leave_subsection();
  }


  SingleCell::Pacing
  SingleCell::Pacing::parse(const dealii::ParameterHandler &prm)
  {
    Pacing p;
    parse_entries(prm, {"Cell"}, pacing_entries(), p);
    AssertThrow(p.duration > 0,
                dealii::ExcMessage("Cell / Stimulus duration must be > 0."));
    AssertThrow(p.period == 0 || p.start + p.duration < p.period,
                dealii::ExcMessage(
                  "Cell / Stimulus start + Stimulus duration must be shorter "
                  "than the Pacing cycle length (the stimulus lies inside "
                  "its beat)."));
    return p;
  }


  struct SingleCell::Impl
  {
    Impl(const IonicModel &model,
         const Settings   &settings,
         const Pacing     &pacing,
         const double      t0);

    const IonicModel &model;
    const Settings    settings;
    const Pacing      pacing;
    Stimulus          stimulus; ///< the pacing as a Stimulus (no region)
    unsigned int      n_components;
    double            t;
    double            stimulus_dv_dt = 0; ///< during the current step
    /// The first step starts with a Rush-Larsen half step of the gates (the
    /// opening half of Strang's splitting, as Monodomain does).
    bool                            gate_half_step_pending = true;
    LA::MPI::Vector                 y;
    std::vector<double>             states;
    std::unique_ptr<ImexIntegrator> integrator;
  };


  SingleCell::Impl::Impl(const IonicModel &model,
                         const Settings   &settings,
                         const Pacing     &pacing,
                         const double      t0)
    : model(model)
    , settings(settings)
    , pacing(pacing)
    , n_components(1 + model.n_states())
    , t(t0)
    , y(MPI_COMM_SELF, n_components, n_components)
    , states(model.n_states())
  {
    stimulus.name      = "pacing";
    stimulus.start     = pacing.start;
    stimulus.duration  = pacing.duration;
    stimulus.amplitude = pacing.amplitude;
    AssertThrow(settings.time_step > 0,
                dealii::ExcMessage("SingleCell: the time step must be > 0."));

    std::vector<double> initial(n_components);
    initial[0] = model.resting_potential();
    model.resting_state(initial.data() + 1);
    for (unsigned int i = 0; i < n_components; ++i)
      y[i] = initial[i];
    y.compress(dealii::VectorOperation::insert);
    std::copy(initial.begin() + 1, initial.end(), states.begin());

    const ImexIntegrator::Settings s = ImexIntegrator::Settings::of(settings);
    ImexIntegrator::Callbacks      callbacks;
    // The reads and writes go through PETSc's local arrays (one rank owns
    // all entries): dv/dt = -I_ion + stimulus, ds/dt of the non-gates.
    callbacks.explicit_rhs =
      [this](const double, const LA::MPI::Vector &z, LA::MPI::Vector &f) {
        const double *zi = nullptr;
        double       *fi = nullptr;
        VecGetArrayRead(static_cast<const Vec &>(z), &zi);
        VecGetArray(static_cast<const Vec &>(f), &fi);
        // The batched kernel, as the monodomain's (one point).
        this->model.rhs_batch(1, n_components, zi, fi);
        fi[0] += stimulus_dv_dt;
        VecRestoreArray(static_cast<const Vec &>(f), &fi);
        VecRestoreArrayRead(static_cast<const Vec &>(z), &zi);
      };
    // No implicit part: the explicit table of the ARK method alone.
    if (model.n_gates() > 0)
      callbacks.after_step =
        [this](const double, const double h, LA::MPI::Vector &z) {
          double *zi = nullptr;
          VecGetArray(static_cast<const Vec &>(z), &zi);
          this->model.advance_gates_batch(h, 1, n_components, zi);
          VecRestoreArray(static_cast<const Vec &>(z), &zi);
        };
    integrator =
      std::make_unique<ImexIntegrator>(s, callbacks, t0, MPI_COMM_SELF);
  }


  SingleCell::SingleCell(const IonicModel &model,
                         const Settings   &settings,
                         const Pacing     &pacing,
                         const double      t0)
    : impl(std::make_unique<Impl>(model, settings, pacing, t0))
  {}

  SingleCell::~SingleCell() = default;


  void
  SingleCell::advance(const double t_end, const Observer &observer)
  {
    Impl &m = *impl;
    AssertThrow(t_end > m.t,
                dealii::ExcMessage("SingleCell::advance: t_end must lie after "
                                   "the current time."));
    // Equal steps of at most the time step between the stimulus switching
    // times (as Monodomain::advance): the stimulus is on or off for a whole
    // step.
    std::vector<double> breakpoints =
      switching_times({m.stimulus}, m.pacing.period, m.t, t_end);
    breakpoints.push_back(t_end);
    const double scale = 1 / m.model.potential_scale_mV();
    const auto   step  = [&](const double t_next) {
      m.stimulus_dv_dt =
        m.stimulus.active(0.5 * (m.t + t_next), m.pacing.period)
             ? m.pacing.amplitude * scale
             : 0.0;
      if (m.gate_half_step_pending && m.model.n_gates() > 0)
        {
          // Before ARKode's first step (it reads the state then).
          double *zi = nullptr;
          VecGetArray(static_cast<const Vec &>(m.y), &zi);
          m.model.advance_gates_batch(0.5 * (t_next - m.t),
                                      1,
                                      m.n_components,
                                      zi);
          VecRestoreArray(static_cast<const Vec &>(m.y), &zi);
        }
      m.gate_half_step_pending = false;
      m.integrator->evolve(m.y, t_next);
      m.t = t_next;
      if (observer)
        {
          const double *zi = nullptr;
          VecGetArrayRead(static_cast<const Vec &>(m.y), &zi);
          observer(m.t, zi[0], zi + 1);
          VecRestoreArrayRead(static_cast<const Vec &>(m.y), &zi);
        }
    };
    for_each_step(m.t, breakpoints, m.settings.time_step, step);
    const double *zi = nullptr;
    VecGetArrayRead(static_cast<const Vec &>(m.y), &zi);
    std::copy(zi + 1, zi + m.n_components, m.states.begin());
    VecRestoreArrayRead(static_cast<const Vec &>(m.y), &zi);
  }


  double
  SingleCell::time() const
  {
    return impl->t;
  }

  double
  SingleCell::potential() const
  {
    return impl->y[0];
  }

  const std::vector<double> &
  SingleCell::state() const
  {
    return impl->states;
  }

  unsigned long
  SingleCell::n_steps() const
  {
    return impl->integrator->n_steps();
  }
} // namespace systole::Electrophysiology
