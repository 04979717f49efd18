// The 8-lane build of the matrix-free tangent for the benchmark. Debian's
// deal.II is configured without vectorization (VectorizedArray<double> has
// one lane, and MatrixFree is compiled for it only), so this translation unit
// raises the vectorization width after deal.II's config.h (which makes the
// 8-lane VectorizedArray<double, 8> available, while the default width stays
// 1), is compiled with -mavx512f, and instantiates MatrixFree for
// VectorizedArray<double, 8> itself (matrix_free_instantiation.h). The
// library's own width is the build machine's (cmake/SystoleSimd.cmake); this
// unit gives the benchmark 8 lanes whatever the library's.
#include <deal.II/base/config.h>
#undef DEAL_II_VECTORIZATION_WIDTH_IN_BITS
#define DEAL_II_VECTORIZATION_WIDTH_IN_BITS 512

#include "mechanics/matrix_free_instantiation.h"
#include "mechanics/matrix_free_tangent_impl.h"

#include "matrix_free_bench_simd.h"

using VA8 = dealii::VectorizedArray<double, 8>;
static_assert(VA8::size() == 8, "compile this file with -mavx512f");

SYSTOLE_INSTANTIATE_MATRIX_FREE(VA8);

namespace bench
{
  namespace
  {
    class SimdTangent : public Tangent
    {
    public:
      template <typename... Args>
      SimdTangent(Args &&...args)
        : op(std::forward<Args>(args)...)
      {}
      void
      initialize_dof_vector(Vector &v) const override
      {
        op.matrix_free.initialize_dof_vector(v);
      }
      void
      update(const Vector &u) override
      {
        op.update(u);
      }
      void
      vmult(Vector &dst, const Vector &src) const override
      {
        op.vmult(dst, src);
      }
      double
      m() const override
      {
        return op.u.size();
      }
      std::size_t
      memory_consumption() const override
      {
        return op.matrix_free.memory_consumption() + point_storage_bytes() +
               op.u.memory_consumption();
      }
      std::size_t
      point_storage_bytes() const override
      {
        return op.storage.memory_consumption() +
               op.storage_single.memory_consumption();
      }
      std::size_t
      n_quadrature_points() const override
      {
        return op.n_quadrature_points();
      }
      std::size_t
      n_geometry_numbers() const override
      {
        return op.n_geometry_numbers();
      }

    private:
      systole::Mechanics::internal::TangentOperator<VA8> op;
    };
  } // namespace

  std::unique_ptr<Tangent>
  make_simd_tangent(const dealii::Mapping<3>                    &mapping,
                    const dealii::DoFHandler<3>                 &dof_handler,
                    const dealii::AffineConstraints<double>     &constraints,
                    const systole::Mechanics::NeoHookeanPenalty &law,
                    const Variant                                variant)
  {
    return std::make_unique<SimdTangent>(mapping,
                                         dof_handler,
                                         constraints,
                                         law,
                                         variant);
  }
} // namespace bench
