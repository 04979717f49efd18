#include <deal.II/base/exceptions.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include "fibres/fibre_field.h"
#include "geometry/mesh.h"
#include "geometry/mesh_checks.h"
#include "geometry/mesh_file.h"

#include <catch2/catch.hpp>
#include <gmsh.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

using namespace systole;
using dealii::Point;

namespace
{
  /// A file in the working directory (the build tree under ctest), removed at
  /// the end of the test.
  struct ScratchFile
  {
    explicit ScratchFile(const std::string &name)
      : name("mesh_file_test_" + name)
    {}
    ~ScratchFile()
    {
      std::filesystem::remove(name);
    }
    std::string name;
  };

  /// A mesh as a file stores it: gmsh/VTK vertex order, 0-based indices (the
  /// writers number nodes and elements from 1 for gmsh).
  struct FileMesh
  {
    bool                                   hexahedra = false;
    std::vector<Point<3>>                  vertices;
    std::vector<std::vector<unsigned int>> cells;
    std::vector<std::vector<unsigned int>> faces;
    std::vector<int>                       face_tags;
    std::map<int, std::string>             names; ///< physical names
  };

  /// The faces of the unit cube are tagged by side: x = 0 -> 1, x = 1 -> 2,
  /// y = 0 -> 3, ..., z = 1 -> 6.
  const std::array<const char *, 6> side_names = {
    {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"}};

  int
  side_of(const Point<3> &centre)
  {
    for (unsigned int d = 0; d < 3; ++d)
      {
        if (std::abs(centre[d]) < 1e-12)
          return 2 * d + 1;
        if (std::abs(centre[d] - 1.0) < 1e-12)
          return 2 * d + 2;
      }
    return 0;
  }

  /// The unit cube in @p n^3 hexahedra, or the same cubes split into
  /// tetrahedra, by deal.II's generators, with its boundary faces tagged by
  /// side_of().
  FileMesh
  unit_cube(const bool hexahedra, const unsigned int n)
  {
    dealii::Triangulation<3> tria;
    if (hexahedra)
      dealii::GridGenerator::subdivided_hyper_cube(tria, n);
    else
      dealii::GridGenerator::subdivided_hyper_cube_with_simplices(tria, n);
    // deal.II's lexicographic hexahedron and quadrilateral to gmsh's cycles.
    const std::array<unsigned int, 8> hex_order  = {{0, 1, 3, 2, 4, 5, 7, 6}};
    const std::array<unsigned int, 4> quad_order = {{0, 1, 3, 2}};

    FileMesh mesh;
    mesh.hexahedra = hexahedra;
    mesh.vertices  = tria.get_vertices();
    for (const auto &cell : tria.active_cell_iterators())
      {
        std::vector<unsigned int> vertices;
        for (unsigned int v = 0; v < cell->n_vertices(); ++v)
          vertices.push_back(cell->vertex_index(hexahedra ? hex_order[v] : v));
        mesh.cells.push_back(vertices);
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              std::vector<unsigned int> f;
              for (unsigned int v = 0; v < face->n_vertices(); ++v)
                f.push_back(face->vertex_index(hexahedra ? quad_order[v] : v));
              mesh.faces.push_back(f);
              mesh.face_tags.push_back(side_of(face->center()));
            }
      }
    for (unsigned int s = 0; s < 6; ++s)
      mesh.names[s + 1] = side_names[s];
    return mesh;
  }

  /// gmsh format 2.2, ASCII, by hand: faces then cells, elementary tag = the
  /// physical tag.
  void
  write_msh22(const FileMesh &mesh, const std::string &file)
  {
    std::ofstream out(file);
    out << std::setprecision(17);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
    out << "$PhysicalNames\n" << mesh.names.size() + 1 << "\n";
    for (const auto &[tag, name] : mesh.names)
      out << "2 " << tag << " \"" << name << "\"\n";
    out << "3 100 \"volume\"\n$EndPhysicalNames\n";
    out << "$Nodes\n" << mesh.vertices.size() << "\n";
    for (unsigned int v = 0; v < mesh.vertices.size(); ++v)
      out << v + 1 << " " << mesh.vertices[v] << "\n";
    out << "$EndNodes\n$Elements\n"
        << mesh.faces.size() + mesh.cells.size() << "\n";
    unsigned int id = 0;
    for (unsigned int f = 0; f < mesh.faces.size(); ++f)
      {
        out << ++id << " " << (mesh.faces[f].size() == 3 ? 2 : 3) << " 2 "
            << mesh.face_tags[f] << " " << mesh.face_tags[f];
        for (const unsigned int v : mesh.faces[f])
          out << " " << v + 1;
        out << "\n";
      }
    for (const auto &cell : mesh.cells)
      {
        out << ++id << " " << (mesh.hexahedra ? 5 : 4) << " 2 100 100";
        for (const unsigned int v : cell)
          out << " " << v + 1;
        out << "\n";
      }
    out << "$EndElements\n";
  }

  /// Through the gmsh API: one discrete volume and one discrete surface per
  /// face tag, with physical groups and names; msh @p version, ASCII or
  /// binary.
  void
  write_msh_api(const FileMesh    &mesh,
                const std::string &file,
                const double       version,
                const bool         binary)
  {
    const Geometry::GmshSession session;
    gmsh::model::add("mesh_file_test");
    const int                volume = gmsh::model::addDiscreteEntity(3);
    std::vector<std::size_t> node_tags;
    std::vector<double>      coordinates;
    for (unsigned int v = 0; v < mesh.vertices.size(); ++v)
      {
        node_tags.push_back(v + 1);
        for (unsigned int d = 0; d < 3; ++d)
          coordinates.push_back(mesh.vertices[v][d]);
      }
    gmsh::model::mesh::addNodes(3, volume, node_tags, coordinates);
    std::size_t              element = 0;
    std::vector<std::size_t> cell_tags, cell_nodes;
    for (const auto &cell : mesh.cells)
      {
        cell_tags.push_back(++element);
        for (const unsigned int v : cell)
          cell_nodes.push_back(v + 1);
      }
    gmsh::model::mesh::addElementsByType(volume,
                                         mesh.hexahedra ? 5 : 4,
                                         cell_tags,
                                         cell_nodes);
    gmsh::model::addPhysicalGroup(3, {volume}, 100);
    for (const auto &[tag, name] : mesh.names)
      {
        const int                surface = gmsh::model::addDiscreteEntity(2);
        std::vector<std::size_t> face_tags, face_nodes;
        for (unsigned int f = 0; f < mesh.faces.size(); ++f)
          if (mesh.face_tags[f] == tag)
            {
              face_tags.push_back(++element);
              for (const unsigned int v : mesh.faces[f])
                face_nodes.push_back(v + 1);
            }
        gmsh::model::mesh::addElementsByType(surface,
                                             mesh.hexahedra ? 3 : 2,
                                             face_tags,
                                             face_nodes);
        gmsh::model::addPhysicalGroup(2, {surface}, tag);
        gmsh::model::setPhysicalName(2, tag, name);
      }
    gmsh::option::setNumber("Mesh.MshFileVersion", version);
    gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
    gmsh::write(file);
    gmsh::option::setNumber("Mesh.Binary", 0);
    gmsh::model::remove();
  }

  /// A .vtu file by VTK's writer: the cells, then (if @p with_faces) the
  /// faces, with the integer cell array "faces" (0 on volume cells).
  void
  write_vtu(const FileMesh    &mesh,
            const std::string &file,
            const bool         with_faces = true)
  {
    vtkNew<vtkUnstructuredGrid> grid;
    vtkNew<vtkPoints>           points;
    for (const auto &x : mesh.vertices)
      points->InsertNextPoint(x[0], x[1], x[2]);
    grid->SetPoints(points);
    vtkNew<vtkIntArray> tags;
    tags->SetName("faces");
    for (const auto &cell : mesh.cells)
      {
        std::vector<vtkIdType> ids(cell.begin(), cell.end());
        grid->InsertNextCell(mesh.hexahedra ? VTK_HEXAHEDRON : VTK_TETRA,
                             ids.size(),
                             ids.data());
        tags->InsertNextValue(0);
      }
    if (with_faces)
      for (unsigned int f = 0; f < mesh.faces.size(); ++f)
        {
          std::vector<vtkIdType> ids(mesh.faces[f].begin(),
                                     mesh.faces[f].end());
          grid->InsertNextCell(mesh.hexahedra ? VTK_QUAD : VTK_TRIANGLE,
                               ids.size(),
                               ids.data());
          tags->InsertNextValue(mesh.face_tags[f]);
        }
    grid->GetCellData()->AddArray(tags);
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(file.c_str());
    writer->SetInputData(grid);
    REQUIRE(writer->Write() == 1);
  }

  double
  volume(const dealii::Triangulation<3> &tria)
  {
    double sum = 0;
    for (const auto &cell : tria.active_cell_iterators())
      sum += cell->measure();
    return sum;
  }

  /// Every boundary face has the id of its side (in the read mesh: by the
  /// face's centre, @p scale times the unit cube).
  bool
  sides_have_their_ids(const dealii::Triangulation<3> &tria,
                       const Geometry::BoundaryNames  &names,
                       const double                    scale = 1.0)
  {
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            const int side = side_of(face->center() / scale);
            if (side == 0 ||
                face->boundary_id() != names.id(side_names[side - 1]))
              return false;
          }
    return true;
  }

