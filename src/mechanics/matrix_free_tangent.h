#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "mechanics/hyperelastic_kernel.h"

#include <functional>
#include <map>
#include <memory>
#include <vector>

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
  ///
  /// The general tangent (the constructor without a law): update(
  /// CellTangents) takes the first elasticity tangent dP/dF of every point
  /// from the caller, cell by cell (e.g. from the mechanics' own point kernel,
  /// ProblemChecks::matrix_free_tangent(): any passive law with its fibre
  /// frame, the volumetric penalty, the active tension), and stores it like
  /// Variant::cached (or cached_single); vmult() is then the same code.
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

    /// The first elasticity tangent A = dP/dF [kPa] at the quadrature points
    /// of one locally owned @p cell, in the order of QGauss<3>(3) (x
    /// fastest), A[q][i][J][k][L] = dP_iJ/dF_kL; the vector arrives sized
    /// 27. It must have the major symmetry A_iJkL = A_kLiJ (a hyperelastic
    /// tangent): only the upper triangle of the pulled-back 9 x 9 is stored.
    using CellTangents =
      std::function<void(const dealii::DoFHandler<3>::cell_iterator &cell,
                         std::vector<dealii::Tensor<4, 3>>          &A)>;

    /// What the general tangent's MatrixFree holds besides the cells.
    struct Options
    {
      /// The boundary faces: the follower pressure's stiffness
      /// (set_follower_pressure()).
      bool boundary_faces = false;
      /// A Q1^3 DoFHandler on the same mesh and its (homogeneous)
      /// constraints: the coarse level of a p-multigrid, whose matrix the
      /// stored tangent gives at the same quadrature points
      /// (MatrixFreePMultigrid). Both must outlive the tangent.
      const dealii::DoFHandler<3>             *q1             = nullptr;
      const dealii::AffineConstraints<double> *q1_constraints = nullptr;
    };

    /// The general tangent: no law of its own, the point tangents come from
    /// update(const CellTangents &). @p variant: cached or cached_single
    /// (throws for recompute). The arguments as in the other constructor.
    MatrixFreeTangent(const dealii::Mapping<3>                &mapping,
                      const dealii::DoFHandler<3>             &dof_handler,
                      const dealii::AffineConstraints<double> &constraints,
                      const Variant                            variant,
                      const Options                           &options);

    /// The general tangent without boundary faces or Q1 level.
    MatrixFreeTangent(const dealii::Mapping<3>                &mapping,
                      const dealii::DoFHandler<3>             &dof_handler,
                      const dealii::AffineConstraints<double> &constraints,
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

    /// The general tangent: store @p tangents of every locally owned cell
    /// (pulled back to the unit cell, JxW folded in). Throws for a tangent
    /// built with a law. Collective only in what @p tangents does.
    void
    update(const CellTangents &tangents);

    /// The pressure coupling of the mixed Q2-P1disc formulation at one
    /// point: J F^-T, and the weights of the augmented Lagrangian (1/kappa +
    /// 1/mu) and of the Schur preconditioner (the assembly's).
    struct PointPressure
    {
      dealii::Tensor<2, 3> cofactor;
      double               augmentation_weight = 0.0;
      double               schur_weight        = 0.0;
    };

    /// CellTangents with the pressure coupling of every point (vectors
    /// arrive sized 27).
    using MixedCellTangents =
      std::function<void(const dealii::DoFHandler<3>::cell_iterator &cell,
                         std::vector<dealii::Tensor<4, 3>>          &A,
                         std::vector<PointPressure>                 &pressure)>;

    /// What the pressure coupling needs besides the points.
    struct MixedConstants
    {
      /// The pressure element (four shape functions, mapped: FE_DGP(1)).
      const dealii::FiniteElement<3> *pressure_element = nullptr;
      double                          inverse_kappa    = 0.0; ///< [1/kPa]
      double                          gamma            = 0.0; ///< the AL's
    };

    /// The general tangent of a mixed formulation: as update(const
    /// CellTangents &), and the pressure coupling of every cell (its rows
    /// B, the 4 x 4 cell blocks). vmult() and the Q1 level then apply the
    /// displacement block of the augmented system, A + B^T gamma W^-1 B
    /// (the assembly's T K_0, docs: Augmented Lagrangian factor); the
    /// pressure rows and columns are MatrixFreeMixedSolver's.
    void
    update(const MixedCellTangents &tangents, const MixedConstants &constants);

    /// The follower pressure on boundary faces (Options::boundary_faces):
    /// vmult() then adds its stiffness
    /// @f$p\int \varphi_a\cdot(\partial_F\mathrm{cof}(F)[\nabla_0
    /// \varphi_b])N\,dA@f$ on the faces of each boundary id of @p pressures
    /// [kPa] at the displacement @p u (not symmetric: the load follows the
    /// wall). Replaces the last call's pressures; an empty map removes the
    /// term. Collective.
    void
    set_follower_pressure(
      const Vector                                       &u,
      const std::map<dealii::types::boundary_id, double> &pressures);

    /// Whether vmult() has a follower-pressure term (then K is not
    /// symmetric).
    bool
    has_follower_pressure() const;

    /// dst = K src with K the tangent at the last update() (collective).
    void
    vmult(Vector &dst, const Vector &src) const;

    /// dst = R(u) at the last update() (constrained rows zero; collective).
    /// Not for the general tangent (throws).
    void
    residual(Vector &dst) const;

    /// The locally owned constrained DoFs (local indices of the vectors of
    /// initialize_dof_vector()), on which vmult() is the identity.
    const std::vector<unsigned int> &
    constrained_dofs() const;

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

    /// The operator (defined in matrix_free_tangent_impl.h: for the
    /// multigrid built on it).
    struct Impl;
    Impl &
    implementation() const
    {
      return *impl;
    }

  private:
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Mechanics
