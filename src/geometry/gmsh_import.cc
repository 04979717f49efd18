#include <deal.II/base/exceptions.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include "geometry/mesh.h"

#include <fstream>
#include <sstream>

namespace systole::Geometry
{
  namespace
  {
    /// Names of the 2D physical groups in the $PhysicalNames block of a .msh
    /// file.
    std::map<std::string, int>
    physical_surface_names(std::istream &in)
    {
      std::map<std::string, int> names;
      std::string                line;
      while (std::getline(in, line))
        if (line.rfind("$PhysicalNames", 0) == 0)
          {
            unsigned int n = 0;
            in >> n;
            std::getline(in, line);
            for (unsigned int i = 0; i < n && std::getline(in, line); ++i)
              {
                std::istringstream entry(line);
                int                dim = -1, tag = -1;
                entry >> dim >> tag;
                const auto first = line.find('"'), last = line.rfind('"');
                if (dim == 2 && first != std::string::npos && last > first)
                  names[line.substr(first + 1, last - first - 1)] = tag;
              }
            break;
          }
      return names;
    }
  } // namespace

  BoundaryNames
  read_gmsh(const std::string           &file,
            const double                 scale,
            dealii::Triangulation<3, 3> &tria)
  {
    std::ifstream in(file);
    AssertThrow(in.good(),
                dealii::ExcMessage(
                  "Geometry / Gmsh / Mesh file: cannot open '" + file + "'."));

    BoundaryNames names("the gmsh mesh '" + file + "'");
    for (const auto &[name, tag] : physical_surface_names(in))
      {
        AssertThrow(tag >= 0 && tag < 255,
                    dealii::ExcMessage("The gmsh mesh '" + file +
                                       "': physical surface '" + name +
                                       "' has tag " + std::to_string(tag) +
                                       "; boundary tags must lie in 0..254."));
        names.add(name, static_cast<dealii::types::boundary_id>(tag));
      }

    in.clear();
    in.seekg(0);
    // Read into a serial mesh first: a tetrahedral mesh cannot enter p4est.
    dealii::Triangulation<3, 3> serial;
    dealii::GridIn<3>           grid_in;
    grid_in.attach_triangulation(serial);
    try
      {
        grid_in.read_msh(in);
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream info;
        e.print_info(info);
        AssertThrow(false,
                    dealii::ExcMessage("The gmsh mesh '" + file +
                                       "' could not be read: " + info.str()));
      }
    const bool hex = serial.all_reference_cells_are_hyper_cube();
    AssertThrow(hex || serial.all_reference_cells_are_simplex(),
                dealii::ExcMessage(
                  "The gmsh mesh '" + file +
                  "' mixes cell shapes; Systole needs all hexahedra or all "
                  "tetrahedra."));
    const bool p4est =
      dynamic_cast<dealii::parallel::distributed::Triangulation<3, 3> *>(
        &tria) != nullptr;
    AssertThrow(
      hex || !p4est,
      dealii::ExcMessage(
        "The gmsh mesh '" + file +
        "' is tetrahedral, and this problem type runs on hexahedral meshes "
        "only so far (tetrahedral meshes run Problem = mechanics)."));
    tria.copy_triangulation(serial);
    if (scale != 1.0)
      dealii::GridTools::scale(scale, tria);
    return names;
  }
} // namespace systole::Geometry
