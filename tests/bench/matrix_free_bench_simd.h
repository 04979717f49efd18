#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "mechanics/matrix_free_tangent.h"

#include <memory>

/// @file
/// The matrix-free tangent behind one interface for the benchmark: the
/// library's (deal.II's default vectorization, which is none for Debian's
/// deal.II) and an 8-lane AVX-512 build of the same operator template
/// (matrix_free_bench_simd.cc, compiled with -mavx512f and its own
/// instantiation of MatrixFree), to measure what a vectorized deal.II gives.

namespace bench
{
  using Vector  = systole::Mechanics::MatrixFreeTangent::Vector;
  using Variant = systole::Mechanics::MatrixFreeTangent::Variant;

  /// The functions of MatrixFreeTangent the benchmark uses.
  class Tangent
  {
  public:
    virtual ~Tangent() = default;
    virtual void
    initialize_dof_vector(Vector &v) const = 0;
    virtual void
    update(const Vector &u) = 0;
    virtual void
    vmult(Vector &dst, const Vector &src) const = 0;
    virtual double
    m() const = 0;
    virtual std::size_t
    memory_consumption() const = 0;
    virtual std::size_t
    point_storage_bytes() const = 0;
    virtual std::size_t
    n_quadrature_points() const = 0;
    virtual std::size_t
    n_geometry_numbers() const = 0;
  };

  /// The 8-lane operator (call only where the CPU has AVX-512F).
  std::unique_ptr<Tangent>
  make_simd_tangent(const dealii::Mapping<3>                    &mapping,
                    const dealii::DoFHandler<3>                 &dof_handler,
                    const dealii::AffineConstraints<double>     &constraints,
                    const systole::Mechanics::NeoHookeanPenalty &law,
                    const Variant                                variant);
} // namespace bench
