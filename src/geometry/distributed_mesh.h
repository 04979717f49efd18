#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/distributed/tria_base.h>

#include "geometry/boundary_names.h"
#include "geometry/mesh.h"

#include <memory>
#include <string>

namespace systole::Geometry
{
  /// A mesh distributed over the ranks of a communicator, with the names of
  /// its boundary parts.
  struct DistributedMesh
  {
    std::unique_ptr<dealii::parallel::DistributedTriangulationBase<3, 3>> tria;
    BoundaryNames                                                         names;
  };

  /// Build the mesh of @p params on @p comm.
  ///
  /// Hexahedral meshes (the generators, hexahedral files) live on p4est
  /// (parallel::distributed::Triangulation): every rank builds the coarse
  /// mesh, p4est refines and partitions it. Tetrahedral meshes (p4est is
  /// hex-only) are read and refined on every rank as one serial mesh,
  /// partitioned by METIS into the ranks (fewest cut faces) and handed to a
  /// parallel::fullydistributed::Triangulation, which keeps only the owned
  /// cells and one layer of ghosts; the serial copy is freed.
  /// @param[in] saved_mesh if not empty: the mesh of a checkpoint, written by
  ///   save() of the mesh built from the same @p params, with its cell data
  ///   (hexahedra: see create_mesh(), on any number of ranks; tetrahedra:
  ///   the saved partition, on the number of ranks that saved it, else an
  ///   error naming both counts).
  DistributedMesh
  create_distributed_mesh(const Parameters  &params,
                          const MPI_Comm     comm,
                          const std::string &saved_mesh = "");

  /// @p tria as a p4est mesh, for the parts that need one; throws an error
  /// naming @p what when the mesh is tetrahedral.
  const dealii::parallel::distributed::Triangulation<3, 3> &
  hexahedral(const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
             const std::string                                          &what);
} // namespace systole::Geometry
