#include "geometry/distributed_mesh.h"

#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>
#include <deal.II/grid/tria_description.h>

#include "geometry/cell_kind.h"
#include "geometry/mid_edge_nodes.h"

namespace systole::Geometry
{
  namespace
  {
    /// The tetrahedral path: serial mesh, METIS partition, fully distributed.
    DistributedMesh
    fully_distributed(dealii::Triangulation<3, 3> &serial,
                      BoundaryNames                names,
                      const MPI_Comm               comm)
    {
      const unsigned int n_ranks =
        dealii::Utilities::MPI::n_mpi_processes(comm);
      if (n_ranks > 1)
        dealii::GridTools::partition_triangulation(
          n_ranks,
          serial,
          dealii::SparsityTools::Partitioner::metis);
      const auto description = dealii::TriangulationDescription::Utilities::
        create_description_from_triangulation(serial, comm);
      auto tria =
        std::make_unique<dealii::parallel::fullydistributed::Triangulation<3>>(
          comm);
      tria->create_triangulation(description);
      copy_mid_edge_nodes(serial, *tria);
      return {std::move(tria), std::move(names)};
    }

    /// Throws for what tetrahedral meshes cannot do yet.
    void
    require_tetrahedral_support(const Parameters  &params,
                                const std::string &saved_mesh)
    {
      AssertThrow(saved_mesh.empty(),
                  dealii::ExcMessage(
                    "A checkpoint of a run on a tetrahedral mesh cannot be "
                    "resumed yet: rerun it from the start."));
      AssertThrow(params.local_refinements == 0,
                  dealii::ExcMessage(
                    "Geometry / Local refinements > 0 needs a hexahedral "
                    "mesh (no hanging nodes on tetrahedra): refine a "
                    "tetrahedral mesh with Global refinements or mesh it "
                    "finer."));
    }
  } // namespace

  DistributedMesh
  create_distributed_mesh(const Parameters  &params,
                          const MPI_Comm     comm,
                          const std::string &saved_mesh)
  {
    if (params.tetrahedra && params.type != Parameters::Type::gmsh)
      {
        require_tetrahedral_support(params, saved_mesh);
        dealii::Triangulation<3, 3> hexahedra;
        BoundaryNames               names = create_mesh(params, hexahedra);
        dealii::Triangulation<3, 3> serial;
        dealii::GridGenerator::convert_hypercube_to_simplex_mesh(hexahedra,
                                                                 serial);
        return fully_distributed(serial, std::move(names), comm);
      }
    if (params.type == Parameters::Type::gmsh)
      {
        // Read once serially to learn the cell shape.
        dealii::Triangulation<3, 3> serial;
        Parameters                  coarse = params;
        coarse.global_refinements          = 0;
        coarse.local_refinements           = 0;
        BoundaryNames names                = create_mesh(coarse, serial);
        if (CellKind(serial).simplex())
          {
            require_tetrahedral_support(params, saved_mesh);
            serial.refine_global(params.global_refinements);
            return fully_distributed(serial, std::move(names), comm);
          }
      }
    auto tria =
      std::make_unique<dealii::parallel::distributed::Triangulation<3>>(comm);
    BoundaryNames names = create_mesh(params, *tria, saved_mesh);
    return {std::move(tria), std::move(names)};
  }

  const dealii::parallel::distributed::Triangulation<3, 3> &
  hexahedral(const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
             const std::string                                          &what)
  {
    const auto *p4est =
      dynamic_cast<const dealii::parallel::distributed::Triangulation<3, 3> *>(
        &tria);
    AssertThrow(p4est != nullptr,
                dealii::ExcMessage(
                  what + " runs on hexahedral meshes only so far; this mesh is "
                         "tetrahedral."));
    return *p4est;
  }
} // namespace systole::Geometry
