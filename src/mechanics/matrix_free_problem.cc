// The mechanics' own matrix-free tangent outside a linear solver (issue 40):
// the verification hooks (ProblemChecks) to the general MatrixFreeTangent,
// whose point tangents the assembly's kernel fills
// (Problem::Impl::update_matrix_free_tangent, assembly.cc).
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/problem_checks.h"
#include "mechanics/problem_impl.h"

namespace systole::Mechanics
{
  std::unique_ptr<MatrixFreeTangent>
  ProblemChecks::matrix_free_tangent(Problem     &problem,
                                     const double active_tension,
                                     const bool   single)
  {
    Problem::Impl &m = *problem.impl;
    m.check_matrix_free_tangent(); // (before MatrixFree's own checks)
    const Discretization &d       = m.discretization;
    auto                  tangent = std::make_unique<MatrixFreeTangent>(
      d.mapping,
      d.dof_handler,
      d.constraints,
      single ? MatrixFreeTangent::Variant::cached_single
                              : MatrixFreeTangent::Variant::cached,
      MatrixFreeTangent::Options{true, nullptr, nullptr});
    m.update_matrix_free_tangent(*tangent,
                                 m.uniform_pressures(0.0),
                                 active_tension);
    return tangent;
  }


  void
  ProblemChecks::update_matrix_free_tangent(Problem           &problem,
                                            MatrixFreeTangent &tangent,
                                            const double       active_tension)
  {
    update_matrix_free_tangent(problem, tangent, 0.0, active_tension);
  }


  void
  ProblemChecks::update_matrix_free_tangent(Problem           &problem,
                                            MatrixFreeTangent &tangent,
                                            const double       pressure,
                                            const double       active_tension)
  {
    Problem::Impl &m = *problem.impl;
    AssertThrow(tangent.m() == m.discretization.dof_handler.n_dofs(),
                dealii::ExcMessage("ProblemChecks::update_matrix_free_tangent: "
                                   "the tangent is not one of this problem."));
    m.update_matrix_free_tangent(tangent,
                                 m.uniform_pressures(pressure),
                                 active_tension);
  }
} // namespace systole::Mechanics