  std::string
  format_point(const Point<3> &p)
  {
    std::ostringstream o;
    o << std::setprecision(6) << "(" << p[0] << ", " << p[1] << ", " << p[2]
      << ")";
    return o.str();
  }

  /// The message of the deal.II exception @p read throws.
  template <class F>
  std::string
  error_of(const F &read)
  {
    try
      {
        read();
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream o;
        e.print_info(o);
        return o.str();
      }
    return "(no error)";
  }

  /// Read @p file into a fresh serial mesh; return the error message.
  std::string
  read_error(const std::string               &file,
             const Geometry::MeshFileOptions &options = {})
  {
    return error_of([&]() {
      dealii::Triangulation<3> tria;
      Geometry::read_mesh_file(file, options, tria);
    });
  }

  /// The message is one line (a trailing newline aside).
  bool
  one_line(std::string message)
  {
    while (!message.empty() &&
           (message.back() == '\n' || message.back() == ' '))
      message.pop_back();
    return message.find('\n') == std::string::npos;
  }
} // namespace

TEST_CASE("A tetrahedral cube reads from gmsh 2.2 and 4.1, ASCII and binary, "
          "and from .vtu, with its tagged faces",
          "[geometry][mesh_file]")
{
  const FileMesh mesh = unit_cube(false, 2);
  ScratchFile    file("cube.msh"), vtu("cube.vtu");
  for (const std::string format :
       {"2.2 text", "2.2 api", "2.2 binary", "4.1 ascii", "4.1 binary", "vtu"})
    {
      SECTION(format)
      {
        std::string name = file.name;
        if (format == "2.2 text")
          write_msh22(mesh, name);
        else if (format == "vtu")
          write_vtu(mesh, name = vtu.name);
        else
          write_msh_api(mesh,
                        name,
                        format[0] == '2' ? 2.2 : 4.1,
                        format.find("binary") != std::string::npos);

        Geometry::MeshFileOptions options;
        if (format == "vtu")
          {
            options.face_tag_array = "faces";
            for (unsigned int s = 0; s < 6; ++s)
              options.boundary_names.emplace_back(side_names[s],
                                                  std::to_string(s + 1));
          }
        dealii::Triangulation<3> tria;
        const auto names = Geometry::read_mesh_file(name, options, tria);
        CHECK(tria.n_active_cells() == mesh.cells.size());
        CHECK(tria.n_vertices() == mesh.vertices.size());
        CHECK(tria.all_reference_cells_are_simplex());
        CHECK(volume(tria) == Approx(1.0).epsilon(1e-12));
        CHECK(names.names().size() == 6);
        CHECK(sides_have_their_ids(tria, names));
        for (unsigned int s = 0; s < 6; ++s)
          CHECK(names.id(side_names[s]) == s + 1);
      }
    }
}

