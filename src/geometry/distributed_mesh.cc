#include "geometry/distributed_mesh.h"

#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>
#include <deal.II/grid/tria_description.h>

#include "geometry/cell_kind.h"
#include "geometry/mid_edge_nodes.h"

#include <fstream>
#include <numeric>

namespace systole::Geometry
{
  namespace
  {
    /// What the .info file of a fully distributed mesh's save() records.
    struct SavedMeshInfo
    {
      unsigned int n_ranks = 0, n_fixed = 0, n_variable = 0;
    };

    /// The .info file of the mesh saved as @p filename (read on rank 0).
    SavedMeshInfo
    read_saved_mesh_info(const std::string &filename, const MPI_Comm comm)
    {
      std::vector<unsigned int> values(4, 0);
      if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
        {
          std::ifstream in(filename + ".info");
          std::string   header;
          std::getline(in, header);
          for (auto &v : values)
            in >> v;
          if (!in)
            values.assign(4, 0);
        }
      values = dealii::Utilities::MPI::broadcast(comm, values, 0);
      // version, ranks, fixed-size and variable-size data sets, cells
      return {values[1], values[2], values[3]};
    }

    /// A fully distributed mesh whose load() reads the attached cell data of
    /// every rank where save() put them. deal.II 9.4's load() computes each
    /// rank's offset into that file before the mesh exists (zero on every
    /// rank), so every rank reads rank 0's data; this load() reads the data
    /// again at the offsets of save() (the cells of the ranks before, in
    /// units of sizeof(unsigned int) cells, as save() counts them).
    class FullyDistributedTriangulation
      : public dealii::parallel::fullydistributed::Triangulation<3>
    {
    public:
      using Base = dealii::parallel::fullydistributed::Triangulation<3>;
      using Base::Base;
      using Base::load;

      void
      load(const std::string &filename) override
      {
        Base::load(filename);
        const MPI_Comm comm = this->get_communicator();
        const auto     info = read_saved_mesh_info(filename, comm);
        if (info.n_fixed + info.n_variable == 0)
          return;
        const unsigned int n_owned = this->n_locally_owned_active_cells();
        const auto counts = dealii::Utilities::MPI::all_gather(comm, n_owned);
        const unsigned int rank =
          dealii::Utilities::MPI::this_mpi_process(comm);
        const unsigned int before =
          std::accumulate(counts.begin(), counts.begin() + rank, 0u);
        this->data_transfer.clear();
        this->load_attached_data(before * sizeof(unsigned int),
                                 this->n_global_active_cells(),
                                 n_owned,
                                 filename,
                                 info.n_fixed,
                                 info.n_variable);
      }
    };

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
      auto tria = std::make_unique<FullyDistributedTriangulation>(comm);
      tria->create_triangulation(description);
      copy_mid_edge_nodes(serial, *tria);
      return {std::move(tria), std::move(names)};
    }

    /// The tetrahedral path on resume: the partitioned mesh of a checkpoint
    /// (saved by save() of its fully distributed mesh) with its cell data,
    /// and the mid-edge nodes of @p coarse, the mesh it was built from.
    DistributedMesh
    load_fully_distributed(const std::string                 &saved_mesh,
                           const dealii::Triangulation<3, 3> &coarse,
                           BoundaryNames                      names,
                           const MPI_Comm                     comm)
    {
      const auto info = read_saved_mesh_info(saved_mesh, comm);
      AssertThrow(info.n_ranks > 0,
                  dealii::ExcMessage("Cannot read " + saved_mesh +
                                     ".info (the checkpoint's mesh)."));
      const unsigned int n_ranks =
        dealii::Utilities::MPI::n_mpi_processes(comm);
      const std::string folder =
        saved_mesh.substr(0, saved_mesh.find_last_of('/'));
      AssertThrow(info.n_ranks == n_ranks,
                  dealii::ExcMessage(
                    "The checkpoint " + folder +
                    " of a run on a tetrahedral mesh was written on " +
                    std::to_string(info.n_ranks) +
                    " rank(s) and cannot resume on " + std::to_string(n_ranks) +
                    ": a fully distributed mesh keeps the partition it was "
                    "saved with (deal.II 9.4); resume on " +
                    std::to_string(info.n_ranks) + " rank(s)."));
      auto tria = std::make_unique<FullyDistributedTriangulation>(comm);
      tria->load(saved_mesh);
      copy_mid_edge_nodes(coarse, *tria);
      return {std::move(tria), std::move(names)};
    }

    /// Throws for what tetrahedral meshes cannot do yet.
    void
    require_tetrahedral_support(const Parameters &params)
    {
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
        require_tetrahedral_support(params);
        dealii::Triangulation<3, 3> hexahedra;
        BoundaryNames               names = create_mesh(params, hexahedra);
        if (!saved_mesh.empty())
          return load_fully_distributed(saved_mesh,
                                        hexahedra,
                                        std::move(names),
                                        comm);
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
            require_tetrahedral_support(params);
            if (!saved_mesh.empty())
              return load_fully_distributed(saved_mesh,
                                            serial,
                                            std::move(names),
                                            comm);
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
