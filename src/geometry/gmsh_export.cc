#include "geometry/gmsh_export.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/grid/tria.h>

#include "geometry/cell_kind.h"
#include "geometry/point_less.h"

#include <fstream>
#include <iomanip>
#include <map>
#include <set>

namespace systole::Geometry
{
  namespace
  {
    /// One element for the file: its physical tag and its corners.
    struct Element
    {
      int                           tag = 0;
      std::vector<dealii::Point<3>> corners;
    };
  } // namespace

  void
  write_gmsh(const dealii::Triangulation<3, 3> &tria,
             const BoundaryNames               &names,
             const std::string                 &file)
  {
    // gmsh numbers the corners of a hexahedron counter-clockwise around the
    // bottom face, then the top face; deal.II lexicographically. Faces (deal.II
    // lexicographic 0 1 2 3) become the cycle 0 1 3 2. Tetrahedra and
    // triangles keep their order (read_mesh_file() reads them so).
    const bool                      simplex = CellKind(tria).simplex();
    const std::vector<unsigned int> cell_order =
      simplex ? std::vector<unsigned int>{0, 1, 2, 3}
              : std::vector<unsigned int>{0, 1, 3, 2, 4, 5, 7, 6};
    const std::vector<unsigned int> face_order =
      simplex ? std::vector<unsigned int>{0, 1, 2}
              : std::vector<unsigned int>{0, 1, 3, 2};

    // Flatten this rank's locally owned cells and boundary faces: per element
    // [tag, x0, y0, z0, x1, ...]. Physical tags are ids + 1: gmsh reads tag 0
    // as "no physical group".
    std::vector<double> volumes, surfaces;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          volumes.push_back(cell->material_id() + 1);
          for (const unsigned int v : cell_order)
            for (unsigned int d = 0; d < 3; ++d)
              volumes.push_back(cell->vertex(v)[d]);
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              {
                surfaces.push_back(cell->face(f)->boundary_id() + 1);
                for (const unsigned int v : face_order)
                  for (unsigned int d = 0; d < 3; ++d)
                    surfaces.push_back(cell->face(f)->vertex(v)[d]);
              }
        }
    const auto *distributed =
      dynamic_cast<const dealii::parallel::TriangulationBase<3, 3> *>(&tria);
    const MPI_Comm comm =
      distributed ? distributed->get_communicator() : MPI_COMM_SELF;
    const auto all_volumes  = dealii::Utilities::MPI::gather(comm, volumes, 0);
    const auto all_surfaces = dealii::Utilities::MPI::gather(comm, surfaces, 0);

    bool ok = true;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::map<dealii::Point<3>, unsigned int, PointLess> nodes;
        const auto elements = [&](const std::vector<std::vector<double>> &data,
                                  const unsigned int n_corners) {
          std::vector<Element> result;
          for (const auto &rank : data)
            for (std::size_t i = 0; i < rank.size(); i += 1 + 3 * n_corners)
              {
                Element e;
                e.tag = static_cast<int>(rank[i]);
                for (unsigned int c = 0; c < n_corners; ++c)
                  {
                    const dealii::Point<3> p(rank[i + 1 + 3 * c],
                                             rank[i + 2 + 3 * c],
                                             rank[i + 3 + 3 * c]);
                    nodes.emplace(p, 0);
                    e.corners.push_back(p);
                  }
                result.push_back(e);
              }
          return result;
        };
        const auto   cells = elements(all_volumes, cell_order.size());
        const auto   faces = elements(all_surfaces, face_order.size());
        unsigned int index = 0;
        for (auto &[point, number] : nodes)
          number = ++index;
        std::set<int> materials;
        for (const auto &e : cells)
          materials.insert(e.tag);

        std::ofstream out(file);
        ok = out.good();
        out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n"
            << names.names().size() + materials.size() << '\n';
        for (const auto &name : names.names())
          out << "2 " << static_cast<int>(names.id(name)) + 1 << " \"" << name
              << "\"\n";
        for (const int tag : materials)
          out << "3 " << tag << " \""
              << (materials.size() == 1 ? std::string("myocardium")
                                        : "material_" + std::to_string(tag))
              << "\"\n";
        out << "$EndPhysicalNames\n$Nodes\n"
            << nodes.size() << '\n'
            << std::setprecision(17);
        for (const auto &[point, number] : nodes)
          out << number << ' ' << point[0] << ' ' << point[1] << ' ' << point[2]
              << '\n';
        out << "$EndNodes\n$Elements\n" << faces.size() + cells.size() << '\n';
        unsigned int element = 0;
        const auto   write   = [&](const Element &e, const int type) {
          // number, type, 2 tags (physical, elementary), the nodes
          out << ++element << ' ' << type << " 2 " << e.tag << ' ' << e.tag;
          for (const auto &p : e.corners)
            out << ' ' << nodes.at(p);
          out << '\n';
        };
        // gmsh element types: triangle 2, quadrangle 3, tetrahedron 4,
        // hexahedron 5.
        for (const auto &e : faces)
          write(e, simplex ? 2 : 3);
        for (const auto &e : cells)
          write(e, simplex ? 4 : 5);
        out << "$EndElements\n";
        ok = ok && out.good();
      }
    ok = dealii::Utilities::MPI::broadcast(comm, ok, 0);
    AssertThrow(ok,
                dealii::ExcMessage("Cannot write the gmsh file '" + file +
                                   "' (check the output folder)."));
  }
} // namespace systole::Geometry
