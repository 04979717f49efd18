#include "geometry/mesh_file.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>
#include <deal.II/grid/tria_description.h>

#include "geometry/mesh_checks.h"
#include "geometry/mid_edge_nodes.h"
#include "geometry/point_location.h"
#include "geometry/vtk_messages.h"

#include <gmsh.h>
#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <unordered_map>

namespace systole::Geometry
{
  std::string
  file_in_directory(const std::string &name, const std::string &base_directory)
  {
    std::filesystem::path file(name);
    if (!file.empty() && file.is_relative() && !base_directory.empty())
      file = std::filesystem::path(base_directory) / file;
    return file.empty() ? "" : file.lexically_normal().string();
  }


  namespace
  {
    void
    fail(const std::string &message)
    {
      AssertThrow(false, dealii::ExcMessage(message));
    }

    std::string
    trim(const std::string &text)
    {
      const auto first = text.find_first_not_of(" \t\n\r");
      if (first == std::string::npos)
        return "";
      const auto last = text.find_last_not_of(" \t\n\r");
      return text.substr(first, last - first + 1);
    }

    /// The extension of @p file in lower case, with the dot (".msh").
    std::string
    extension(const std::string &file)
    {
      std::string ext = std::filesystem::path(file).extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](const char c) {
        return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      });
      return ext;
    }

    void
    check_readable(const std::string &file)
    {
      AssertThrow(std::filesystem::is_regular_file(file) &&
                    std::ifstream(file).good(),
                  dealii::ExcMessage("Mesh file '" + file +
                                     "': cannot open it (no such file or no "
                                     "permission to read)."));
    }

    /// @p text as an integer if it is one (optional sign, digits only).
    bool
    parse_integer(const std::string &text, int &value)
    {
      if (text.empty())
        return false;
      std::size_t used = 0;
      try
        {
          const long long v = std::stoll(text, &used);
          if (used != text.size() || v < std::numeric_limits<int>::min() ||
              v > std::numeric_limits<int>::max())
            return false;
          value = static_cast<int>(v);
          return true;
        }
      catch (const std::exception &)
        {
          return false;
        }
    }

    /// "5 BASE, 6 ENDO, 9" for messages.
    std::string
    list_face_tags(const MeshData &mesh)
    {
      std::set<int> tags;
      for (const auto &face : mesh.faces)
        tags.insert(face.tag);
      for (const auto &[tag, name] : mesh.tag_names)
        tags.insert(tag);
      std::string list;
      for (const int tag : tags)
        {
          list += (list.empty() ? "" : ", ") + std::to_string(tag);
          const auto name = mesh.tag_names.find(tag);
          if (name != mesh.tag_names.end())
            list += " " + name->second;
        }
      return list.empty() ? "none" : list;
    }

    /// gmsh's vertex order of a hexahedron (counter-clockwise bottom, then
    /// top; also VTK's) to deal.II's lexicographic one.
    constexpr std::array<unsigned int, 8> hex_to_lexicographic = {
      {0, 1, 3, 2, 4, 5, 7, 6}};

    unsigned int gmsh_sessions = 0;

    /// The corners (0 to 3) of an edge of a tetrahedron.
    struct Edge
    {
      unsigned int first, second;
    };

    /// The edge of each mid-edge node (4 to 9) of gmsh's 10-node
    /// tetrahedron, from the reference coordinates gmsh gives its nodes (a
    /// mid-edge node sits halfway between its corners), so that no node
    /// order is copied from gmsh's manual.
    std::vector<Edge>
    tet10_edges()
    {
      std::string         name;
      int                 dim, order, n_nodes, n_primary;
      std::vector<double> x;
      gmsh::model::mesh::getElementProperties(11,
                                              name,
                                              dim,
                                              order,
                                              n_nodes,
                                              x,
                                              n_primary);
      const auto coordinate = [&](const unsigned int node, const unsigned d) {
        return x[3 * node + d];
      };
      std::vector<Edge> edges;
      for (unsigned int k = 4; k < 10; ++k)
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int b = a + 1; b < 4; ++b)
            {
              double distance = 0;
              for (unsigned int d = 0; d < 3; ++d)
                distance +=
                  std::abs(coordinate(k, d) -
                           0.5 * (coordinate(a, d) + coordinate(b, d)));
              if (distance < 1e-12)
                edges.push_back({a, b});
            }
      AssertThrow(edges.size() == 6,
                  dealii::ExcMessage("gmsh's 10-node tetrahedron has no "
                                     "node halfway along each edge."));
      return edges;
    }

    /// Drops the nodes that are no corner of a cell (the mid-edge nodes of
    /// second-order cells, and those of their faces) from @p mesh's vertices,
    /// renumbering the cells, faces and mid-edge nodes.
    void
    keep_corners_only(MeshData &mesh)
    {
      const unsigned int        none = dealii::numbers::invalid_unsigned_int;
      std::vector<unsigned int> new_index(mesh.vertices.size(), none);
      for (const auto &cell : mesh.cells)
        for (const unsigned int v : cell)
          new_index[v] = 0;
      std::vector<dealii::Point<3>> vertices;
      std::vector<std::size_t>      ids;
      for (std::size_t i = 0; i < new_index.size(); ++i)
        if (new_index[i] != none)
          {
            new_index[i] = static_cast<unsigned int>(vertices.size());
            vertices.push_back(mesh.vertices[i]);
            ids.push_back(mesh.vertex_ids[i]);
          }
      for (auto &cell : mesh.cells)
        for (unsigned int &v : cell)
          v = new_index[v];
      for (auto &face : mesh.faces)
        for (unsigned int &v : face.vertices)
          v = new_index[v];
      for (auto &node : mesh.mid_edge_nodes)
        node = {new_index[node.first], new_index[node.second], node.position};
      mesh.vertices   = std::move(vertices);
      mesh.vertex_ids = std::move(ids);
    }
  } // namespace

  void
  collect_vtk_message(vtkObject *,
                      unsigned long,
                      void *client_data,
                      void *call_data)
  {
    auto *messages = static_cast<std::string *>(client_data);
    if (call_data != nullptr)
      {
        std::string text(static_cast<const char *>(call_data));
        while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
          text.pop_back();
        *messages += (messages->empty() ? "" : "; ") + text;
      }
  }

  std::string
  vtk_array_names(vtkFieldData &data)
  {
    std::string names;
    for (int a = 0; a < data.GetNumberOfArrays(); ++a)
      names += std::string(names.empty() ? "" : ", ") + "'" +
               (data.GetArrayName(a) != nullptr ? data.GetArrayName(a) : "") +
               "'";
    return names;
  }

  BoundaryNameTable
  parse_boundary_name_table(const std::string &text, const std::string &entry)
  {
    BoundaryNameTable     table;
    std::set<std::string> parts;
    for (const std::string &item :
         dealii::Utilities::split_string_list(text, ';'))
      {
        if (trim(item).empty())
          continue;
        const auto colon = item.find(':');
        AssertThrow(colon != std::string::npos,
                    dealii::ExcMessage(
                      entry + ": '" + trim(item) +
                      "' is not of the form 'part: file name or tag' (entries "
                      "are separated by ';', e.g. 'base: BASE; endocardium: "
                      "6')."));
        const std::string part = trim(item.substr(0, colon));
        const std::string name = trim(item.substr(colon + 1));
        AssertThrow(!part.empty() && !name.empty(),
                    dealii::ExcMessage(entry + ": '" + trim(item) +
                                       "' has an empty part or file name."));
        AssertThrow(parts.insert(part).second,
                    dealii::ExcMessage(entry + ": part '" + part +
                                       "' is named twice."));
        table.emplace_back(part, name);
      }
    return table;
  }

  // ---------------------------------------------------------------------------
  // gmsh

  GmshSession::GmshSession()
  {
    if (gmsh_sessions == 0)
      {
        gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
        gmsh::option::setNumber("General.Terminal", 0);
      }
    ++gmsh_sessions;
  }

  GmshSession::~GmshSession()
  {
    --gmsh_sessions;
    if (gmsh_sessions == 0)
      try
        {
          gmsh::finalize();
        }
      catch (...)
        {}
  }

  namespace
  {
    /// Reads into a model of our own and removes it afterwards, so that a
    /// model of a caller that holds the session stays as it was.
    class ScopedGmshModel
    {
    public:
      ScopedGmshModel()
      {
        gmsh::model::getCurrent(previous);
        gmsh::model::add("systole-mesh-file");
      }
      ~ScopedGmshModel()
      {
        try
          {
            gmsh::model::remove();
            if (!previous.empty())
              gmsh::model::setCurrent(previous);
          }
        catch (...)
          {}
      }
      ScopedGmshModel(const ScopedGmshModel &) = delete;
      ScopedGmshModel &
      operator=(const ScopedGmshModel &) = delete;

    private:
      std::string previous;
    };

    /// gmsh::merge() of @p file; throws naming gmsh's error (an exception
    /// or the first line of its log that starts with "Error").
    void
    merge_gmsh_file(const std::string &file)
    {
      std::string error;
      gmsh::logger::start();
      try
        {
          gmsh::merge(file);
        }
      catch (const std::string &message)
        {
          error = message;
        }
      catch (const std::exception &e)
        {
          error = e.what();
        }
      std::vector<std::string> log;
      gmsh::logger::get(log);
      gmsh::logger::stop();
      for (const auto &line : log)
        if (error.empty() && line.rfind("Error", 0) == 0)
          error = line;
      AssertThrow(error.empty(),
                  dealii::ExcMessage(
                    "Mesh file '" + file + "': gmsh could not read it (" +
                    error +
                    "). Systole reads gmsh .msh files of format 2.2 or 4.1, "
                    "ASCII or binary."));
    }

    /// The name of gmsh element type @p type, for messages.
    std::string
    gmsh_type_name(const int type)
    {
      std::string         name;
      int                 dim, order, n_nodes, n_primary;
      std::vector<double> local;
      gmsh::model::mesh::getElementProperties(type,
                                              name,
                                              dim,
                                              order,
                                              n_nodes,
                                              local,
                                              n_primary);
      return name + " (gmsh element type " + std::to_string(type) + ")";
    }

    /// The nodes of the current gmsh model into @p mesh (vertices and
    /// their ids), and the vertex index of a node tag.
    class GmshNodes
    {
    public:
      GmshNodes(const std::string &file, MeshData &mesh)
        : file(file)
      {
        std::vector<std::size_t> node_tags;
        std::vector<double>      coordinates, parametric;
        gmsh::model::mesh::getNodes(node_tags,
                                    coordinates,
                                    parametric,
                                    -1,
                                    -1,
                                    false,
                                    false);
        index_of.reserve(node_tags.size());
        mesh.vertices.resize(node_tags.size());
        mesh.vertex_ids = node_tags;
        for (std::size_t i = 0; i < node_tags.size(); ++i)
          {
            mesh.vertices[i]       = dealii::Point<3>(coordinates[3 * i],
                                                coordinates[3 * i + 1],
                                                coordinates[3 * i + 2]);
            index_of[node_tags[i]] = static_cast<unsigned int>(i);
          }
      }

      /// The vertex index of node @p tag; throws when the file does not
      /// define it.
      unsigned int
      operator()(const std::size_t tag) const
      {
        const auto it = index_of.find(tag);
        AssertThrow(it != index_of.end(),
                    dealii::ExcMessage("Mesh file '" + file +
                                       "': an element refers to node " +
                                       std::to_string(tag) +
                                       ", which the file does not define."));
        return it->second;
      }

    private:
      const std::string                             file;
      std::unordered_map<std::size_t, unsigned int> index_of;
    };

    /// The cell type of the volume elements of @p types (gmsh types,
    /// @p element_tags per type); throws on other types or a mix.
    dealii::ReferenceCell
    gmsh_cell_type(const std::string                           &file,
                   const std::vector<int>                      &types,
                   const std::vector<std::vector<std::size_t>> &element_tags)
    {
      std::size_t n_tets = 0, n_hexes = 0;
      for (std::size_t t = 0; t < types.size(); ++t)
        {
          AssertThrow(types[t] == 4 || types[t] == 5 || types[t] == 11,
                      dealii::ExcMessage(
                        "Mesh file '" + file + "' has " +
                        std::to_string(element_tags[t].size()) + " " +
                        gmsh_type_name(types[t]) +
                        " elements; Systole reads tetrahedra of 4 or 10 nodes "
                        "(types 4, 11) or 8-node hexahedra (type 5). Mesh "
                        "with Mesh.ElementOrder = 1 or 2 (2 on tetrahedra "
                        "only) and without prisms or pyramids."));
          (types[t] == 5 ? n_hexes : n_tets) += element_tags[t].size();
        }
      AssertThrow(n_tets == 0 || n_hexes == 0,
                  dealii::ExcMessage(
                    "Mesh file '" + file + "' mixes " + std::to_string(n_tets) +
                    " tetrahedra and " + std::to_string(n_hexes) +
                    " hexahedra; a mesh must be all tetrahedra or all "
                    "hexahedra (gmsh: Mesh.SubdivisionAlgorithm = 2 makes "
                    "all hexahedra)."));
      AssertThrow(n_tets + n_hexes > 0,
                  dealii::ExcMessage(
                    "Mesh file '" + file +
                    "' has no tetrahedra or hexahedra: mesh the volume (gmsh "
                    "-3) and save its physical volume."));
      return n_tets > 0 ? dealii::ReferenceCells::Tetrahedron
                        : dealii::ReferenceCells::Hexahedron;
    }

    /// The volume cells of the current gmsh model into @p mesh (the
    /// mid-edge nodes of 10-node tetrahedra too).
    void
    read_gmsh_cells(const std::string &file,
                    const GmshNodes   &vertex_index,
                    MeshData          &mesh)
    {
      std::vector<int>                      types;
      std::vector<std::vector<std::size_t>> element_tags, element_nodes;
      gmsh::model::mesh::getElements(types, element_tags, element_nodes, 3, -1);
      mesh.cell_type = gmsh_cell_type(file, types, element_tags);
      for (std::size_t t = 0; t < types.size(); ++t)
        {
          const unsigned int n       = types[t] == 5 ? 8 : 4;
          const unsigned int n_nodes = types[t] == 11 ? 10 : n;
          const auto         edges =
            types[t] == 11 ? tet10_edges() : std::vector<Edge>();
          for (std::size_t e = 0; e < element_tags[t].size(); ++e)
            {
              const std::size_t        *nodes = &element_nodes[t][n_nodes * e];
              std::vector<unsigned int> cell(n);
              for (unsigned int v = 0; v < n; ++v)
                cell[n == 8 ? hex_to_lexicographic[v] : v] =
                  vertex_index(nodes[v]);
              for (unsigned int k = 0; k < edges.size(); ++k)
                {
                  const unsigned int mid = vertex_index(nodes[4 + k]);
                  mesh.mid_edge_nodes.push_back({cell[edges[k].first],
                                                 cell[edges[k].second],
                                                 mesh.vertices[mid]});
                }
              mesh.cells.push_back(std::move(cell));
              mesh.cell_ids.push_back(element_tags[t][e]);
            }
        }
    }

    /// The faces of the 2D physical group @p tag of the current gmsh model
    /// (its triangles and quadrilaterals) into @p mesh, with its name.
    void
    read_gmsh_physical_surface(const std::string &file,
                               const int          tag,
                               const GmshNodes   &vertex_index,
                               MeshData          &mesh)
    {
      std::string name;
      gmsh::model::getPhysicalName(2, tag, name);
      if (!name.empty())
        mesh.tag_names[tag] = name;
      std::vector<int> entities;
      gmsh::model::getEntitiesForPhysicalGroup(2, tag, entities);
      std::vector<int>                      types;
      std::vector<std::vector<std::size_t>> element_tags, element_nodes;
      for (const int entity : entities)
        {
          gmsh::model::mesh::getElements(types,
                                         element_tags,
                                         element_nodes,
                                         2,
                                         entity);
          for (std::size_t t = 0; t < types.size(); ++t)
            {
              AssertThrow(types[t] == 2 || types[t] == 3 || types[t] == 9,
                          dealii::ExcMessage(
                            "Mesh file '" + file + "': physical surface " +
                            std::to_string(tag) + " has " +
                            std::to_string(element_tags[t].size()) + " " +
                            gmsh_type_name(types[t]) +
                            " elements; Systole reads triangles of 3 or 6 "
                            "nodes (types 2, 9) and 4-node quadrilaterals "
                            "(type 3)."));
              const unsigned int n       = types[t] == 3 ? 4 : 3;
              const unsigned int n_nodes = types[t] == 9 ? 6 : n;
              for (std::size_t e = 0; e < element_tags[t].size(); ++e)
                {
                  MeshData::TaggedFace face;
                  face.tag = tag;
                  face.id  = element_tags[t][e];
                  for (unsigned int v = 0; v < n; ++v) // the corners
                    face.vertices.push_back(
                      vertex_index(element_nodes[t][n_nodes * e + v]));
                  mesh.faces.push_back(std::move(face));
                }
            }
        }
    }
  } // namespace

  MeshData
  read_gmsh_data(const std::string &file)
  {
    check_readable(file);
    MeshData mesh;
    mesh.file = file;

    const GmshSession     session;
    const ScopedGmshModel model;
    merge_gmsh_file(file);
    const GmshNodes vertex_index(file, mesh);
    read_gmsh_cells(file, vertex_index, mesh);
    // Faces: the triangles and quadrilaterals of each 2D physical group.
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, 2);
    for (const auto &group : groups)
      read_gmsh_physical_surface(file, group.second, vertex_index, mesh);
    if (!mesh.mid_edge_nodes.empty())
      keep_corners_only(mesh);
    return mesh;
  }

  // ---------------------------------------------------------------------------
  // VTK

  namespace
  {
    /// The unstructured grid of a .vtu file; VTK's errors and warnings in
    /// the message of the exception.
    vtkSmartPointer<vtkUnstructuredGrid>
    read_vtu_grid(const std::string &file)
    {
      check_readable(file);
      std::string                          vtk_messages;
      vtkNew<vtkCallbackCommand>           on_message;
      vtkNew<vtkXMLUnstructuredGridReader> reader;
      on_message->SetCallback(collect_vtk_message);
      on_message->SetClientData(&vtk_messages);
      reader->AddObserver(vtkCommand::ErrorEvent, on_message);
      reader->AddObserver(vtkCommand::WarningEvent, on_message);
      reader->SetFileName(file.c_str());
      reader->Update();
      vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
      AssertThrow(
        reader->GetErrorCode() == 0 && vtk_messages.empty() && grid != nullptr,
        dealii::ExcMessage(
          "Mesh file '" + file +
          "': VTK could not read it as an XML unstructured grid (.vtu)" +
          (vtk_messages.empty() ? std::string(".") : ": " + vtk_messages)));
      return grid;
    }

    /// The cell-data array @p name of @p grid that tags the boundary faces
    /// (nullptr for an empty @p name); throws naming the arrays there are.
    vtkDataArray *
    vtu_face_tags(vtkUnstructuredGrid &grid,
                  const std::string   &file,
                  const std::string   &name)
    {
      if (name.empty())
        return nullptr;
      vtkCellData  *cell_data = grid.GetCellData();
      vtkDataArray *tags      = cell_data->GetArray(name.c_str());
      if (tags == nullptr)
        {
          const std::string arrays = vtk_array_names(*cell_data);
          fail("Mesh file '" + file + "' has no cell-data array '" + name +
               "' (its cell arrays: " + (arrays.empty() ? "none" : arrays) +
               "). Set Face tag array to the array that tags its boundary "
               "triangles or quadrilaterals.");
        }
      AssertThrow(tags->GetNumberOfComponents() == 1,
                  dealii::ExcMessage(
                    "Mesh file '" + file + "': the face tag array '" + name +
                    "' has " + std::to_string(tags->GetNumberOfComponents()) +
                    " components; it must have one integer per cell."));
      return tags;
    }

    /// What read_vtu_cells() counted.
    struct VtuCellCounts
    {
      std::size_t n_tets = 0, n_hexes = 0, n_face_cells = 0;
      /// Per unsupported VTK cell type: how many, and the first cell.
      std::map<int, std::pair<std::size_t, vtkIdType>> unsupported;
    };

    /// The cells of @p grid into @p mesh: tetrahedra and hexahedra, and,
    /// with @p tags, the triangles and quadrilaterals as tagged faces.
    VtuCellCounts
    read_vtu_cells(vtkUnstructuredGrid &grid,
                   const std::string   &file,
                   vtkDataArray        *tags,
                   const std::string   &tag_name,
                   MeshData            &mesh)
    {
      VtuCellCounts     counts;
      vtkNew<vtkIdList> points;
      for (vtkIdType c = 0; c < grid.GetNumberOfCells(); ++c)
        {
          const int type = grid.GetCellType(c);
          grid.GetCellPoints(c, points);
          std::vector<unsigned int> ids(points->GetNumberOfIds());
          for (vtkIdType i = 0; i < points->GetNumberOfIds(); ++i)
            ids[i] = static_cast<unsigned int>(points->GetId(i));
          if (type == VTK_TETRA)
            {
              mesh.cells.push_back(ids);
              mesh.cell_ids.push_back(c);
              ++counts.n_tets;
            }
          else if (type == VTK_HEXAHEDRON)
            {
              std::vector<unsigned int> cell(8);
              for (unsigned int v = 0; v < 8; ++v)
                cell[hex_to_lexicographic[v]] = ids[v];
              mesh.cells.push_back(cell);
              mesh.cell_ids.push_back(c);
              ++counts.n_hexes;
            }
          else if (type == VTK_TRIANGLE || type == VTK_QUAD)
            {
              ++counts.n_face_cells;
              if (tags == nullptr)
                continue;
              const double value = tags->GetComponent(c, 0);
              AssertThrow(value == std::round(value) &&
                            std::abs(value) < std::numeric_limits<int>::max(),
                          dealii::ExcMessage("Mesh file '" + file +
                                             "': the face tag array '" +
                                             tag_name + "' has the value " +
                                             std::to_string(value) +
                                             " on cell " + std::to_string(c) +
                                             "; face tags must be integers."));
              mesh.faces.push_back(
                {ids, static_cast<int>(value), static_cast<std::size_t>(c)});
            }
          else if (type != VTK_VERTEX && type != VTK_POLY_VERTEX &&
                   type != VTK_LINE && type != VTK_POLY_LINE)
            {
              auto &entry = counts.unsupported[type];
              if (entry.first++ == 0)
                entry.second = c;
            }
        }
      return counts;
    }
  } // namespace

  MeshData
  read_vtu_data(const std::string &file, const std::string &face_tag_array)
  {
    check_readable(file);
    MeshData mesh;
    mesh.file = file;

    const vtkSmartPointer<vtkUnstructuredGrid> grid = read_vtu_grid(file);

    const vtkIdType n_points = grid->GetNumberOfPoints();
    mesh.vertices.resize(n_points);
    mesh.vertex_ids.resize(n_points);
    for (vtkIdType i = 0; i < n_points; ++i)
      {
        double x[3];
        grid->GetPoint(i, x);
        mesh.vertices[i]   = dealii::Point<3>(x[0], x[1], x[2]);
        mesh.vertex_ids[i] = static_cast<std::size_t>(i);
      }

    vtkDataArray       *tags = vtu_face_tags(*grid, file, face_tag_array);
    const VtuCellCounts counts =
      read_vtu_cells(*grid, file, tags, face_tag_array, mesh);
    if (!counts.unsupported.empty())
      {
        const auto &[type, entry] = *counts.unsupported.begin();
        fail("Mesh file '" + file + "' has " + std::to_string(entry.first) +
             " cells of VTK type " + std::to_string(type) + " (" +
             vtkCellTypes::GetClassNameFromTypeId(type) + "), the first cell " +
             std::to_string(entry.second) +
             "; Systole reads linear tetrahedra (VTK_TETRA) or hexahedra "
             "(VTK_HEXAHEDRON), with triangles or quadrilaterals for the "
             "boundary faces.");
      }
    AssertThrow(counts.n_tets == 0 || counts.n_hexes == 0,
                dealii::ExcMessage(
                  "Mesh file '" + file + "' mixes " +
                  std::to_string(counts.n_tets) + " tetrahedra and " +
                  std::to_string(counts.n_hexes) +
                  " hexahedra; a mesh must be all tetrahedra or all "
                  "hexahedra."));
    AssertThrow(counts.n_tets + counts.n_hexes > 0,
                dealii::ExcMessage("Mesh file '" + file +
                                   "' has no tetrahedra or hexahedra."));
    mesh.cell_type = counts.n_tets > 0 ? dealii::ReferenceCells::Tetrahedron
                                       : dealii::ReferenceCells::Hexahedron;
    AssertThrow(
      tags == nullptr || counts.n_face_cells > 0,
      dealii::ExcMessage(
        "Mesh file '" + file + "' has only volume cells, so the cell array '" +
        face_tag_array +
        "' cannot tag boundary faces (a tag on a cell does not say which of "
        "its faces lie on which surface). Add the boundary triangles or "
        "quadrilaterals to the file with their tag in that array (meshio: "
        "write the 'triangle' cells with the tag as cell data), or use the "
        "gmsh .msh file with its physical surfaces."));
    return mesh;
  }

  std::vector<dealii::Tensor<1, 3>>
  read_vtu_cell_vectors(const std::string &file, const std::string &array)
  {
    const vtkSmartPointer<vtkUnstructuredGrid> grid = read_vtu_grid(file);
    vtkDataArray *cell_array  = grid->GetCellData()->GetArray(array.c_str());
    vtkDataArray *point_array = grid->GetPointData()->GetArray(array.c_str());
    if (cell_array == nullptr && point_array == nullptr)
      {
        std::string arrays;
        for (vtkFieldData *data :
             {static_cast<vtkFieldData *>(grid->GetCellData()),
              static_cast<vtkFieldData *>(grid->GetPointData())})
          for (int a = 0; a < data->GetNumberOfArrays(); ++a)
            if (data->GetArrayName(a) != nullptr)
              arrays += std::string(arrays.empty() ? "" : ", ") + "'" +
                        data->GetArrayName(a) + "'";
        fail("Mesh file '" + file + "' has no cell or point array '" + array +
             "' (its arrays: " + (arrays.empty() ? "none" : arrays) + ").");
      }
    vtkDataArray *data = cell_array != nullptr ? cell_array : point_array;
    AssertThrow(data->GetNumberOfComponents() == 3,
                dealii::ExcMessage(
                  "Mesh file '" + file + "': the array '" + array + "' has " +
                  std::to_string(data->GetNumberOfComponents()) +
                  " components; a vector has 3."));

    const auto vector_of = [&](const vtkIdType i) {
      double v[3];
      data->GetTuple(i, v);
      return dealii::Tensor<1, 3>({v[0], v[1], v[2]});
    };
    std::vector<dealii::Tensor<1, 3>> vectors;
    vtkNew<vtkIdList>                 points;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
      {
        const int type = grid->GetCellType(c);
        if (type != VTK_TETRA && type != VTK_HEXAHEDRON)
          continue;
        grid->GetCellPoints(c, points);
        dealii::Tensor<1, 3> v;
        if (cell_array != nullptr)
          v = vector_of(c);
        else
          {
            // The dominant direction of the vertices' vectors: the sign of a
            // fibre direction carries no meaning, so average a a^T, not a.
            dealii::SymmetricTensor<2, 3> sum;
            for (vtkIdType i = 0; i < points->GetNumberOfIds(); ++i)
              {
                const auto a = vector_of(points->GetId(i));
                sum += dealii::symmetrize(dealii::outer_product(a, a));
              }
            const auto first = vector_of(points->GetId(0));
            v = dealii::eigenvectors(sum)[0].second * std::sqrt(sum.norm());
            if (v * first < 0)
              v = -v;
          }
        if (v.norm() == 0 || !std::isfinite(v.norm()))
          {
            dealii::Point<3> centre;
            for (vtkIdType i = 0; i < points->GetNumberOfIds(); ++i)
              {
                double x[3];
                grid->GetPoint(points->GetId(i), x);
                centre += dealii::Point<3>(x[0], x[1], x[2]) /
                          static_cast<double>(points->GetNumberOfIds());
              }
            fail("Mesh file '" + file + "': the vector array '" + array +
                 "' is zero or not finite " +
                 (cell_array != nullptr ? "on" : "at the vertices of") +
                 " cell " + std::to_string(c) + " at " + format_point(centre) +
                 "; every cell needs a direction.");
          }
        vectors.push_back(v / v.norm());
      }
    return vectors;
  }

  // ---------------------------------------------------------------------------
  // Building the triangulation

  namespace
  {
    /// A boundary part of the table, resolved to a face tag.
    struct Part
    {
      std::string name;
      std::string file_name; ///< as the table (or the file) gives it
      int         tag;
    };

    std::vector<Part>
    resolve_parts(const MeshData &mesh, const BoundaryNameTable &table)
    {
      std::vector<Part> parts;
      if (table.empty())
        {
          std::set<int> tags;
          for (const auto &face : mesh.faces)
            tags.insert(face.tag);
          for (const auto &[tag, name] : mesh.tag_names)
            tags.insert(tag);
          for (const int tag : tags)
            {
              const auto  named = mesh.tag_names.find(tag);
              std::string name  = named != mesh.tag_names.end()
                                    ? named->second
                                    : std::to_string(tag);
              parts.push_back({name, name, tag});
            }
          return parts;
        }
      for (const auto &[part, file_name] : table)
        {
          int  tag   = 0;
          bool found = false;
          for (const auto &[t, name] : mesh.tag_names)
            if (name == file_name)
              {
                tag   = t;
                found = true;
                break;
              }
          if (!found)
            found = parse_integer(file_name, tag);
          AssertThrow(found,
                      dealii::ExcMessage(
                        "Boundary names: '" + part + ": " + file_name +
                        "' names no face of mesh file '" + mesh.file +
                        "': it has no face tag named '" + file_name +
                        "' (its face tags: " + list_face_tags(mesh) + ")."));
          parts.push_back({part, file_name, tag});
        }
      return parts;
    }

    /// The sorted vertex indices of a face (a triangle padded with an
    /// invalid index).
    using FaceKey = std::array<unsigned int, 4>;

    FaceKey
    face_key(const std::vector<unsigned int> &vertices)
    {
      FaceKey key;
      key.fill(dealii::numbers::invalid_unsigned_int);
      const std::size_t n = std::min<std::size_t>(vertices.size(), 4);
      std::copy(vertices.begin(), vertices.begin() + n, key.begin());
      // Insertion sort by hand: GCC 12 warns about std::sort on 4 entries.
      for (std::size_t i = 1; i < n; ++i)
        for (std::size_t j = i; j > 0 && key[j] < key[j - 1]; --j)
          std::swap(key[j], key[j - 1]);
      return key;
    }

    /// The mid-edge nodes of @p mesh keyed by their corners' positions.
    std::shared_ptr<const MidEdgeTable>
    mid_edge_table(const MeshData &mesh)
    {
      auto table = std::make_shared<MidEdgeTable>(make_mid_edge_table());
      for (const auto &node : mesh.mid_edge_nodes)
        table->emplace(mid_edge_key(mesh.vertices[node.first],
                                    mesh.vertices[node.second]),
                       node.position);
      return table;
    }

    dealii::Point<3>
    centroid(const MeshData &mesh, const std::vector<unsigned int> &vertices)
    {
      dealii::Point<3> c;
      for (const unsigned int v : vertices)
        c += mesh.vertices[v];
      return c / static_cast<double>(vertices.size());
    }

    /// The parts by face tag (the first part of a tag); throws at a
    /// negative tag.
    std::map<int, std::string>
    used_face_tags(const MeshData &mesh, const std::vector<Part> &parts)
    {
      std::map<int, std::string> used_tags; // tag -> its first part
      for (const auto &part : parts)
        {
          AssertThrow(part.tag >= 0,
                      dealii::ExcMessage(
                        "Mesh file '" + mesh.file + "': face tag " +
                        std::to_string(part.tag) + " (part '" + part.name +
                        "') is negative; boundary ids are non-negative."));
          used_tags.emplace(part.tag, part.name);
        }
      return used_tags;
    }

    /// The cells of @p mesh for deal.II, hexahedra consistently oriented.
    std::vector<dealii::CellData<3>>
    volume_cells(const MeshData &mesh)
    {
      std::vector<dealii::CellData<3>> cells(mesh.cells.size());
      for (std::size_t c = 0; c < cells.size(); ++c)
        cells[c].vertices = mesh.cells[c];
      if (mesh.cell_type != dealii::ReferenceCells::Tetrahedron)
        try
          {
            dealii::GridTools::consistently_order_cells(cells);
          }
        catch (const dealii::ExceptionBase &e)
          {
            fail("Mesh file '" + mesh.file +
                 "': deal.II cannot orient its hexahedra consistently (" +
                 e.get_exc_name() +
                 "); a hexahedral mesh must be orientable in deal.II's sense "
                 "(see GridTools::consistently_order_cells).");
          }
      return cells;
    }

    /// Every face of every cell, sorted by its vertices, and for each entry
    /// how many cells share its face: a face that occurs once is a boundary
    /// face.
    struct CellFaces
    {
      struct Entry
      {
        FaceKey      key;
        unsigned int cell;
        unsigned int face;
      };
      std::vector<Entry>        entries;
      std::vector<unsigned int> multiplicity;
      unsigned int              n_face_vertices; ///< 3 or 4

      /// The vertices of the face of entry @p i.
      dealii::CellData<2>
      face(const std::vector<dealii::CellData<3>> &cells,
           const dealii::ReferenceCell            &reference,
           const std::size_t                       i) const
      {
        dealii::CellData<2> face(n_face_vertices);
        for (unsigned int v = 0; v < n_face_vertices; ++v)
          face.vertices[v] =
            cells[entries[i].cell]
              .vertices[reference.face_to_cell_vertices(entries[i].face, v, 1)];
        return face;
      }
    };

    /// The faces of @p cells; throws at a face of more than two cells.
    CellFaces
    cell_faces(const MeshData                         &mesh,
               const std::vector<dealii::CellData<3>> &cells)
    {
      const dealii::ReferenceCell &reference = mesh.cell_type;
      CellFaces                    faces;
      faces.n_face_vertices =
        mesh.cell_type == dealii::ReferenceCells::Tetrahedron ? 3 : 4;
      auto &entries = faces.entries;
      entries.reserve(cells.size() * reference.n_faces());
      std::vector<unsigned int> face_vertices(faces.n_face_vertices);
      for (unsigned int c = 0; c < cells.size(); ++c)
        for (const unsigned int f : reference.face_indices())
          {
            for (unsigned int i = 0; i < faces.n_face_vertices; ++i)
              face_vertices[i] =
                cells[c].vertices[reference.face_to_cell_vertices(f, i, 1)];
            entries.push_back({face_key(face_vertices), c, f});
          }
      std::sort(entries.begin(),
                entries.end(),
                [](const CellFaces::Entry &a, const CellFaces::Entry &b) {
                  return a.key < b.key;
                });
      faces.multiplicity.resize(entries.size());
      std::size_t n_overshared = 0, first_overshared = 0;
      for (std::size_t i = 0; i < entries.size();)
        {
          std::size_t j = i;
          while (j < entries.size() && entries[j].key == entries[i].key)
            ++j;
          for (std::size_t k = i; k < j; ++k)
            faces.multiplicity[k] = j - i;
          if (j - i > 2 && n_overshared++ == 0)
            first_overshared = i;
          i = j;
        }
      if (n_overshared > 0)
        {
          const auto &entry = entries[first_overshared];
          fail("Mesh file '" + mesh.file +
               "': " + std::to_string(n_overshared) +
               " faces are shared by more than two cells (duplicate cells or "
               "a non-manifold mesh); the first is a face of element " +
               std::to_string(mesh.cell_ids[entry.cell]) + " near " +
               format_point(centroid(mesh, mesh.cells[entry.cell])) +
               ". Remove the duplicate cells.");
        }
      return faces;
    }

    /// The tag of each boundary face of @p faces (-1: none) from the file's
    /// faces in a used tag; throws at a face in two parts, at tagged faces
    /// that are no face of a cell, and (with a @p table) at a part without
    /// a boundary face.
    std::vector<int>
    boundary_face_tags(const MeshData             &mesh,
                       const BoundaryNameTable    &table,
                       const std::vector<Part>    &parts,
                       std::map<int, std::string> &used_tags,
                       const CellFaces            &faces)
    {
      std::vector<int>            tag_of(faces.entries.size(), -1);
      std::map<int, std::size_t>  n_boundary_faces; // per used tag
      std::size_t                 n_dangling = 0, n_wrong_kind = 0;
      const MeshData::TaggedFace *first_dangling = nullptr;
      for (const auto &face : mesh.faces)
        {
          if (used_tags.count(face.tag) == 0)
            continue;
          if (face.vertices.size() != faces.n_face_vertices)
            {
              if (n_wrong_kind++ == 0)
                first_dangling = &face;
              continue;
            }
          const FaceKey key = face_key(face.vertices);
          const auto    found =
            std::lower_bound(faces.entries.begin(),
                             faces.entries.end(),
                             key,
                             [](const CellFaces::Entry &a, const FaceKey &b) {
                               return a.key < b;
                             });
          if (found == faces.entries.end() || found->key != key)
            {
              if (n_dangling++ == 0)
                first_dangling = &face;
              continue;
            }
          const std::size_t i = found - faces.entries.begin();
          if (faces.multiplicity[i] != 1)
            continue; // between two cells: not a boundary face
          if (tag_of[i] >= 0 && tag_of[i] != face.tag)
            fail("Mesh file '" + mesh.file + "': the boundary face at " +
                 format_point(centroid(mesh, face.vertices)) +
                 " is in face tag " + std::to_string(tag_of[i]) + " (part '" +
                 used_tags[tag_of[i]] + "') and face tag " +
                 std::to_string(face.tag) + " (part '" + used_tags[face.tag] +
                 "'); a boundary face can carry one part only.");
          if (tag_of[i] < 0)
            ++n_boundary_faces[face.tag];
          tag_of[i] = face.tag;
        }
      if (n_wrong_kind > 0)
        fail("Mesh file '" + mesh.file + "': " + std::to_string(n_wrong_kind) +
             " faces tagged " + std::to_string(first_dangling->tag) +
             " and others have " +
             std::to_string(first_dangling->vertices.size()) +
             " vertices, but the faces of " + mesh.cell_kind() + " have " +
             std::to_string(faces.n_face_vertices) + "; the first, element " +
             std::to_string(first_dangling->id) + ", at " +
             format_point(centroid(mesh, first_dangling->vertices)) +
             ". Tag the faces of the volume mesh.");
      if (n_dangling > 0)
        fail("Mesh file '" + mesh.file + "': " + std::to_string(n_dangling) +
             " tagged faces are no face of any of its " + mesh.cell_kind() +
             "; the first, element " + std::to_string(first_dangling->id) +
             " (tag " + std::to_string(first_dangling->tag) + "), at " +
             format_point(centroid(mesh, first_dangling->vertices)) +
             ". The surface and the volume mesh must share their nodes "
             "(gmsh: mesh the volume from the tagged surfaces; Coherence "
             "Mesh).");
      if (!table.empty())
        for (const auto &part : parts)
          AssertThrow(n_boundary_faces[part.tag] > 0,
                      dealii::ExcMessage(
                        "Boundary names: '" + part.name + ": " +
                        part.file_name +
                        "' names no boundary face of mesh "
                        "file '" +
                        mesh.file + "' (face tag " + std::to_string(part.tag) +
                        " has no face on its boundary; its face tags: " +
                        list_face_tags(mesh) + ")."));
      return tag_of;
    }
  } // namespace

  unsigned int
  default_boundary_id(const MeshData &mesh, const BoundaryNameTable &table)
  {
    std::set<int> used;
    for (const auto &part : resolve_parts(mesh, table))
      used.insert(part.tag);
    unsigned int id = 0;
    while (used.count(static_cast<int>(id)) > 0)
      ++id;
    return id;
  }

  BoundaryNames
  build_triangulation(const MeshData              &mesh,
                      const BoundaryNameTable     &table,
                      dealii::Triangulation<3, 3> &tria)
  {
    const bool tets   = mesh.cell_type == dealii::ReferenceCells::Tetrahedron;
    using Distributed = dealii::parallel::distributed::Triangulation<3, 3>;
    const bool distributed = dynamic_cast<Distributed *>(&tria) != nullptr;
    AssertThrow(!tets || !distributed,
                dealii::ExcMessage(
                  "Mesh file '" + mesh.file +
                  "' has tetrahedra, which a parallel::distributed::"
                  "Triangulation (p4est) cannot hold: read it into a serial "
                  "Triangulation, or use an all-hexahedral mesh."));

    const std::vector<Part>    parts      = resolve_parts(mesh, table);
    std::map<int, std::string> used_tags  = used_face_tags(mesh, parts);
    const unsigned int         default_id = default_boundary_id(mesh, table);
    const std::vector<dealii::CellData<3>> cells = volume_cells(mesh);
    const CellFaces                        faces = cell_faces(mesh, cells);
    const std::vector<int>                 tag_of =
      boundary_face_tags(mesh, table, parts, used_tags, faces);

    dealii::SubCellData boundary;
    for (std::size_t i = 0; i < faces.entries.size(); ++i)
      if (faces.multiplicity[i] == 1)
        {
          dealii::CellData<2> face = faces.face(cells, mesh.cell_type, i);
          face.boundary_id =
            tag_of[i] >= 0 ? static_cast<dealii::types::boundary_id>(tag_of[i])
                           : default_id;
          boundary.boundary_quads.push_back(std::move(face));
        }
    try
      {
        tria.create_triangulation(mesh.vertices, cells, boundary);
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream info;
        e.print_info(info);
        fail("Mesh file '" + mesh.file +
             "': deal.II could not build the mesh: " + trim(info.str()));
      }
    if (!mesh.mid_edge_nodes.empty())
      attach_mid_edge_nodes(tria, mid_edge_table(mesh));

    BoundaryNames names("the mesh file '" + mesh.file + "'");
    for (const auto &part : parts)
      names.add(part.name, static_cast<dealii::types::boundary_id>(part.tag));
    return names;
  }

  BoundaryNames
  read_mesh_file(const std::string           &file,
                 const MeshFileOptions       &options,
                 dealii::Triangulation<3, 3> &tria)
  {
    const std::string ext = extension(file);
    AssertThrow(ext == ".msh" || ext == ".vtu",
                dealii::ExcMessage(
                  "Mesh file '" + file +
                  "': Systole reads gmsh .msh and VTK .vtu files (by their "
                  "extension), not '" +
                  ext + "'."));
    AssertThrow(ext == ".vtu" || options.face_tag_array.empty(),
                dealii::ExcMessage(
                  "Mesh file '" + file +
                  "': Face tag array is for .vtu files; a gmsh file tags its "
                  "faces with physical surfaces."));
    AssertThrow(ext == ".msh" || options.boundary_names.empty() ||
                  !options.face_tag_array.empty(),
                dealii::ExcMessage(
                  "Mesh file '" + file +
                  "': Boundary names needs Face tag array, the cell-data "
                  "array of the file that tags its boundary faces."));
    MeshData mesh = ext == ".msh" ? read_gmsh_data(file)
                                  : read_vtu_data(file, options.face_tag_array);
    if (options.scale != 1.0)
      {
        for (auto &x : mesh.vertices)
          x *= options.scale;
        for (auto &node : mesh.mid_edge_nodes)
          node.position *= options.scale;
      }
    check_mesh_data(mesh);
    return build_triangulation(mesh, options.boundary_names, tria);
  }

  BoundaryNames
  read_gmsh(const std::string           &file,
            const double                 scale,
            dealii::Triangulation<3, 3> &tria)
  {
    MeshFileOptions options;
    options.scale = scale;
    return read_mesh_file(file, options, tria);
  }
} // namespace systole::Geometry
