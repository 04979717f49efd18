#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/dofs/dof_handler.h>

#include "base/linear_algebra.h"

#include <memory>
#include <vector>

/// @file
/// Vectors of a DoFHandler that travel with the cells of its distributed mesh
/// through a checkpoint (SolutionTransfer: the mesh's save() writes them, its
/// load() brings them back), so that a run can resume on another number of
/// ranks. The monodomain model's and the mechanics problem's checkpoints use
/// them.

namespace systole
{
  /// Copies of vectors attached to the cells for the next save() of the mesh.
  /// Keep the object alive until that save() has run, then clear() it.
  class AttachedVectors
  {
  public:
    /// Attaches copies of @p sources (vectors of @p dof_handler on the mesh's
    /// communicator), ghosted with @p relevant (SolutionTransfer reads every
    /// DoF of the owned cells). Replaces what was attached before.
    void
    attach(const dealii::DoFHandler<3>                &dof_handler,
           const dealii::IndexSet                     &relevant,
           const std::vector<const LA::MPI::Vector *> &sources);

    /// Releases the copies.
    void
    clear();

  private:
    std::vector<LA::MPI::Vector> vectors;
    std::unique_ptr<
      dealii::parallel::distributed::SolutionTransfer<3, LA::MPI::Vector>>
      transfer;
  };

  /// The @p n vectors that AttachedVectors::attach() attached, read from the
  /// cells of the mesh of @p dof_handler loaded from the checkpoint, in the
  /// layout @p owned (on the mesh's communicator). Collective.
  std::vector<LA::MPI::Vector>
  read_attached_vectors(const dealii::DoFHandler<3> &dof_handler,
                        const dealii::IndexSet      &owned,
                        const unsigned int           n);
} // namespace systole