TEST_CASE("A hexahedral cube reads from gmsh and .vtu, scaled to mm",
          "[geometry][mesh_file]")
{
  const FileMesh mesh = unit_cube(true, 3);
  ScratchFile    file("hex.msh"), vtu("hex.vtu");
  write_msh22(mesh, file.name);
  write_vtu(mesh, vtu.name);
  for (const double scale : {1.0, 10.0})
    {
      dealii::Triangulation<3> tria;
      const auto names = Geometry::read_gmsh(file.name, scale, tria);
      CHECK(tria.n_active_cells() == 27);
      CHECK(tria.all_reference_cells_are_hyper_cube());
      CHECK(volume(tria) == Approx(std::pow(scale, 3)).epsilon(1e-12));
      CHECK(sides_have_their_ids(tria, names, scale));
    }
  Geometry::MeshFileOptions options;
  options.face_tag_array = "faces";
  options.boundary_names = Geometry::parse_boundary_name_table(
    "x_min: 1; x_max: 2; y_min: 3; y_max: 4; z_min: 5; z_max: 6",
    "test");
  dealii::Triangulation<3> tria;
  const auto names = Geometry::read_mesh_file(vtu.name, options, tria);
  CHECK(tria.n_active_cells() == 27);
  CHECK(volume(tria) == Approx(1.0).epsilon(1e-12));
  CHECK(sides_have_their_ids(tria, names));

  // A hexahedral mesh also goes into a distributed mesh.
  dealii::parallel::distributed::Triangulation<3> distributed(MPI_COMM_WORLD);
  const auto d_names = Geometry::read_gmsh(file.name, 1.0, distributed);
  CHECK(distributed.n_global_active_cells() == 27);
  CHECK(d_names.id("z_max") == 6);
}

TEST_CASE("The name table maps parts to the file's names or tags, and the "
          "other faces get the default id",
          "[geometry][mesh_file]")
{
  const FileMesh mesh = unit_cube(false, 1);
  ScratchFile    file("table.msh");
  write_msh22(mesh, file.name);

  Geometry::MeshFileOptions options;
  options.boundary_names =
    Geometry::parse_boundary_name_table(" base : z_min ;apex: 6; ",
                                        "Geometry / Gmsh / Boundary names");
  REQUIRE(options.boundary_names.size() == 2);
  CHECK(options.boundary_names[0].first == "base");
  CHECK(options.boundary_names[0].second == "z_min");
  dealii::Triangulation<3> tria;
  const auto names = Geometry::read_mesh_file(file.name, options, tria);
  CHECK(names.names() == std::vector<std::string>{"apex", "base"});
  CHECK(names.id("base") == 5);
  CHECK(names.id("apex") == 6);
  // No used tag is 0: the untagged faces get 0.
  std::map<unsigned int, unsigned int> n_faces;
  for (const auto &cell : tria.active_cell_iterators())
    for (const auto &face : cell->face_iterators())
      if (face->at_boundary())
        {
          ++n_faces[face->boundary_id()];
          const int side = side_of(face->center());
          CHECK(face->boundary_id() == (side == 5 ? 5u : side == 6 ? 6u : 0u));
        }
  CHECK(n_faces.size() == 3);

  SECTION("a used tag 0 moves the default id")
  {
    // gmsh reads physical tag 0 as "no group": a zero tag comes from a .vtu.
    FileMesh zero = mesh;
    for (auto &tag : zero.face_tags)
      if (tag == 1)
        tag = 0;
    ScratchFile vtu("zero.vtu");
    write_vtu(zero, vtu.name);
    Geometry::MeshFileOptions o;
    o.face_tag_array        = "faces";
    o.boundary_names        = {{"left", "0"}, {"right", "2"}};
    const auto         data = Geometry::read_vtu_data(vtu.name, "faces");
    const unsigned int default_id =
      Geometry::default_boundary_id(data, o.boundary_names);
    CHECK(default_id == 1);
    dealii::Triangulation<3> t;
    const auto               n = Geometry::read_mesh_file(vtu.name, o, t);
    CHECK(n.id("left") == 0);
    CHECK(n.id("right") == 2);
    for (const auto &cell : t.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            const int side = side_of(face->center());
            CHECK(face->boundary_id() == (side == 1   ? 0u
                                          : side == 2 ? 2u
                                                      : default_id));
          }
  }
}

