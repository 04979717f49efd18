#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>

#include <petscpc.h>

#include <memory>
#include <string>

namespace systole::Mechanics
{
  class FieldLayout;

  /// Two-level p-multigrid for the displacement block of the mechanics
  /// tangent (Q_k, k >= 2): one V-cycle of PETSc's PCMG with
  /// - the fine level: the displacement block A itself, smoothed by a few
  ///   Chebyshev iterations with point-block Jacobi (3 x 3 blocks of a node);
  /// - the coarse level: the Galerkin product A_1 = P^T A P on the Q1
  ///   displacement space of the same mesh, solved exactly (MUMPS LU; with
  ///   <prefix>mg_coarse_pc_type gamg approximately, by one GAMG V-cycle
  ///   given the six rigid-body modes of the Q1 space as near-null space).
  ///
  /// P is the exact interpolation from FE_Q(1)^3 to FE_Q(k)^3 of every cell
  /// (FiniteElement::get_interpolation_matrix), built once per mesh as a
  /// PETSc MPIAIJ matrix: rows in the displacement-block numbering of the
  /// FieldLayout (rank by rank its u DoFs, so also the rows of K itself when
  /// there is no pressure), columns in the numbering of a Q1 DoFHandler
  /// (nodes interleaved, block size 3). Rows of constrained fine DoFs (fixed,
  /// sliding, hanging) interpolate nothing, except that a constrained fine
  /// vertex DoF keeps the 1 of its coarse vertex DoF: the tangent holds
  /// constrained DoFs decoupled (a diagonal entry), so the coarse space is
  /// {interpolated Q1 fields, seen on the free DoFs}, and every coarse DoF
  /// keeps a diagonal entry (A_1 stays regular without constraints of its
  /// own).
  ///
  /// The preconditioner takes the place of a PC given to attach() (PCSHELL):
  /// its operator, the displacement block, is read at every set-up (the
  /// Galerkin product reuses its symbolic part across Newton iterations).
  /// PETSc options with the given prefix override the defaults, e.g.
  /// <prefix>mg_levels_ksp_type, <prefix>mg_levels_ksp_max_it,
  /// <prefix>mg_levels_pc_type (fine smoother), <prefix>mg_coarse_pc_type
  /// (coarse solver: lu by default, or gamg), <prefix>mg_coarse_mg_levels_*
  /// (GAMG's smoothers).
  class PMultigrid
  {
  public:
    /// Whether @p dof_handler's displacement has a degree above 1 (only then
    /// there is a coarser level).
    static bool
    applicable(const dealii::DoFHandler<3, 3> &dof_handler);

    /// Build the interpolation and the coarse near-null space.
    /// @param[in] dof_handler the mechanics DoFs, renumbered by @p layout
    /// @param[in] constraints the (homogeneous) constraints of the tangent
    /// @param[in] prefix PETSc options prefix of the two-level cycle
    PMultigrid(const dealii::Mapping<3, 3>             &mapping,
               const dealii::DoFHandler<3, 3>          &dof_handler,
               const FieldLayout                       &layout,
               const dealii::AffineConstraints<double> &constraints,
               const std::string                       &prefix);
    ~PMultigrid();
    PMultigrid(const PMultigrid &) = delete;
    PMultigrid &
    operator=(const PMultigrid &) = delete;

    /// Make @p pc (whose operator will be the displacement block) apply one
    /// V-cycle of this preconditioner. This object must outlive @p pc.
    void
    attach(PC pc);

    /// E.g. "p-multigrid Q2 -> Q1 (...)".
    std::string
    name() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Mechanics
