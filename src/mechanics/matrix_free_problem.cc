// The mechanics' own matrix-free tangent (issue 40): Problem's entry points
// to the general MatrixFreeTangent, whose point tangents the assembly's
// kernel fills (Problem::Impl::update_matrix_free_tangent, assembly.cc).
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/problem_impl.h"

namespace systole::Mechanics
{
  std::unique_ptr<MatrixFreeTangent>
  Problem::matrix_free_tangent(const double active_tension, const bool single)
  {
    impl->check_matrix_free_tangent(); // (before MatrixFree's own checks)
    const Discretization &d       = impl->discretization;
    auto                  tangent = std::make_unique<MatrixFreeTangent>(
      d.mapping,
      d.dof_handler,
      d.constraints,
      single ? MatrixFreeTangent::Variant::cached_single
                              : MatrixFreeTangent::Variant::cached,
      MatrixFreeTangent::Options{true, nullptr, nullptr});
    impl->update_matrix_free_tangent(*tangent,
                                     impl->uniform_pressures(0.0),
                                     active_tension);
    return tangent;
  }


  void
  Problem::update_matrix_free_tangent(MatrixFreeTangent &tangent,
                                      const double       active_tension)
  {
    AssertThrow(tangent.m() == impl->discretization.dof_handler.n_dofs(),
                dealii::ExcMessage("Problem::update_matrix_free_tangent: the "
                                   "tangent is not one of this problem."));
    impl->update_matrix_free_tangent(tangent,
                                     impl->uniform_pressures(0.0),
                                     active_tension);
  }


  void
  Problem::update_matrix_free_tangent(MatrixFreeTangent &tangent,
                                      const double       pressure,
                                      const double       active_tension)
  {
    AssertThrow(tangent.m() == impl->discretization.dof_handler.n_dofs(),
                dealii::ExcMessage("Problem::update_matrix_free_tangent: the "
                                   "tangent is not one of this problem."));
    impl->update_matrix_free_tangent(tangent,
                                     impl->uniform_pressures(pressure),
                                     active_tension);
  }
} // namespace systole::Mechanics