TEST_CASE("A table entry that names no face is one clear error",
          "[geometry][mesh_file][errors]")
{
  const FileMesh mesh = unit_cube(false, 1);
  ScratchFile    file("noface.msh");
  write_msh22(mesh, file.name);
  Geometry::MeshFileOptions options;
  options.boundary_names = {{"base", "z_min"}, {"endocardium", "ENDO"}};
  std::string message    = read_error(file.name, options);
  CHECK(one_line(message));
  CHECK_THAT(message,
             Catch::Contains("'endocardium: ENDO' names no face") &&
               Catch::Contains(file.name) &&
               Catch::Contains("1 x_min, 2 x_max"));
  options.boundary_names = {{"endocardium", "42"}};
  message                = read_error(file.name, options);
  CHECK_THAT(message,
             Catch::Contains("'endocardium: 42' names no boundary face") &&
               Catch::Contains("face tag 42"));
  // Bad table text.
  CHECK_THROWS_WITH(Geometry::parse_boundary_name_table("base BASE", "E"),
                    Catch::Contains("E: 'base BASE' is not of the form"));
  CHECK_THROWS_WITH(Geometry::parse_boundary_name_table("a: 1; a: 2", "E"),
                    Catch::Contains("part 'a' is named twice"));
}

TEST_CASE("Inverted and flat tetrahedra are one clear error",
          "[geometry][mesh_file][errors]")
{
  FileMesh    mesh = unit_cube(false, 2);
  ScratchFile file("inverted.msh");
  // Invert cells 3 and 7 (0-based; gmsh element numbers count the faces
  // first).
  for (const unsigned int c : {3u, 7u})
    std::swap(mesh.cells[c][0], mesh.cells[c][1]);
  write_msh22(mesh, file.name);
  const std::string message = read_error(file.name);
  CHECK(one_line(message));
  CHECK_THAT(message,
             Catch::Contains(file.name) &&
               Catch::Contains("2 of its " + std::to_string(mesh.cells.size()) +
                               " tetrahedra are inverted or flat") &&
               Catch::Contains("element " +
                               std::to_string(mesh.faces.size() + 3 + 1)) &&
               Catch::Contains(format_point(mesh.vertices[mesh.cells[3][0]])));

  // One flat tetrahedron.
  FileMesh flat;
  flat.vertices = {Point<3>(0, 0, 0),
                   Point<3>(1, 0, 0),
                   Point<3>(0, 1, 0),
                   Point<3>(0.3, 0.3, 0)};
  flat.cells    = {{0, 1, 2, 3}};
  write_msh22(flat, file.name);
  CHECK_THAT(read_error(file.name),
             Catch::Contains("1 of its 1 tetrahedra are inverted or flat") &&
               Catch::Contains("(0.3, 0.3, 0)"));
}

TEST_CASE("A hexahedron with a negative Jacobian at a vertex is one clear "
          "error",
          "[geometry][mesh_file][errors]")
{
  FileMesh mesh = unit_cube(true, 1);
  // gmsh vertex 6 is (1, 1, 1): pull it inside, beyond the centre.
  REQUIRE(mesh.vertices[mesh.cells[0][6]].distance(Point<3>(1, 1, 1)) == 0);
  mesh.vertices[mesh.cells[0][6]] = Point<3>(0.2, 0.2, 0.2);
  ScratchFile file("tangled.msh");
  write_msh22(mesh, file.name);
  const std::string message = read_error(file.name);
  CHECK(one_line(message));
  CHECK_THAT(message,
             Catch::Contains("1 of its 1 hexahedra have a non-positive "
                             "Jacobian at a vertex") &&
               Catch::Contains("at its vertex (0.2, 0.2, 0.2)"));
}

TEST_CASE("Duplicate nodes are one clear error",
          "[geometry][mesh_file][errors]")
{
  FileMesh mesh = unit_cube(false, 2);
  // A copy of the centre node, used by one cell instead of the centre.
  unsigned int centre = 0;
  while (mesh.vertices[centre].distance(Point<3>(0.5, 0.5, 0.5)) > 1e-12)
    ++centre;
  unsigned int cell = 0;
  while (std::find(mesh.cells[cell].begin(), mesh.cells[cell].end(), centre) ==
         mesh.cells[cell].end())
    ++cell;
  mesh.vertices.push_back(mesh.vertices[centre] + Point<3>(1e-13, 0, 0));
  std::replace(mesh.cells[cell].begin(),
               mesh.cells[cell].end(),
               centre,
               static_cast<unsigned int>(mesh.vertices.size() - 1));
  ScratchFile file("duplicate.msh");
  write_msh22(mesh, file.name);
  const std::string message = read_error(file.name);
  CHECK(one_line(message));
  CHECK_THAT(message,
             Catch::Contains("1 pairs of nodes coincide") &&
               Catch::Contains("nodes " + std::to_string(centre + 1) + " and " +
                               std::to_string(mesh.vertices.size())) &&
               Catch::Contains("(0.5, 0.5, 0.5)"));
}

TEST_CASE("Unused nodes are one clear error", "[geometry][mesh_file][errors]")
{
  FileMesh mesh = unit_cube(false, 1);
  mesh.vertices.push_back(Point<3>(2, 3, 4));
  mesh.vertices.push_back(Point<3>(5, 6, 7));
  // gmsh drops unused nodes of format 2.2; VTK keeps every point.
  ScratchFile file("unused.vtu");
  write_vtu(mesh, file.name);
  const std::string message = read_error(file.name);
  CHECK(one_line(message));
  CHECK_THAT(
    message,
    Catch::Contains("2 of its " + std::to_string(mesh.vertices.size()) +
                    " nodes belong to no tetrahedron") &&
      Catch::Contains("node " + std::to_string(mesh.vertices.size() - 2)) &&
      Catch::Contains("(2, 3, 4)"));
}

