#pragma once

#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "materials/passive_law.h"
#include "materials/volumetric_law.h"

#include <memory>

/// @file
/// An independent, matrix-based reference for the matrix-free mechanics
/// operator (Mechanics::MatrixFreeTangent): the consistent tangent of the
/// penalty residual R_a = int P(F) : grad phi_a dV assembled with FEValues
/// from Systole's material laws (PassiveLaw's S and dS/dE plus a
/// VolumetricLaw), in the form of the mechanics' assembly:
/// A_iJkL = F_iI C_IJKL F_kK + delta_ik S_JL, C = dS/dE. Also the cube
/// meshes of the matrix-free tests and bench.

namespace test_support
{
  using DistributedVector = dealii::LinearAlgebra::distributed::Vector<double>;

  /// A box [0, 2] x [0, 1.5] x [0, 1] mm of @p n x @p n x @p n hexahedra,
  /// its vertices moved by a smooth nonlinear map (so no cell is a
  /// parallelepiped and the geometry differs at every quadrature point),
  /// boundary id 0 on the face x = 0.
  void
  distorted_box(dealii::parallel::distributed::Triangulation<3> &tria,
                const unsigned int                               n);

  /// The Q2 displacement problem of the matrix-free tests: distorted_box(n)
  /// on @p comm refined @p n_refinements times (with the multigrid
  /// hierarchy and level DoFs), FESystem(FE_Q(2), 3), MappingQ(2), u = 0 on
  /// the face x = 0
  /// (constraints, homogeneous) and the displacement Bulge interpolated
  /// into u (ghosted; it does not satisfy the constraints, which the
  /// linearization does not need).
  struct BoxMechanics
  {
    BoxMechanics(const MPI_Comm     comm,
                 const unsigned int n,
                 const unsigned int n_refinements = 0);

    dealii::parallel::distributed::Triangulation<3> tria;
    std::unique_ptr<dealii::FiniteElement<3>>       fe;
    std::unique_ptr<dealii::Mapping<3>>             mapping;
    dealii::DoFHandler<3>                           dof_handler;
    dealii::AffineConstraints<double>               constraints;
    dealii::IndexSet                                owned, relevant;

    /// A ghosted vector of the DoFHandler's layout (owned, relevant).
    DistributedVector
    ghosted_vector() const;

    /// @p f interpolated (ghosted result).
    DistributedVector
    interpolate(const dealii::Function<3> &f) const;
  };

  /// A smooth displacement of order 0.1 mm (strains of order 0.1; det F > 0
  /// on distorted_box()).
  class Bulge : public dealii::Function<3>
  {
  public:
    Bulge();

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override;
  };

  /// The sparsity of @p dof_handler with @p constraints and the matrix
  /// @p K on it (PETSc, rows and columns in the locally owned DoFs;
  /// collective).
  void
  setup_sparse_tangent(const dealii::DoFHandler<3>              &dof_handler,
                       const dealii::AffineConstraints<double>  &constraints,
                       dealii::PETScWrappers::MPI::SparseMatrix &K);

  /// @p K (set up by setup_sparse_tangent()) = the tangent at the ghosted
  /// displacement @p u: K = sum_cells int grad phi_a : A : grad phi_b with
  /// QGauss(3), condensed with @p constraints (constrained rows get a
  /// diagonal entry, as deal.II's distribute_local_to_global). Collective.
  void
  assemble_penalty_tangent(const dealii::Mapping<3>                &mapping,
                           const dealii::DoFHandler<3>             &dof_handler,
                           const dealii::AffineConstraints<double> &constraints,
                           const DistributedVector                 &u,
                           const systole::Materials::PassiveLaw    &passive,
                           const systole::Materials::VolumetricLaw &volumetric,
                           dealii::PETScWrappers::MPI::SparseMatrix &K);

  /// dst = @p K src over the locally owned entries (src, dst in the
  /// distributed layout; @p x, @p y PETSc vectors of K's layout used as
  /// buffers).
  void
  sparse_vmult(const dealii::PETScWrappers::MPI::SparseMatrix &K,
               const DistributedVector                        &src,
               dealii::PETScWrappers::MPI::Vector             &x,
               dealii::PETScWrappers::MPI::Vector             &y,
               DistributedVector                              &dst);
} // namespace test_support
