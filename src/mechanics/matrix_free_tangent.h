#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "mechanics/hyperelastic_kernel.h"

#include <memory>

namespace systole::Mechanics
{
  /// The consistent tangent of the displacement-only (penalty) hyperelastic
  /// residual
  /// @f$R_a(u) = \int_{\Omega_0} P(F) : \nabla_0 \phi_a \,dV@f$,
  /// @f$F = I + \nabla_0 u@f$, applied matrix-free: deal.II's MatrixFree with
  /// sum factorization on Q2 hexahedra (FEEvaluation<3, 2, 3, 3>, 3 Gauss
  /// points per direction), after deal.II's step-37 and Davydov et al. 2020
  /// (Int. J. Numer. Meth. Eng. 121:2874, matrix-free finite-strain
  /// hyperelasticity with geometric multigrid).
  ///
  /// Three variants of the storage at the quadrature points:
  /// - Variant::cached: update() stores the 9 x 9 tangent
  ///   @f$\mathbb{A} = \partial P/\partial F@f$ of every point (45 numbers
  ///   by its major symmetry), pulled back to the unit cell with the inverse
  ///   Jacobian and JxW folded in, and vmult() contracts it with the
  ///   unit-cell gradient of the input (no geometry read): memory bound;
  /// - Variant::cached_single: as cached, the tangent rounded to single
  ///   precision (half the bytes; the product is then accurate to about
  ///   1e-7 relative, e.g. for a preconditioner or an inexact Newton step);
  /// - Variant::recompute: update() stores the law's state per point (F,
  ///   F^-T and four scalars: 22 numbers, NeoHookeanPenalty::State), and
  ///   vmult() evaluates the linearization from it (products and sums, no
  ///   inverse or power): half the memory, more arithmetic.
  ///
  /// Both use NeoHookeanPenalty's state() and linearization(); its stress()
  /// gives the residual.
  /// Constrained DoFs: the constraints (homogeneous for the tangent) are
  /// applied to the input and the output; on the constrained rows vmult()
  /// returns the input (the identity, as deal.II's MatrixFreeOperators).
  /// The mechanics' own matrix-based path is unchanged by this class.
  class MatrixFreeTangent
  {
  public:
    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;

    /// What the quadrature points keep between update() and vmult().
    enum class Variant
    {
      cached,
      cached_single,
      recompute
    };

    /// @param[in] mapping the geometry (e.g. MappingQ(2) or the mechanics'
    ///   MappingQCache).
    /// @param[in] dof_handler Q2 displacement (an FESystem of 3 FE_Q(2), or
    ///   FE_Q(2)^3) on hexahedra; throws ExcMessage otherwise.
    /// @param[in] constraints homogeneous constraints of the tangent
    ///   (Dirichlet rows, hanging nodes).
    /// The three arguments must outlive this object.
    MatrixFreeTangent(const dealii::Mapping<3>                &mapping,
                      const dealii::DoFHandler<3>             &dof_handler,
                      const dealii::AffineConstraints<double> &constraints,
                      const NeoHookeanPenalty                 &law,
                      const Variant                            variant);

    ~MatrixFreeTangent();

    /// Sizes @p v in the operator's parallel layout (owned + ghosts).
    void
    initialize_dof_vector(Vector &v) const;

    /// Linearize at the displacement @p u (in the layout of
    /// initialize_dof_vector(); its values are used as they are,
    /// constrained entries included). Throws ExcMessage if det F <= 0 at a
    /// point. Collective.
    void
    update(const Vector &u);

    /// dst = K src with K the tangent at the last update() (collective).
    void
    vmult(Vector &dst, const Vector &src) const;

    /// dst = R(u) at the last update() (constrained rows zero; collective).
    void
    residual(Vector &dst) const;

    /// Global number of DoFs.
    dealii::types::global_dof_index
    m() const;

    /// Bytes held by this rank: MatrixFree's data (indices, geometry), the
    /// point storage and the ghosted displacement.
    std::size_t
    memory_consumption() const;

    /// Bytes of the point storage alone (this rank).
    std::size_t
    point_storage_bytes() const;

    /// Quadrature points of this rank's cells.
    std::size_t
    n_quadrature_points() const;

    /// Numbers of geometry vmult() reads per application on this rank: 0
    /// for Variant::cached; for Variant::recompute 10 per point of a general
    /// cell (inverse Jacobian and JxW) and 10 per affine cell batch.
    std::size_t
    n_geometry_numbers() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Mechanics