TEST_CASE("Mixed, pyramid and face-less meshes are clear errors",
          "[geometry][mesh_file][errors]")
{
  ScratchFile file("mixed.msh");
  {
    std::ofstream out(file.name);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n"
           "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n"
           "8 0 1 1\n9 0 0 2\n$EndNodes\n$Elements\n2\n"
           "1 5 2 1 1 1 2 3 4 5 6 7 8\n2 4 2 1 1 5 6 8 9\n$EndElements\n";
  }
  CHECK_THAT(read_error(file.name),
             Catch::Contains("mixes 1 tetrahedra and 1 hexahedra"));
  {
    std::ofstream out(file.name);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n"
           "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0.5 1\n$EndNodes\n"
           "$Elements\n1\n1 7 2 1 1 1 2 3 4 5\n$EndElements\n";
  }
  CHECK_THAT(read_error(file.name),
             Catch::Contains("has 1 ") &&
               Catch::Contains("(gmsh element type 7)") &&
               Catch::Contains("Mesh.ElementOrder = 1 or 2"));

  // A .vtu with volume cells only cannot tag faces.
  const FileMesh            mesh = unit_cube(false, 1);
  ScratchFile               vtu("volume_only.vtu");
  Geometry::MeshFileOptions options;
  options.face_tag_array = "faces";
  write_vtu(mesh, vtu.name, /*with_faces=*/false);
  std::string message = read_error(vtu.name, options);
  CHECK(one_line(message));
  CHECK_THAT(message, Catch::Contains("has only volume cells"));
  options.face_tag_array = "labels";
  CHECK_THAT(read_error(vtu.name, options),
             Catch::Contains("no cell-data array 'labels'") &&
               Catch::Contains("'faces'"));
  // Without a face tag array it reads, every boundary face with id 0.
  dealii::Triangulation<3> tria;
  const auto               names = Geometry::read_mesh_file(vtu.name, {}, tria);
  CHECK(names.names().empty());
  for (const auto &face : tria.active_face_iterators())
    if (face->at_boundary())
      CHECK(face->boundary_id() == 0);

  // Tetrahedra do not go into a distributed mesh.
  ScratchFile tets("tets.msh");
  write_msh22(mesh, tets.name);
  CHECK_THAT(error_of([&]() {
               dealii::parallel::distributed::Triangulation<3> d(
                 MPI_COMM_WORLD);
               Geometry::read_gmsh(tets.name, 1.0, d);
             }),
             Catch::Contains("cannot hold"));
  CHECK_THAT(read_error("no_such_file.msh"), Catch::Contains("cannot open"));
  CHECK_THAT(read_error(file.name + ".stl"), Catch::Contains("'.stl'"));
}

TEST_CASE("Reading gmsh files repeatedly and inside a session is safe",
          "[geometry][mesh_file]")
{
  const FileMesh mesh = unit_cube(false, 1);
  ScratchFile    file("repeat.msh"), bad("bad.msh");
  write_msh22(mesh, file.name);
  std::ofstream(bad.name) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  for (unsigned int i = 0; i < 3; ++i)
    {
      dealii::Triangulation<3> tria;
      Geometry::read_gmsh(file.name, 1.0, tria);
      CHECK(tria.n_active_cells() == mesh.cells.size());
      // A failed read leaves gmsh usable for the next one.
      CHECK_THAT(read_error(bad.name), Catch::Contains("gmsh could not read"));
    }
  const Geometry::GmshSession session;
  gmsh::model::add("caller");
  dealii::Triangulation<3> tria;
  Geometry::read_gmsh(file.name, 1.0, tria);
  std::string current;
  gmsh::model::getCurrent(current);
  CHECK(current == "caller");
  gmsh::model::remove();
}

