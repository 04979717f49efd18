// Time integration of Monodomain: the right-hand sides and stage solves that
// ImexIntegrator (ARKode) calls, sub-cycling and activation sampling.

#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include "electrophysiology/monodomain_impl.h"
#include "electrophysiology/time_steps.h"

#include <petscmat.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace systole::Electrophysiology
{
  namespace
  {
    /// Solves @p A x = b by CG with @p preconditioner from the guess @p x, in
    /// at most @p max_steps steps to the residual @p tolerance, and returns
    /// the steps. Otherwise a recoverable step failure: "<method> did not
    /// converge on <system> (residual ... after ... iterations)".
    template <class Matrix, class Preconditioner>
    unsigned int
    solve_cg(const Matrix          &A,
             LA::MPI::Vector       &x,
             const LA::MPI::Vector &b,
             const Preconditioner  &preconditioner,
             const unsigned int     max_steps,
             const double           tolerance,
             const std::string     &method,
             const std::string     &system)
    {
      dealii::SolverControl control(max_steps, tolerance, false, false);
      dealii::SolverCG<LA::MPI::Vector> cg(control);
      try
        {
          cg.solve(A, x, b, preconditioner);
        }
      catch (const dealii::SolverControl::NoConvergence &e)
        {
          AssertThrow(false,
                      ExcRecoverableStepFailure(
                        method + " did not converge on " + system +
                        " (residual " + std::to_string(e.last_residual) +
                        " after " + std::to_string(e.last_step) +
                        " iterations)"));
        }
      return control.last_step();
    }
  } // namespace


  LocalRead::LocalRead(const LA::MPI::Vector &v)
    : vec(static_cast<const Vec &>(v))
  {
    const PetscErrorCode ierr = VecGetArrayRead(vec, &values);
    AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
  }

  LocalRead::~LocalRead()
  {
    VecRestoreArrayRead(vec, &values);
  }

  LocalWrite::LocalWrite(LA::MPI::Vector &v)
    : vec(static_cast<const Vec &>(v))
  {
    const PetscErrorCode ierr = VecGetArray(vec, &values);
    AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
  }

  LocalWrite::~LocalWrite()
  {
    VecRestoreArray(vec, &values);
  }


  void
  Monodomain::Impl::initialize_state()
  {
    state.reinit(space.state_owned, comm);
    LocalWrite          y(state);
    std::vector<double> rest(space.n_components);
    rest[0] = model.resting_potential();
    model.resting_state(rest.data() + 1);
    for (unsigned int i = 0; i < space.n_owned; ++i)
      std::copy(rest.begin(), rest.end(), y.data() + i * space.n_components);
  }


  void
  Monodomain::Impl::extract_potential(std::vector<double> &v) const
  {
    v.resize(space.n_owned);
    const LocalRead y(state);
    for (unsigned int i = 0; i < space.n_owned; ++i)
      v[i] = y.data()[i * space.n_components];
  }


  void
  Monodomain::Impl::explicit_rhs(const double /*t*/,
                                 const LA::MPI::Vector &y_vector,
                                 LA::MPI::Vector       &f_vector)
  {
    const LocalRead  y(y_vector);
    const LocalWrite f(f_vector);
    // All owned nodes in one call: the model's batched kernel.
    model.rhs_batch(space.n_owned, space.n_components, y.data(), f.data());
    // On or off for the whole step (advance() ends steps at the switching
    // times), not by the stage time.
    for (unsigned int s = 0; s < params.stimuli.size(); ++s)
      if (stimulation.on[s])
        {
          const double dv_dt = params.stimuli[s].amplitude * stimulation.scale;
          for (const unsigned int i : stimulation.nodes[s])
            f.data()[i * space.n_components] += dv_dt;
        }
    // Reaction-eikonal: the nodal stimulus of this step.
    for (const auto &[i, dv_dt] : eikonal.stimulus)
      f.data()[i * space.n_components] += dv_dt;
  }


  void
  Monodomain::Impl::implicit_rhs(const LA::MPI::Vector &y_vector,
                                 LA::MPI::Vector       &f_vector)
  {
    if (!diffusion())
      {
        f_vector = 0;
        return;
      }
    {
      const LocalRead  y(y_vector);
      const LocalWrite v(matrices.v_work);
      for (unsigned int i = 0; i < space.n_owned; ++i)
        v.data()[i] = y.data()[i * space.n_components];
    }
    matrices.stiffness.vmult(matrices.Kv_work, matrices.v_work);
    // M^-1 K v, from the last one as the guess (consistent mass).
    solve_mass(matrices.Kv_work, matrices.MinvKv_work);
    const LocalRead  MinvKv(params.consistent_mass ? matrices.MinvKv_work
                                                  : matrices.Kv_work);
    const LocalWrite f(f_vector);
    for (unsigned int i = 0; i < space.n_owned; ++i)
      {
        double *fi = f.data() + i * space.n_components;
        fi[0]      = params.consistent_mass
                       ? -MinvKv.data()[i]
                       : -MinvKv.data()[i] / matrices.lumped_mass[i];
        for (unsigned int c = 1; c < space.n_components; ++c)
          fi[c] = 0;
      }
  }


  void
  Monodomain::Impl::solve_mass(const LA::MPI::Vector &b, LA::MPI::Vector &x)
  {
    // The lumped mass is divided out by the callers (x untouched).
    if (!params.consistent_mass)
      return;
    const double b_norm = b.l2_norm();
    if (b_norm == 0)
      {
        x = 0;
        return;
      }
    // M is spectrally equivalent to its diagonal, independently of h (for
    // Q1 hexahedra diag(M)^-1 M has a condition number of at most 3^3), and
    // the guess is the last solution: a few CG iterations.
    stats.mass_iterations += solve_cg(matrices.mass,
                                      x,
                                      b,
                                      *matrices.mass_jacobi,
                                      200,
                                      params.linear_tolerance * b_norm,
                                      "CG + Jacobi",
                                      "the consistent mass matrix");
    ++stats.mass_solves;
  }


  double
  Monodomain::Impl::explicit_stiffness(const LA::MPI::Vector &y_vector) const
  {
    // The explicit part is local to each node: dv/dt = -I_ion(v, s), ds/dt
    // = g(v, s). Its stiff eigenvalue is -dI_ion/dv, of the potential (the
    // states are slow, or gates advanced by Rush-Larsen): on the plateau of
    // Mitchell-Schaeffer -2.8/ms at a node that has just activated (h = 1),
    // -2/ms a few tens of ms later. A central difference of 1e-4 mV.
    const double    dv = 1e-4 / model.potential_scale_mV();
    const LocalRead y(y_vector);
    double          rho = 0;
    // The model's batched currents, a block of nodes at a time.
    constexpr unsigned int block = 256;
    double                 above[block], below[block];
    for (unsigned int start = 0; start < space.n_owned; start += block)
      {
        const unsigned int count = std::min(block, space.n_owned - start);
        const double *y0 = y.data() + std::size_t(start) * space.n_components;
        model.ionic_current_batch(count, space.n_components, y0, dv, above);
        model.ionic_current_batch(count, space.n_components, y0, -dv, below);
        for (unsigned int i = 0; i < count; ++i)
          rho = std::max(rho, (above[i] - below[i]) / (2 * dv));
      }
    return dealii::Utilities::MPI::max(rho, comm);
  }


  void
  Monodomain::Impl::prepare_stage(const double gamma)
  {
    const auto update = [&](LA::MPI::SparseMatrix &matrix, double &gamma_of) {
      PetscErrorCode ierr = MatCopy(static_cast<Mat>(matrices.stiffness),
                                    static_cast<Mat>(matrix),
                                    SAME_NONZERO_PATTERN);
      AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      ierr = MatScale(static_cast<Mat>(matrix), gamma);
      AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      if (params.consistent_mass)
        ierr = MatAXPY(static_cast<Mat>(matrix),
                       1.0,
                       static_cast<Mat>(matrices.mass),
                       SAME_NONZERO_PATTERN);
      else
        ierr =
          MatDiagonalSet(static_cast<Mat>(matrix),
                         static_cast<const Vec &>(matrices.lumped_mass_vector),
                         ADD_VALUES);
      AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      gamma_of = gamma;
    };
    if (std::abs(gamma / matrices.gamma_stage - 1) > 1e-10)
      {
        update(matrices.stage, matrices.gamma_stage);
        if (params.preconditioner == "Jacobi")
          {
            auto jacobi = std::make_unique<LA::MPI::PreconditionJacobi>();
            jacobi->initialize(matrices.stage);
            matrices.preconditioner = std::move(jacobi);
          }
      }
    if (params.preconditioner == "AMG" &&
        (!matrices.preconditioner ||
         std::abs(gamma / matrices.gamma_amg - 1) > 0.2))
      {
        // Its own copy of the matrix: the AMG hierarchy is kept while the
        // stage matrix follows small changes of gamma (PETSc would set the
        // preconditioner up again whenever its matrix changes).
        update(matrices.amg_matrix, matrices.gamma_amg);
        // BoomerAMG for a 3D, mass-dominated operator: strong threshold 0.5
        // and one level of aggressive coarsening halve the cost of a
        // V-cycle against the defaults (2 CG iterations either way).
        LA::MPI::PreconditionAMG::AdditionalData data;
        data.symmetric_operator               = true;
        data.strong_threshold                 = 0.5;
        data.aggressive_coarsening_num_levels = 1;
        auto amg = std::make_unique<LA::MPI::PreconditionAMG>();
        amg->initialize(matrices.amg_matrix, data);
        matrices.preconditioner = std::move(amg);
        ++stats.amg_setups;
      }
  }


  void
  Monodomain::Impl::solve_stage(const double           gamma,
                                const LA::MPI::Vector &b_vector,
                                LA::MPI::Vector       &x_vector)
  {
    // (I - gamma J) x = b with J = diag(-M^-1 K, 0):
    // (M + gamma K) x_v = M b_v, and x_s = b_s for the ionic states (M the
    // lumped or the consistent mass).
    if (!diffusion())
      {
        x_vector = b_vector;
        return;
      }
    prepare_stage(gamma);

    {
      const LocalRead  b(b_vector);
      const LocalWrite rhs(matrices.rhs_work);
      const LocalWrite v(matrices.v_work);
      for (unsigned int i = 0; i < space.n_owned; ++i)
        {
          v.data()[i]   = b.data()[i * space.n_components]; // initial guess
          rhs.data()[i] = matrices.lumped_mass[i] * v.data()[i];
        }
    }
    if (params.consistent_mass)
      matrices.mass.vmult(matrices.rhs_work, matrices.v_work);
    const double rhs_norm = matrices.rhs_work.l2_norm();
    if (rhs_norm > 0)
      {
        stats.linear_iterations +=
          solve_cg(matrices.stage,
                   matrices.v_work,
                   matrices.rhs_work,
                   *matrices.preconditioner,
                   1000,
                   params.linear_tolerance * rhs_norm,
                   "CG + " + params.preconditioner,
                   "(M + " + std::to_string(gamma) + " K) x = M b");
      }
    else
      matrices.v_work = 0;
    ++stats.linear_solves;

    const LocalRead  b(b_vector);
    const LocalRead  v(matrices.v_work);
    const LocalWrite x(x_vector);
    for (unsigned int i = 0; i < space.n_owned; ++i)
      {
        x.data()[i * space.n_components] = v.data()[i];
        for (unsigned int c = 1; c < space.n_components; ++c)
          x.data()[i * space.n_components + c] =
            b.data()[i * space.n_components + c];
      }
  }


  std::unique_ptr<ImexIntegrator>
  Monodomain::Impl::create_integrator(const double t0)
  {
    ImexIntegrator::Settings settings = ImexIntegrator::Settings::of(params);
    // A consistent mass makes every evaluation of the diffusion term a mass
    // solve: take the one at the end of each implicit stage from the stage
    // solve instead (solved to the same relative tolerance).
    settings.deduce_implicit_rhs = params.consistent_mass;
    ImexIntegrator::Callbacks callbacks;
    callbacks.explicit_rhs =
      [this](const double t, const LA::MPI::Vector &y, LA::MPI::Vector &f) {
        explicit_rhs(t, y, f);
      };
    // Without diffusion (reaction-eikonal RE-) no implicit part at all.
    if (diffusion())
      {
        callbacks.implicit_rhs = [this](const LA::MPI::Vector &y,
                                        LA::MPI::Vector       &f) {
          implicit_rhs(y, f);
        };
        callbacks.solve = [this](const double           gamma,
                                 const LA::MPI::Vector &b,
                                 LA::MPI::Vector       &x) {
          solve_stage(gamma, b, x);
        };
      }
    // The ionic currents are explicit: their stiffness bounds the step.
    callbacks.explicit_stiffness = [this](const LA::MPI::Vector &y) {
      return explicit_stiffness(y);
    };
    // The gates: a Rush-Larsen step after every ARKode step (ARKode sees
    // them frozen, state_rhs() gives them no rate). The step sequence
    // G(h/2) A(h) G(h) A(h) G(h) ... (step() does the first half step) is
    // Strang's splitting G(h/2) A(h) G(h/2) with the two half steps of
    // consecutive steps merged (exact for equal steps when the gates' rates
    // do not depend on the gates, as in ten Tusscher-Panfilov: G at a fixed
    // state then composes additively), so the potential at the step ends is
    // second-order accurate; the stored gates are half a step ahead
    // (docs/architecture.md, Electrophysiology).
    if (model.n_gates() > 0)
      callbacks.after_step =
        [this](const double, const double h, LA::MPI::Vector &y) {
          const LocalWrite values(y);
          model.advance_gates_batch(h,
                                    space.n_owned,
                                    space.n_components,
                                    values.data());
        };
    return std::make_unique<ImexIntegrator>(settings, callbacks, t0, comm);
  }


  void
  Monodomain::Impl::update_output_vectors()
  {
    {
      const LocalRead  y(state);
      const LocalWrite V(outputs.potential_mV);
      const LocalWrite first(outputs.activation_first);
      const LocalWrite latest(outputs.activation_latest);
      const LocalWrite calcium(outputs.calcium_uM);
      const LocalWrite field(outputs.activation_field);
      for (unsigned int i = 0; i < space.n_owned; ++i)
        {
          V.data()[i]      = model.to_mV(y.data()[i * space.n_components]);
          first.data()[i]  = tracker.first()[i];
          field.data()[i]  = std::isnan(tracker.first()[i]) ? not_activated_time
                                                            : tracker.first()[i];
          latest.data()[i] = tracker.latest()[i];
          calcium.data()[i] =
            model.calcium_uM(y.data() + i * space.n_components + 1);
        }
    }
    // deal.II 9.4's PETSc update_ghost_values() does nothing (its ghosted
    // vectors are refreshed by assignment from a non-ghosted one): scatter
    // the owned values written above to the other ranks' ghosts here.
    for (LA::MPI::Vector *v : {&outputs.potential_mV,
                               &outputs.activation_first,
                               &outputs.activation_latest,
                               &outputs.calcium_uM,
                               &outputs.activation_field})
      {
        const Vec      vec = static_cast<const Vec &>(*v);
        PetscErrorCode ierr =
          VecGhostUpdateBegin(vec, INSERT_VALUES, SCATTER_FORWARD);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
        ierr = VecGhostUpdateEnd(vec, INSERT_VALUES, SCATTER_FORWARD);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      }
    const unsigned int n_local = space.n_owned + space.ghosts.n_elements();
    outputs.values.resize(4 * n_local);
    unsigned int c = 0;
    for (LA::MPI::Vector *v : {&outputs.potential_mV,
                               &outputs.activation_first,
                               &outputs.activation_latest,
                               &outputs.calcium_uM})
      {
        const Vec vec   = static_cast<const Vec &>(*v);
        Vec       local = nullptr;
        AssertThrow(VecGhostGetLocalForm(vec, &local) == 0,
                    dealii::ExcInternalError());
        const Vec      from = local != nullptr ? local : vec;
        const double  *a    = nullptr;
        PetscInt       size = 0;
        PetscErrorCode ierr = VecGetLocalSize(from, &size);
        AssertThrow(ierr == 0 && static_cast<unsigned int>(size) == n_local,
                    dealii::ExcInternalError());
        ierr = VecGetArrayRead(from, &a);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
        for (unsigned int i = 0; i < n_local; ++i)
          outputs.values[4 * i + c] = a[i];
        ierr = VecRestoreArrayRead(from, &a);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
        if (local != nullptr)
          VecGhostRestoreLocalForm(vec, &local);
        ++c;
      }
  }


  void
  Monodomain::Impl::step(const double t_next, std::vector<double> &v_new)
  {
    const double middle = 0.5 * (t + t_next);
    for (unsigned int s = 0; s < params.stimuli.size(); ++s)
      stimulation.on[s] =
        params.stimuli[s].active(middle, params.stimulus_period);
    if (gate_half_step_pending && model.n_gates() > 0)
      {
        // Before ARKode's first step (it reads the state then).
        const LocalWrite y(state);
        model.advance_gates_batch(0.5 * (t_next - t),
                                  space.n_owned,
                                  space.n_components,
                                  y.data());
      }
    gate_half_step_pending = false;
    if (params.model == Parameters::Model::reaction_eikonal)
      eikonal_step_stimulus(t, t_next);
    integrator->evolve(state, t_next);
    extract_potential(v_new);
    tracker.update(t, v_sample.data(), t_next, v_new.data());
    v_sample.swap(v_new);
    t = t_next;
  }


  void
  Monodomain::advance(const double t_end)
  {
    Impl      &m     = *impl;
    const auto start = std::chrono::steady_clock::now();
    AssertThrow(t_end > m.t,
                dealii::ExcMessage("Monodomain::advance: t_end (" +
                                   std::to_string(t_end) +
                                   " ms) must lie after the current time (" +
                                   std::to_string(m.t) + " ms)."));
    // Steps end at t_end and at every stimulus switching time; between
    // those breakpoints they are equal and at most Time step long
    // (for_each_step).
    if (m.params.model == Parameters::Model::eikonal)
      {
        m.advance_eikonal_only(t_end);
        m.update_output_vectors();
        m.stats.seconds += std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
        return;
      }
    std::vector<double> breakpoints =
      switching_times(m.params.stimuli, m.params.stimulus_period, m.t, t_end);
    // Reaction-eikonal: short steps while nodes are being stimulated.
    const auto eikonal = m.eikonal_breakpoints(m.t, t_end);
    breakpoints.insert(breakpoints.end(), eikonal.begin(), eikonal.end());
    std::sort(breakpoints.begin(), breakpoints.end());
    breakpoints.erase(std::unique(breakpoints.begin(), breakpoints.end()),
                      breakpoints.end());
    breakpoints.push_back(t_end);
    std::vector<double> v_new;
    for_each_step(m.t, breakpoints, m.params.time_step, [&](const double t) {
      m.step(t, v_new);
    });
    m.update_output_vectors();
    m.stats.steps = m.steps_before + m.integrator->n_steps();
    m.stats.seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
  }
} // namespace systole::Electrophysiology
