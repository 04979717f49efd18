// The verification hooks of Mechanics::Problem (problem_checks.h).
#include "mechanics/problem_checks.h"

#include "mechanics/linear_solver.h"
#include "mechanics/problem_impl.h"

#include <cmath>

namespace systole::Mechanics
{
  namespace
  {
    /// The direction of the finite-difference checks: sin(1 + 0.37 i)
    /// cos(0.11 i) at DoF i, zero where constrained.
    LA::MPI::Vector
    check_direction(const Discretization &discretization, const MPI_Comm comm)
    {
      LA::MPI::Vector d(discretization.owned, comm);
      for (const auto i : discretization.owned)
        d(i) = std::sin(1.0 + 0.37 * i) * std::cos(0.11 * i);
      d.compress(dealii::VectorOperation::insert);
      discretization.constraints.set_zero(d);
      return d;
    }
  } // namespace

  double
  ProblemChecks::tangent_error(Problem     &problem,
                               const double pressure,
                               const double active_tension,
                               const double h)
  {
    Problem::Impl               &m         = *problem.impl;
    const dealii::Vector<double> pressures = m.uniform_pressures(pressure);
    m.assemble(pressures, active_tension, true);
    const LA::MPI::Vector d = check_direction(m.discretization, m.comm);
    LA::MPI::Vector       Kd(m.discretization.owned, m.comm);
    m.tangent_vmult(Kd, d);

    const LA::MPI::Vector u0          = m.u_owned;
    const auto            residual_at = [&](const double step) {
      m.u_owned = u0;
      m.u_owned.add(step, d);
      m.u = m.u_owned;
      m.assemble(pressures, active_tension, false);
      return LA::MPI::Vector(m.system.residual);
    };
    LA::MPI::Vector difference = residual_at(h);
    difference -= residual_at(-h);
    difference /= 2.0 * h;
    m.u_owned = u0;
    m.u       = m.u_owned;

    difference -= Kd;
    return difference.l2_norm() / Kd.l2_norm();
  }

  std::array<double, 2>
  ProblemChecks::bordered_jacobian_error(
    Problem                      &problem,
    const dealii::Vector<double> &pressures,
    const double                  active_tension,
    const double                  h)
  {
    Problem::Impl     &m = *problem.impl;
    const unsigned int k = m.loads.cavities.size();
    AssertThrow(
      k > 0 && pressures.size() == k,
      dealii::ExcMessage(
        "bordered_jacobian_error: one pressure per cavity expected (" +
        std::to_string(pressures.size()) + " given, " + std::to_string(k) +
        " cavities)."));
    m.assemble(pressures, active_tension, true, true);
    const LA::MPI::Vector d = check_direction(m.discretization, m.comm);
    LA::MPI::Vector       Jd(m.discretization.owned, m.comm);
    // The pressure direction: a different size and sign in each cavity.
    dealii::Vector<double> dp(k);
    for (unsigned int i = 0; i < k; ++i)
      dp[i] =
        0.3 * std::max(std::abs(pressures[i]), 1.0) * (i % 2 == 0 ? 1.0 : -0.7);
    // First block row: K d - B dp (R depends on p through -p_i b_i); second:
    // D^T d (D = dV/du, the volume rows).
    m.tangent_vmult(Jd, d);
    dealii::Vector<double> volume_row(k);
    for (unsigned int i = 0; i < k; ++i)
      {
        Jd.add(-dp[i], m.loads.volume_derivatives[i]);
        volume_row[i] = m.loads.volume_rows[i] * d;
      }

    const LA::MPI::Vector u0          = m.u_owned;
    const auto            evaluate_at = [&](const double            step,
                                 dealii::Vector<double> &volumes) {
      m.u_owned = u0;
      m.u_owned.add(step, d);
      m.u                            = m.u_owned;
      dealii::Vector<double> stepped = pressures;
      stepped.add(step, dp);
      m.assemble(stepped, active_tension, false);
      volumes = m.cavity_volumes_now();
      return LA::MPI::Vector(m.system.residual);
    };
    dealii::Vector<double> v_plus, v_minus;
    LA::MPI::Vector        difference = evaluate_at(h, v_plus);
    difference -= evaluate_at(-h, v_minus);
    difference /= 2.0 * h;
    m.u_owned = u0;
    m.u       = m.u_owned;

    difference -= Jd;
    double volume_error = 0, volume_scale = 0;
    for (unsigned int i = 0; i < k; ++i)
      {
        const double volume_difference = (v_plus[i] - v_minus[i]) / (2.0 * h);
        volume_error += (volume_difference - volume_row[i]) *
                        (volume_difference - volume_row[i]);
        volume_scale += volume_row[i] * volume_row[i];
      }
    return {{difference.l2_norm() / Jd.l2_norm(),
             std::sqrt(volume_error) / std::sqrt(volume_scale)}};
  }

  std::array<double, 2>
  ProblemChecks::bordered_jacobian_error(Problem     &problem,
                                         const double pressure,
                                         const double active_tension,
                                         const double h)
  {
    dealii::Vector<double> pressures(problem.n_cavities());
    pressures = pressure;
    return bordered_jacobian_error(problem, pressures, active_tension, h);
  }

  void
  ProblemChecks::set_pressure_field(Problem &problem, const double amplitude)
  {
    Problem::Impl &m = *problem.impl;
    for (const auto i : m.discretization.layout.owned(1))
      m.u_owned(i) = amplitude * std::sin(1.0 + 0.7 * i);
    m.u_owned.compress(dealii::VectorOperation::insert);
    m.u = m.u_owned;
  }

  const dealii::PETScWrappers::MPI::SparseMatrix &
  ProblemChecks::assembled_tangent(Problem     &problem,
                                   const double pressure,
                                   const double active_tension)
  {
    Problem::Impl &m = *problem.impl;
    AssertThrow(m.system.linear_solver->matrix_free_tangent() == nullptr,
                dealii::ExcMessage("ProblemChecks::assembled_tangent: the "
                                   "matrix-free solver assembles no tangent."));
    m.assemble(m.uniform_pressures(pressure), active_tension, true);
    return m.system.tangent;
  }
} // namespace systole::Mechanics