TEST_CASE("Surfaces of boundary parts: closed, open, holed and non-manifold",
          "[geometry][mesh_checks]")
{
  // The cube's x_max side is a disc (one rim loop); all sides together are
  // closed; x_max without its centre square is an annulus.
  FileMesh mesh = unit_cube(false, 3);
  mesh.names[7] = "shell";
  mesh.names[8] = "centre";
  ScratchFile file("surfaces.msh");
  FileMesh    shell = mesh;
  for (unsigned int f = 0; f < shell.faces.size(); ++f)
    {
      Point<3> c;
      for (const unsigned int v : shell.faces[f])
        c += shell.vertices[v] / 3.0;
      if (shell.face_tags[f] == 2 && std::abs(c[1] - 0.5) < 1.0 / 6 &&
          std::abs(c[2] - 0.5) < 1.0 / 6)
        shell.face_tags[f] = 8;
    }
  write_msh22(shell, file.name);
  dealii::Triangulation<3> tria;
  const auto               names = Geometry::read_gmsh(file.name, 1.0, tria);
  const auto x_min = Geometry::surface_topology(tria, names.id("x_min"));
  CHECK(x_min.n_faces == 18);
  CHECK(x_min.n_rim_edges == 12);
  CHECK(x_min.n_rim_loops == 1);
  CHECK(x_min.n_non_manifold_edges == 0);
  CHECK_NOTHROW(Geometry::check_part_surface(tria, names, "x_min", 1));
  const auto x_max = Geometry::surface_topology(tria, names.id("x_max"));
  CHECK(x_max.n_faces == 16);
  CHECK(x_max.n_rim_loops == 2);
  const std::string message =
    error_of([&]() { Geometry::check_part_surface(tria, names, "x_max", 1); });
  CHECK(one_line(message));
  CHECK_THAT(message,
             Catch::Contains("Boundary part 'x_max'") &&
               Catch::Contains(file.name) &&
               Catch::Contains("has 2 rim loops") &&
               Catch::Contains("the smallest has 4 edges"));

  // All sides as one part: closed.
  FileMesh closed = mesh;
  for (auto &tag : closed.face_tags)
    tag = 7;
  write_msh22(closed, file.name);
  dealii::Triangulation<3> closed_tria;
  const auto closed_names = Geometry::read_gmsh(file.name, 1.0, closed_tria);
  CHECK_NOTHROW(
    Geometry::check_part_surface(closed_tria, closed_names, "shell", 0));
  CHECK_THAT(error_of([&]() {
               Geometry::check_part_surface(closed_tria,
                                            closed_names,
                                            "shell",
                                            1);
             }),
             Catch::Contains("has 0 rim loops"));

  // Two squares of a side that touch at one vertex: the rim is pinched.
  FileMesh pinched = unit_cube(true, 2);
  for (unsigned int f = 0; f < pinched.faces.size(); ++f)
    {
      Point<3> c;
      for (const unsigned int v : pinched.faces[f])
        c += pinched.vertices[v] / 4.0;
      if (pinched.face_tags[f] == 1 && (c[1] - 0.5) * (c[2] - 0.5) > 0)
        pinched.face_tags[f] = 7;
    }
  pinched.names[7] = "pinch";
  write_msh22(pinched, file.name);
  dealii::Triangulation<3> pinched_tria;
  const auto pinched_names = Geometry::read_gmsh(file.name, 1.0, pinched_tria);
  const auto pinch =
    Geometry::surface_topology(pinched_tria, pinched_names.id("pinch"));
  CHECK(pinch.n_faces == 2);
  CHECK(pinch.n_rim_edges == 8);
  CHECK(pinch.n_rim_junctions == 1);
  CHECK_THAT(error_of([&]() {
               Geometry::check_part_surface(pinched_tria,
                                            pinched_names,
                                            "pinch",
                                            1);
             }),
             Catch::Contains("is pinched") &&
               Catch::Contains("the first at (0, 0.5, 0.5) has 4 rim edges"));

  // Two cubes that share one edge: the edge is in four faces of the part.
  FileMesh pair;
  pair.hexahedra = true;
  for (unsigned int c = 0; c < 2; ++c)
    for (unsigned int k = 0; k < 2; ++k)
      for (const auto &[i, j] :
           std::vector<std::pair<int, int>>{{0, 0}, {1, 0}, {1, 1}, {0, 1}})
        pair.vertices.emplace_back(c + i, c + j, k);
  pair.cells = {{0, 1, 2, 3, 4, 5, 6, 7}, {8, 9, 10, 11, 12, 13, 14, 15}};
  // The shared edge: (1, 1, z) is vertex 2 / 6 of the first cube and 8 / 12
  // of the second: merge them.
  for (auto &v : pair.cells[1])
    v = v == 8 ? 2 : v == 12 ? 6 : v;
  pair.vertices.erase(pair.vertices.begin() + 12);
  pair.vertices.erase(pair.vertices.begin() + 8);
  for (auto &v : pair.cells[1])
    v = v > 12 ? v - 2 : v > 8 ? v - 1 : v;
  const std::array<std::array<unsigned int, 4>, 6> hex_faces = {
    {{{0, 3, 7, 4}},
     {{1, 2, 6, 5}},
     {{0, 1, 5, 4}},
     {{3, 2, 6, 7}},
     {{0, 1, 2, 3}},
     {{4, 5, 6, 7}}}};
  for (const auto &cell : pair.cells)
    for (const auto &face : hex_faces)
      {
        pair.faces.push_back(
          {cell[face[0]], cell[face[1]], cell[face[2]], cell[face[3]]});
        pair.face_tags.push_back(1);
      }
  pair.names[1] = "surface";
  write_msh22(pair, file.name);
  dealii::Triangulation<3> pair_tria;
  const auto pair_names = Geometry::read_gmsh(file.name, 1.0, pair_tria);
  CHECK(volume(pair_tria) == Approx(2.0));
  const auto pair_topology =
    Geometry::surface_topology(pair_tria, pair_names.id("surface"));
  CHECK(pair_topology.n_faces == 12);
  CHECK(pair_topology.n_non_manifold_edges == 1);
  const std::string non_manifold = error_of([&]() {
    Geometry::check_part_surface(pair_tria, pair_names, "surface", 0);
  });
  CHECK(one_line(non_manifold));
  CHECK_THAT(non_manifold,
             Catch::Contains("is not a manifold surface: 1 of its edges") &&
               Catch::Contains("(1, 1, 0)") && Catch::Contains("(1, 1, 1)"));

  // The same surface as a cavity (with a base part of no faces): the
  // cavity check names the non-manifold edge before the open rim.
  auto cavity_names = pair_names;
  cavity_names.add("base", 42);
  const std::string cavity = error_of([&]() {
    Geometry::check_cavity_rim(pair_tria, cavity_names, "surface", "base");
  });
  CHECK(one_line(cavity));
  CHECK_THAT(cavity,
             Catch::Contains("The cavity 'surface'") &&
               Catch::Contains("is not a manifold surface: 1 of its edges") &&
               Catch::Contains("(1, 1, 0)") && Catch::Contains("(1, 1, 1)"));
}

