// The matrix-free tangent on the matrix-free mechanics' vectorization
// (internal::Lanes; the operator itself is in matrix_free_tangent_impl.h).
#include "mechanics/matrix_free_tangent.h"

#include "mechanics/matrix_free_tangent_impl.h"

namespace systole::Mechanics
{
  MatrixFreeTangent::MatrixFreeTangent(
    const dealii::Mapping<3>                &mapping,
    const dealii::DoFHandler<3>             &dof_handler,
    const dealii::AffineConstraints<double> &constraints,
    const NeoHookeanPenalty                 &law,
    const Variant                            variant)
    : impl(
        std::make_unique<Impl>(mapping, dof_handler, constraints, law, variant))
  {}


  MatrixFreeTangent::MatrixFreeTangent(
    const dealii::Mapping<3>                &mapping,
    const dealii::DoFHandler<3>             &dof_handler,
    const dealii::AffineConstraints<double> &constraints,
    const Variant                            variant,
    const Options                           &options)
    : impl(std::make_unique<Impl>(mapping,
                                  dof_handler,
                                  constraints,
                                  NeoHookeanPenalty(),
                                  variant,
                                  dealii::numbers::invalid_unsigned_int,
                                  &options))
  {
    AssertThrow(variant != Variant::recompute,
                dealii::ExcMessage("MatrixFreeTangent: the general tangent "
                                   "(no law) is stored: Variant::cached or "
                                   "cached_single, not recompute."));
    impl->general = true;
  }


  MatrixFreeTangent::MatrixFreeTangent(
    const dealii::Mapping<3>                &mapping,
    const dealii::DoFHandler<3>             &dof_handler,
    const dealii::AffineConstraints<double> &constraints,
    const Variant                            variant)
    : MatrixFreeTangent(mapping, dof_handler, constraints, variant, Options())
  {}


  MatrixFreeTangent::~MatrixFreeTangent() = default;


  void
  MatrixFreeTangent::initialize_dof_vector(Vector &v) const
  {
    impl->matrix_free.initialize_dof_vector(v);
  }


  void
  MatrixFreeTangent::update(const Vector &u)
  {
    AssertThrow(!impl->general,
                dealii::ExcMessage("MatrixFreeTangent: the general tangent has "
                                   "no law; update it with CellTangents."));
    impl->update(u);
  }


  void
  MatrixFreeTangent::update(const CellTangents &tangents)
  {
    AssertThrow(impl->general,
                dealii::ExcMessage("MatrixFreeTangent: a tangent built with a "
                                   "law is updated from a displacement."));
    impl->update_from(tangents);
  }


  void
  MatrixFreeTangent::update(const MixedCellTangents &tangents,
                            const MixedConstants    &constants)
  {
    AssertThrow(impl->general && constants.pressure_element != nullptr,
                dealii::ExcMessage("MatrixFreeTangent: the pressure coupling "
                                   "needs the general tangent and a pressure "
                                   "element."));
    impl->update_from(tangents, constants);
  }


  void
  MatrixFreeTangent::set_follower_pressure(
    const Vector                                       &u,
    const std::map<dealii::types::boundary_id, double> &pressures)
  {
    impl->set_follower_pressure(u, pressures);
  }


  bool
  MatrixFreeTangent::has_follower_pressure() const
  {
    return !impl->face_pressures.empty();
  }


  void
  MatrixFreeTangent::vmult(Vector &dst, const Vector &src) const
  {
    impl->vmult(dst, src);
  }


  void
  MatrixFreeTangent::residual(Vector &dst) const
  {
    AssertThrow(!impl->general,
                dealii::ExcMessage("MatrixFreeTangent: the general tangent has "
                                   "no residual."));
    impl->residual(dst);
  }


  const std::vector<unsigned int> &
  MatrixFreeTangent::constrained_dofs() const
  {
    return impl->matrix_free.get_constrained_dofs();
  }


  dealii::types::global_dof_index
  MatrixFreeTangent::m() const
  {
    return impl->u.size();
  }


  std::size_t
  MatrixFreeTangent::memory_consumption() const
  {
    return impl->matrix_free.memory_consumption() + point_storage_bytes() +
           impl->u.memory_consumption();
  }


  std::size_t
  MatrixFreeTangent::point_storage_bytes() const
  {
    return impl->storage.memory_consumption() +
           impl->storage_single.memory_consumption() +
           impl->pressure.storage.memory_consumption();
  }


  std::size_t
  MatrixFreeTangent::n_quadrature_points() const
  {
    return impl->n_quadrature_points();
  }


  std::size_t
  MatrixFreeTangent::n_geometry_numbers() const
  {
    return impl->n_geometry_numbers();
  }
} // namespace systole::Mechanics

template class systole::Mechanics::internal::TangentOperator<
  systole::Mechanics::internal::Lanes>;
