#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "base/linear_algebra.h"

#include <petscmat.h>
#include <petscsys.h>

#include <array>
#include <string>

/// @file
/// PETSc helpers of the mechanics' linear solvers (linear_solver.cc) and
/// preconditioners (p_multigrid.cc).

namespace systole::Mechanics
{
  /// The six rigid-body modes of the displacement (translations, rotations
  /// about the axes) at the support points of the displacement components
  /// (0-2) of @p dof_handler, on its locally owned DoFs, zero on other
  /// components, orthonormalized (as PETSc requires of a near-null space).
  std::array<LA::MPI::Vector, 6>
  rigid_body_modes(const dealii::Mapping<3, 3>    &mapping,
                   const dealii::DoFHandler<3, 3> &dof_handler);

  /// Gives @p A the rigid-body @p modes (rigid_body_modes() of A's DoFs) as
  /// its near-null space (what PETSc's GAMG builds its coarse spaces from).
  void
  set_near_null_space(Mat A, const std::array<LA::MPI::Vector, 6> &modes);

  /// The locally owned entries of @p from into @p to (the same owned
  /// indices, e.g. a PETSc vector and a MatrixFree vector of one
  /// DoFHandler); ghosts of @p to are left alone.
  void
  copy_owned(const LA::MPI::Vector                              &from,
             dealii::LinearAlgebra::distributed::Vector<double> &to);
  void
  copy_owned(const dealii::LinearAlgebra::distributed::Vector<double> &from,
             LA::MPI::Vector                                          &to);

  /// Throws naming @p what (the PETSc call) unless @p code is 0.
  void
  check_petsc(const PetscErrorCode code, const char *what);

  /// Sets the PETSc option @p name (with its leading '-') to @p value unless
  /// it is set already (by the user, or by an earlier call).
  void
  set_default_petsc_option(const std::string &name, const std::string &value);
} // namespace systole::Mechanics