TEST_CASE("A cavity open away from its base names the count and the first "
          "edge",
          "[geometry][mesh_file][errors]")
{
  // The cube as a cavity closed by its top: every side but z_max is the
  // cavity, z_max the base.
  ScratchFile file("open_cavity.msh");
  FileMesh    mesh = unit_cube(false, 3);
  for (auto &tag : mesh.face_tags)
    tag = tag == 6 ? 6 : 7;
  mesh.names = {{6, "base"}, {7, "cavity"}, {8, "epicardium"}};
  write_msh22(mesh, file.name);
  dealii::Triangulation<3> tria;
  const auto               names = Geometry::read_gmsh(file.name, 1.0, tria);
  CHECK_NOTHROW(Geometry::check_cavity_rim(tria, names, "cavity", "base"));

  // The middle square of x_max tagged as another part: a hole in the
  // cavity, its 4 edges a rim that is not on the base.
  for (unsigned int f = 0; f < mesh.faces.size(); ++f)
    {
      Point<3> c;
      for (const unsigned int v : mesh.faces[f])
        c += mesh.vertices[v] / 3.0;
      if (std::abs(c[0] - 1) < 1e-12 && std::abs(c[1] - 0.5) < 1.0 / 6 &&
          std::abs(c[2] - 0.5) < 1.0 / 6)
        mesh.face_tags[f] = 8;
    }
  write_msh22(mesh, file.name);
  dealii::Triangulation<3> open_tria;
  const auto        open_names = Geometry::read_gmsh(file.name, 1.0, open_tria);
  const std::string message    = error_of([&]() {
    Geometry::check_cavity_rim(open_tria, open_names, "cavity", "base");
  });
  CHECK(one_line(message));
  CHECK_THAT(message,
             Catch::Contains("The cavity 'cavity'") &&
               Catch::Contains(file.name) &&
               Catch::Contains("is open away from its lid, the part 'base': "
                               "4 edges of its rim") &&
               Catch::Contains("the first joins (1, 0.333333, 0.333333)"));
}

TEST_CASE("A part that no boundary face carries names the part, the file and "
          "the parts",
          "[geometry][mesh_file][errors]")
{
  // A physical surface of interior faces only: the faces between the two
  // halves x < 0.5 and x > 0.5 of a tetrahedral cube.
  dealii::Triangulation<3> generated;
  dealii::GridGenerator::subdivided_hyper_cube_with_simplices(generated, 2);
  FileMesh mesh = unit_cube(false, 2);
  for (const auto &cell : generated.active_cell_iterators())
    for (const auto &face : cell->face_iterators())
      if (!face->at_boundary() && std::abs(face->center()[0] - 0.5) < 1e-12)
        {
          mesh.faces.push_back({face->vertex_index(0),
                                face->vertex_index(1),
                                face->vertex_index(2)});
          mesh.face_tags.push_back(9);
        }
  mesh.names[9] = "septum";
  ScratchFile file("septum.msh");
  write_msh22(mesh, file.name);
  dealii::Triangulation<3> tria;
  const auto               names = Geometry::read_gmsh(file.name, 1.0, tria);
  CHECK(names.has("septum"));
  CHECK_NOTHROW(Geometry::require_boundary(tria, names, "x_min"));
  const std::string message =
    error_of([&]() { Geometry::require_boundary(tria, names, "septum"); });
  CHECK_THAT(message,
             Catch::Contains("'septum'") && Catch::Contains(file.name) &&
               Catch::Contains("its parts: septum, x_max, x_min"));
  // Named in the table, it is an error when reading.
  Geometry::MeshFileOptions options;
  options.boundary_names = {{"septum", "septum"}};
  CHECK_THAT(read_error(file.name, options),
             Catch::Contains("'septum: septum' names no boundary face"));
}

TEST_CASE("Every shipped gmsh mesh reads as deal.II's own reader reads it",
          "[geometry][mesh_file]")
{
  for (const auto &entry :
       std::filesystem::directory_iterator(SYSTOLE_SOURCE_DIR "/meshes"))
    // deal.II 9.4's GridIn reads first-order cells only: the second-order
    // meshes (*_p2.msh) are checked by the 10-node tests.
    if (entry.path().extension() == ".msh" &&
        entry.path().stem().string().find("_p2") == std::string::npos)
      {
        const std::string file = entry.path().string();
        INFO(file);
        dealii::Triangulation<3> reference;
        dealii::GridIn<3>        grid_in;
        grid_in.attach_triangulation(reference);
        std::ifstream in(file);
        grid_in.read_msh(in);

        dealii::Triangulation<3> tria;
        const auto               names = Geometry::read_gmsh(file, 1.0, tria);
        CHECK(tria.n_active_cells() == reference.n_active_cells());
        CHECK(tria.n_vertices() == reference.n_vertices());
        CHECK(volume(tria) == Approx(volume(reference)).epsilon(1e-12));
        std::map<unsigned int, unsigned int> faces, reference_faces;
        for (const auto &face : tria.active_face_iterators())
          if (face->at_boundary())
            ++faces[face->boundary_id()];
        for (const auto &face : reference.active_face_iterators())
          if (face->at_boundary())
            ++reference_faces[face->boundary_id()];
        CHECK(faces == reference_faces);
        for (const auto &name : names.names())
          CHECK(faces.count(names.id(name)) == 1);
      }
}

TEST_CASE("Per-cell vectors of a .vtu file come in the mesh's cell order",
          "[geometry][mesh_file][fibres]")
{
  const FileMesh mesh = unit_cube(false, 2);
  // A cell array: a direction that varies with the cell's centre; a point
  // array: one direction with the sign flipped at every other vertex.
  const auto field = [](const Point<3> &x) {
    return dealii::Tensor<1, 3>({1.0, 2.0 * x[0] - x[1], 0.5 + x[2]});
  };
  const dealii::Tensor<1, 3>  direction({1.0 / 3, 2.0 / 3, 2.0 / 3});
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints>           points;
  vtkNew<vtkDoubleArray>      cell_vectors, point_vectors;
  cell_vectors->SetName("fibres");
  cell_vectors->SetNumberOfComponents(3);
  point_vectors->SetName("directions");
  point_vectors->SetNumberOfComponents(3);
  for (unsigned int v = 0; v < mesh.vertices.size(); ++v)
    {
      points->InsertNextPoint(mesh.vertices[v][0],
                              mesh.vertices[v][1],
                              mesh.vertices[v][2]);
      const dealii::Tensor<1, 3> d = (v % 2 == 0 ? 1.0 : -1.0) * direction;
      point_vectors->InsertNextTuple3(d[0], d[1], d[2]);
    }
  grid->SetPoints(points);
  // A boundary triangle first: its tuple must be skipped.
  std::vector<vtkIdType> face(mesh.faces[0].begin(), mesh.faces[0].end());
  grid->InsertNextCell(VTK_TRIANGLE, 3, face.data());
  cell_vectors->InsertNextTuple3(0, 0, 0);
  for (const auto &cell : mesh.cells)
    {
      std::vector<vtkIdType> ids(cell.begin(), cell.end());
      grid->InsertNextCell(VTK_TETRA, 4, ids.data());
      Point<3> centre;
      for (const unsigned int v : cell)
        centre += mesh.vertices[v] / 4.0;
      const auto f = field(centre);
      cell_vectors->InsertNextTuple3(f[0], f[1], f[2]);
    }
  grid->GetCellData()->AddArray(cell_vectors);
  grid->GetPointData()->AddArray(point_vectors);
  ScratchFile                          file("vectors.vtu");
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(file.name.c_str());
  writer->SetInputData(grid);
  REQUIRE(writer->Write() == 1);

  dealii::Triangulation<3> tria;
  Geometry::read_mesh_file(file.name, {}, tria);
  const auto fibres = Geometry::read_vtu_cell_vectors(file.name, "fibres");
  REQUIRE(fibres.size() == tria.n_cells(0));
  for (const auto &cell : tria.cell_iterators_on_level(0))
    {
      const auto f = field(cell->center());
      CHECK((fibres[cell->index()] - f / f.norm()).norm() < 1e-12);
    }

  const auto directions =
    Geometry::read_vtu_cell_vectors(file.name, "directions");
  REQUIRE(directions.size() == tria.n_cells(0));
  for (const auto &cell : tria.cell_iterators_on_level(0))
    {
      const double sign = cell->vertex_index(0) % 2 == 0 ? 1.0 : -1.0;
      CHECK((directions[cell->index()] - sign * direction).norm() < 1e-12);
    }

  // The same vectors as the fibre generator vtu: f of each cell, s a unit
  // vector across it, n = f x s; a file of other cells is refused.
  Fibres::Parameters fibre_params;
  fibre_params.generator       = "vtu";
  fibre_params.vtu_file        = file.name;
  fibre_params.vtu_fibre_array = "fibres";
  const auto frames            = Fibres::create_fibre_field(fibre_params,
                                                 Geometry::LVShape(),
                                                 tria,
                                                 Geometry::BoundaryNames());
  std::vector<Fibres::FibreBasis> bases;
  for (const auto &cell : tria.active_cell_iterators())
    {
      frames(cell, {cell->center(), cell->vertex(0)}, bases);
      REQUIRE(bases.size() == 2);
      const auto f = field(cell->center());
      CHECK((bases[0].f - f / f.norm()).norm() < 1e-12);
      CHECK(std::abs(bases[1].s * bases[1].f) < 1e-12);
      CHECK(std::abs(bases[1].s.norm() - 1.0) < 1e-12);
    }
  dealii::Triangulation<3> other;
  dealii::GridGenerator::subdivided_hyper_cube_with_simplices(other, 1);
  CHECK_THAT(error_of([&]() {
               Fibres::create_fibre_field(fibre_params,
                                          Geometry::LVShape(),
                                          other,
                                          Geometry::BoundaryNames());
             }),
             Catch::Contains("coarse cells: give the mesh file itself"));

  CHECK_THAT(error_of(
               [&]() { Geometry::read_vtu_cell_vectors(file.name, "sheets"); }),
             Catch::Contains("no cell or point array 'sheets'") &&
               Catch::Contains("'fibres', 'directions'"));
}

TEST_CASE("A NaN, infinite or huge coordinate is one clear error naming the "
          "node",
          "[geometry][mesh_file][errors]")
{
  for (const double bad : {std::nan(""), HUGE_VAL, -1e300})
    {
      FileMesh mesh = unit_cube(false, 1);
      // VTK keeps the values as written (and numbers points from 0).
      mesh.vertices[3][1] = bad;
      ScratchFile file("bad_coordinate.vtu");
      write_vtu(mesh, file.name);
      const std::string message = read_error(file.name);
      CHECK(one_line(message));
      CHECK_THAT(message,
                 Catch::Contains("1 of its " +
                                 std::to_string(mesh.vertices.size()) +
                                 " nodes have a coordinate that is not a "
                                 "finite number") &&
                   Catch::Contains("node 3,"));
    }
}

TEST_CASE("A mesh in two pieces is one clear error naming the smaller",
          "[geometry][mesh_file][errors]")
{
  FileMesh mesh = unit_cube(true, 2);
  // A copy of one cell, 10 units away: a second piece of 1 cell.
  const auto                cell = mesh.cells[0];
  std::vector<unsigned int> copy;
  for (const unsigned int v : cell)
    {
      mesh.vertices.push_back(mesh.vertices[v] + Point<3>(10, 0, 0));
      copy.push_back(mesh.vertices.size() - 1);
    }
  mesh.cells.push_back(copy);
  ScratchFile file("two_pieces.msh");
  write_msh22(mesh, file.name);
  const std::string message = read_error(file.name);
  CHECK(one_line(message));
  CHECK_THAT(message,
             Catch::Contains("form 2 disconnected pieces") &&
               Catch::Contains(
                 "the smallest has 1 cell(s), e.g. element " +
                 std::to_string(mesh.faces.size() + mesh.cells.size())));
}
