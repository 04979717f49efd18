#include "geometry/mesh_checks.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/grid/cell_id.h>
#include <deal.II/grid/tria.h>

#include "base/first_members.h"
#include "base/format.h"
#include "geometry/point_location.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <unordered_map>

namespace systole::Geometry
{
  namespace
  {
    std::string
    list_points(const MeshData &mesh, const std::vector<unsigned int> &cell)
    {
      std::string list;
      for (const unsigned int v : cell)
        list += (list.empty() ? "" : ", ") + format_point(mesh.vertices[v]);
      return list;
    }

    double
    longest_edge(const MeshData &mesh, const std::vector<unsigned int> &cell)
    {
      double longest = 0;
      for (unsigned int i = 0; i < cell.size(); ++i)
        for (unsigned int j = i + 1; j < cell.size(); ++j)
          longest =
            std::max(longest,
                     mesh.vertices[cell[i]].distance(mesh.vertices[cell[j]]));
      return longest;
    }

    double
    determinant(const dealii::Tensor<1, 3> &a,
                const dealii::Tensor<1, 3> &b,
                const dealii::Tensor<1, 3> &c)
    {
      return a * dealii::cross_product_3d(b, c);
    }
  } // namespace

  void
  check_mesh_data(const MeshData &mesh)
  {
    check_coordinates(mesh);
    check_vertex_references(mesh);
    check_unused_vertices(mesh);
    check_duplicate_vertices(mesh);
    check_cell_orientation(mesh);
    check_connected(mesh);
  }

  void
  check_coordinates(const MeshData &mesh, const double max_coordinate)
  {
    const auto bad = [&](const dealii::Point<3> &p) {
      for (unsigned int d = 0; d < 3; ++d)
        if (!std::isfinite(p[d]) || std::abs(p[d]) > max_coordinate)
          return true;
      return false;
    };
    const std::size_t n_bad =
      std::count_if(mesh.vertices.begin(), mesh.vertices.end(), bad);
    if (n_bad == 0)
      return;
    const std::size_t first =
      std::find_if(mesh.vertices.begin(), mesh.vertices.end(), bad) -
      mesh.vertices.begin();
    AssertThrow(false,
                dealii::ExcMessage(
                  "Mesh file '" + mesh.file + "': " + std::to_string(n_bad) +
                  " of its " + std::to_string(mesh.vertices.size()) +
                  " nodes have a coordinate that is not a finite number or "
                  "exceeds " +
                  format_number(max_coordinate) + " in size; the first, node " +
                  std::to_string(mesh.vertex_ids.at(first)) + ", at " +
                  format_point(mesh.vertices[first]) +
                  ". The file is corrupt or in the wrong units: re-export it "
                  "(or fix Geometry / Gmsh / Scale)."));
  }

  void
  check_connected(const MeshData &mesh)
  {
    // Union-find over the vertices: the vertices of a cell are one set.
    std::vector<unsigned int> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto find = [&](unsigned int v) {
      while (parent[v] != v)
        v = parent[v] = parent[parent[v]];
      return v;
    };
    for (const auto &cell : mesh.cells)
      for (std::size_t i = 1; i < cell.size(); ++i)
        parent[find(cell[i])] = find(cell[0]);
    std::map<unsigned int, std::size_t> cells_per_piece;
    for (const auto &cell : mesh.cells)
      ++cells_per_piece[find(cell[0])];
    if (cells_per_piece.size() <= 1)
      return;
    const auto  smallest = std::min_element(cells_per_piece.begin(),
                                           cells_per_piece.end(),
                                           [](const auto &a, const auto &b) {
                                             return a.second < b.second;
                                           });
    std::size_t c        = 0;
    while (find(mesh.cells[c][0]) != smallest->first)
      ++c;
    dealii::Point<3> centre;
    for (const unsigned int v : mesh.cells[c])
      centre += mesh.vertices[v] / static_cast<double>(mesh.cells[c].size());
    AssertThrow(false,
                dealii::ExcMessage(
                  "Mesh file '" + mesh.file + "': the " + mesh.cell_kind() +
                  " form " + std::to_string(cells_per_piece.size()) +
                  " disconnected pieces (cells sharing no node); the "
                  "smallest has " +
                  std::to_string(smallest->second) + " cell(s), e.g. element " +
                  std::to_string(mesh.cell_ids.at(c)) + " at " +
                  format_point(centre) +
                  ". Remove the stray cells or merge the pieces' nodes "
                  "(gmsh: Coherence Mesh)."));
  }

  void
  check_vertex_references(const MeshData &mesh)
  {
    const unsigned int n =
      mesh.cell_type == dealii::ReferenceCells::Tetrahedron ? 4 : 8;
    AssertThrow(mesh.cell_ids.size() == mesh.cells.size() &&
                  mesh.vertex_ids.size() == mesh.vertices.size(),
                dealii::ExcMessage("Mesh file '" + mesh.file +
                                   "': inconsistent mesh data (ids)."));
    for (std::size_t c = 0; c < mesh.cells.size(); ++c)
      {
        const auto &cell = mesh.cells[c];
        AssertThrow(cell.size() == n,
                    dealii::ExcMessage(
                      "Mesh file '" + mesh.file + "': element " +
                      std::to_string(mesh.cell_ids[c]) + " has " +
                      std::to_string(cell.size()) + " vertices, not " +
                      std::to_string(n) + "."));
        for (unsigned int i = 0; i < n; ++i)
          {
            AssertThrow(cell[i] < mesh.vertices.size(),
                        dealii::ExcMessage(
                          "Mesh file '" + mesh.file + "': element " +
                          std::to_string(mesh.cell_ids[c]) +
                          " refers to vertex " + std::to_string(cell[i]) +
                          ", but the file has " +
                          std::to_string(mesh.vertices.size()) + " vertices."));
            for (unsigned int j = 0; j < i; ++j)
              AssertThrow(cell[i] != cell[j],
                          dealii::ExcMessage(
                            "Mesh file '" + mesh.file + "': element " +
                            std::to_string(mesh.cell_ids[c]) + " uses node " +
                            std::to_string(mesh.vertex_ids[cell[i]]) + " at " +
                            format_point(mesh.vertices[cell[i]]) +
                            " twice (a collapsed cell). Re-mesh."));
          }
      }
  }

  void
  check_unused_vertices(const MeshData &mesh)
  {
    std::vector<bool> used(mesh.vertices.size(), false);
    for (const auto &cell : mesh.cells)
      for (const unsigned int v : cell)
        used[v] = true;
    const std::size_t n_unused = std::count(used.begin(), used.end(), false);
    if (n_unused == 0)
      return;
    const std::size_t first =
      std::find(used.begin(), used.end(), false) - used.begin();
    AssertThrow(
      false,
      dealii::ExcMessage(
        "Mesh file '" + mesh.file + "': " + std::to_string(n_unused) +
        " of its " + std::to_string(mesh.vertices.size()) +
        " nodes belong to no " +
        (mesh.cell_type == dealii::ReferenceCells::Tetrahedron ? "tetrahedron"
                                                               : "hexahedron") +
        "; the first, node " + std::to_string(mesh.vertex_ids[first]) +
        ", at " + format_point(mesh.vertices[first]) +
        ". Remove the unused nodes (gmsh: save only the physical "
        "groups' elements and renumber; ParaView: Clean to Grid)."));
  }

  void
  check_duplicate_vertices(const MeshData &mesh,
                           const double    relative_tolerance)
  {
    if (mesh.vertices.empty())
      return;
    dealii::Point<3> lower = mesh.vertices[0], upper = mesh.vertices[0];
    for (const auto &x : mesh.vertices)
      for (unsigned int d = 0; d < 3; ++d)
        {
          lower[d] = std::min(lower[d], x[d]);
          upper[d] = std::max(upper[d], x[d]);
        }
    const double tolerance = relative_tolerance * lower.distance(upper);

    std::vector<unsigned int> order(mesh.vertices.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(),
              order.end(),
              [&](const unsigned int a, const unsigned int b) {
                return mesh.vertices[a][0] < mesh.vertices[b][0];
              });
    std::size_t                           n_pairs = 0;
    std::pair<unsigned int, unsigned int> first   = {
        std::numeric_limits<unsigned int>::max(),
        std::numeric_limits<unsigned int>::max()};
    for (std::size_t i = 0; i < order.size(); ++i)
      for (std::size_t j = i + 1;
           j < order.size() &&
           mesh.vertices[order[j]][0] - mesh.vertices[order[i]][0] <= tolerance;
           ++j)
        if (mesh.vertices[order[i]].distance(mesh.vertices[order[j]]) <=
            tolerance)
          {
            ++n_pairs;
            const std::pair<unsigned int, unsigned int> pair(
              std::min(order[i], order[j]),
              std::max(order[i], order[j]));
            if (pair < first)
              first = pair;
          }
    if (n_pairs == 0)
      return;
    AssertThrow(false,
                dealii::ExcMessage(
                  "Mesh file '" + mesh.file + "': " + std::to_string(n_pairs) +
                  " pairs of nodes coincide (within " +
                  format_number(relative_tolerance) +
                  " of the mesh diameter); the first, nodes " +
                  std::to_string(mesh.vertex_ids[first.first]) + " and " +
                  std::to_string(mesh.vertex_ids[first.second]) + ", at " +
                  format_point(mesh.vertices[first.first]) +
                  ". The cells on either side are not connected: merge "
                  "duplicate nodes (gmsh: Coherence Mesh; ParaView: Clean to "
                  "Grid; meshio: remove duplicate points)."));
  }

  void
  check_cell_orientation(const MeshData &mesh, const double relative_tolerance)
  {
    const bool   tets  = mesh.cell_type == dealii::ReferenceCells::Tetrahedron;
    std::size_t  n_bad = 0, first = 0;
    unsigned int first_vertex = 0;
    double       first_value  = 0;
    for (std::size_t c = 0; c < mesh.cells.size(); ++c)
      {
        const auto  &cell      = mesh.cells[c];
        const auto  &x         = mesh.vertices;
        const double L         = longest_edge(mesh, cell);
        const double tolerance = relative_tolerance * L * L * L;
        if (tets)
          {
            const double volume = determinant(x[cell[1]] - x[cell[0]],
                                              x[cell[2]] - x[cell[0]],
                                              x[cell[3]] - x[cell[0]]) /
                                  6.0;
            if (volume <= tolerance && n_bad++ == 0)
              {
                first       = c;
                first_value = volume;
              }
          }
        else
          for (unsigned int v = 0; v < 8; ++v)
            {
              // Along reference direction d: from the vertex with bit d
              // cleared to the one with it set (lexicographic numbering).
              std::array<dealii::Tensor<1, 3>, 3> e;
              for (unsigned int d = 0; d < 3; ++d)
                e[d] = x[cell[v | (1u << d)]] - x[cell[v & ~(1u << d)]];
              const double J = determinant(e[0], e[1], e[2]);
              if (J <= tolerance)
                {
                  if (n_bad++ == 0)
                    {
                      first        = c;
                      first_vertex = v;
                      first_value  = J;
                    }
                  break;
                }
            }
      }
    if (n_bad == 0)
      return;
    const auto &cell = mesh.cells[first];
    if (tets)
      {
        AssertThrow(false,
                    dealii::ExcMessage(
                      "Mesh file '" + mesh.file +
                      "': " + std::to_string(n_bad) + " of its " +
                      std::to_string(mesh.cells.size()) +
                      " tetrahedra are inverted or flat (signed volume <= " +
                      format_number(relative_tolerance) +
                      " x longest edge^3); the first, element " +
                      std::to_string(mesh.cell_ids[first]) +
                      ", has signed volume " + format_number(first_value) +
                      " and vertices " + list_points(mesh, cell) +
                      ". Re-mesh, or if all are inverted write the vertices in "
                      "gmsh's order (0, 1, 2 counter-clockwise seen from 3)."));
      }
    else
      {
        AssertThrow(
          false,
          dealii::ExcMessage(
            "Mesh file '" + mesh.file + "': " + std::to_string(n_bad) +
            " of its " + std::to_string(mesh.cells.size()) +
            " hexahedra have a non-positive Jacobian at a vertex "
            "(<= " +
            format_number(relative_tolerance) +
            " x longest edge^3); the first, element " +
            std::to_string(mesh.cell_ids[first]) + ", has " +
            format_number(first_value) + " at its vertex " +
            format_point(mesh.vertices[cell[first_vertex]]) +
            ". Re-mesh (smaller elements where the surface is curved, "
            "or optimise the mesh) or fix the vertex order (gmsh's: "
            "bottom face counter-clockwise seen from the top)."));
      }
  }

  // ---------------------------------------------------------------------------
  // Surfaces of boundary parts

  namespace
  {
    /// SurfaceTopology plus where its first offenders are.
    struct SurfaceReport
    {
      SurfaceTopology  topology;
      dealii::Point<3> non_manifold_edge[2];
      dealii::Point<3> junction;
      unsigned int     junction_degree = 0;
      /// The smallest rim loop: its number of edges and one of its vertices.
      unsigned int     smallest_loop_edges = 0;
      dealii::Point<3> smallest_loop_vertex;
    };

    SurfaceReport
    surface_report(const dealii::Triangulation<3, 3> &tria,
                   const dealii::types::boundary_id   id)
    {
      SurfaceReport report;
      auto         &t = report.topology;
      // Per line of the coarse mesh: in how many faces of the part it lies.
      std::unordered_map<unsigned int, unsigned int> n_faces_of_line;
      std::unordered_map<unsigned int,
                         typename dealii::Triangulation<3, 3>::line_iterator>
        lines;
      for (const auto &cell : tria.cell_iterators_on_level(0))
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == id)
            {
              ++t.n_faces;
              for (unsigned int l = 0; l < face->n_lines(); ++l)
                {
                  const auto line = face->line(l);
                  ++n_faces_of_line[line->index()];
                  lines.emplace(line->index(), line);
                }
            }
      t.n_edges = n_faces_of_line.size();

      // Rim edges, and the rim's vertices with their rim edges.
      std::map<unsigned int, std::vector<unsigned int>> rim_neighbours;
      std::map<unsigned int, dealii::Point<3>>          vertex_of;
      std::vector<unsigned int> sorted_lines = first_members(n_faces_of_line);
      std::sort(sorted_lines.begin(), sorted_lines.end());
      for (const unsigned int index : sorted_lines)
        {
          const unsigned int count = n_faces_of_line[index];
          const auto        &line  = lines.at(index);
          if (count > 2 && t.n_non_manifold_edges++ == 0)
            {
              report.non_manifold_edge[0] = line->vertex(0);
              report.non_manifold_edge[1] = line->vertex(1);
            }
          if (count == 1)
            {
              ++t.n_rim_edges;
              const unsigned int a = line->vertex_index(0),
                                 b = line->vertex_index(1);
              rim_neighbours[a].push_back(b);
              rim_neighbours[b].push_back(a);
              vertex_of[a] = line->vertex(0);
              vertex_of[b] = line->vertex(1);
            }
        }
      for (const auto &[v, neighbours] : rim_neighbours)
        if (neighbours.size() != 2 && t.n_rim_junctions++ == 0)
          {
            report.junction        = vertex_of[v];
            report.junction_degree = neighbours.size();
          }

      // Connected components of the rim.
      std::map<unsigned int, bool> seen;
      for (const auto &[start, neighbours] : rim_neighbours)
        {
          if (seen[start])
            continue;
          ++t.n_rim_loops;
          unsigned int              n_vertices = 0;
          std::vector<unsigned int> stack      = {start};
          seen[start]                          = true;
          while (!stack.empty())
            {
              const unsigned int v = stack.back();
              stack.pop_back();
              ++n_vertices;
              for (const unsigned int w : rim_neighbours[v])
                if (!seen[w])
                  {
                    seen[w] = true;
                    stack.push_back(w);
                  }
            }
          if (report.smallest_loop_edges == 0 ||
              n_vertices < report.smallest_loop_edges)
            {
              // A closed loop has as many edges as vertices.
              report.smallest_loop_edges  = n_vertices;
              report.smallest_loop_vertex = vertex_of[start];
            }
        }
      return report;
    }
  } // namespace

  SurfaceTopology
  surface_topology(const dealii::Triangulation<3, 3> &tria,
                   const dealii::types::boundary_id   id)
  {
    return surface_report(tria, id).topology;
  }

  void
  check_part_surface(const dealii::Triangulation<3, 3> &tria,
                     const BoundaryNames               &names,
                     const std::string                 &part,
                     const unsigned int                 n_rim_loops)
  {
    const auto          id     = names.id(part);
    const SurfaceReport report = surface_report(tria, id);
    const auto         &t      = report.topology;
    const std::string   what =
      "Boundary part '" + part + "' of " + names.source();
    AssertThrow(t.n_faces > 0,
                dealii::ExcMessage(what + " has no faces (boundary id " +
                                   std::to_string(id) + ")."));
    AssertThrow(t.n_non_manifold_edges == 0,
                dealii::ExcMessage(
                  what + " is not a manifold surface: " +
                  std::to_string(t.n_non_manifold_edges) +
                  " of its edges lie in more than two of its faces; the "
                  "first joins " +
                  format_point(report.non_manifold_edge[0]) + " and " +
                  format_point(report.non_manifold_edge[1]) +
                  ". Tag each sheet of the surface as its own part, or fix the "
                  "mesh (duplicate or folded faces)."));
    AssertThrow(
      t.n_rim_junctions == 0,
      dealii::ExcMessage(
        what + " is pinched: at " + std::to_string(t.n_rim_junctions) +
        " vertices of its rim (the edges in one of its faces) the rim "
        "does not pass through exactly once; the first at " +
        format_point(report.junction) + " has " +
        std::to_string(report.junction_degree) +
        " rim edges. Fix the surface so its rim is a set of separate "
        "closed loops."));
    const std::string smallest =
      t.n_rim_loops == 0
        ? std::string("")
        : "; the smallest has " + std::to_string(report.smallest_loop_edges) +
            " edges, through " + format_point(report.smallest_loop_vertex);
    AssertThrow(t.n_rim_loops == n_rim_loops,
                dealii::ExcMessage(
                  what + " has " + std::to_string(t.n_rim_loops) +
                  " rim loops (closed curves of edges in one of its faces), "
                  "not " +
                  std::to_string(n_rim_loops) + " (" +
                  (n_rim_loops == 0   ? "a closed surface"
                   : n_rim_loops == 1 ? "a surface open at one ring"
                                      : "the expected open rings") +
                  ")" + smallest +
                  ". A hole or a gap in the surface (or faces of it tagged as "
                  "another part) adds a loop, a closed surface has none: fix "
                  "the mesh or its tags."));
  }


  namespace
  {
    using Line = dealii::Triangulation<3, 3>::line_iterator;
    using Cell = dealii::Triangulation<3, 3>::cell_iterator;

    /// The edges of the faces of a cavity part on the coarse mesh, with the
    /// faces around each and the first face's cell; and the base's edges.
    struct CavityEdges
    {
      struct Edge
      {
        Line           line;
        unsigned int   n_faces = 0;
        dealii::CellId first_cell;
        bool           first_owned = false;
      };
      std::map<unsigned int, Edge> edges; ///< by line index, sorted
      std::set<unsigned int>       base_lines;
    };

    CavityEdges
    cavity_edges(const dealii::Triangulation<3, 3> &tria,
                 const bool                         whole,
                 const dealii::types::boundary_id   cavity_id,
                 const dealii::types::boundary_id   base_id)
    {
      CavityEdges result;
      // A fully distributed mesh has no coarser level: its active cells.
      const auto cells =
        whole ? tria.cell_iterators_on_level(0)
              : dealii::IteratorRange<Cell>(tria.begin_active(), tria.end());
      for (const auto &cell : cells)
        {
          if (!whole && cell->is_artificial())
            continue;
          const bool owned = whole || cell->is_locally_owned();
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == base_id)
              for (unsigned int l = 0; l < face->n_lines(); ++l)
                result.base_lines.insert(face->line_index(l));
            else if (face->at_boundary() && face->boundary_id() == cavity_id)
              for (unsigned int l = 0; l < face->n_lines(); ++l)
                {
                  auto &edge = result.edges[face->line_index(l)];
                  if (edge.n_faces++ == 0 || cell->id() < edge.first_cell)
                    {
                      edge.line        = face->line(l);
                      edge.first_cell  = cell->id();
                      edge.first_owned = owned;
                    }
                }
        }
      return result;
    }

    /// The global count of @p local and the first offender's end points, from
    /// the lowest rank that has one (collective).
    std::pair<unsigned int, std::array<dealii::Point<3>, 2>>
    global_offenders(const unsigned int                     local,
                     const std::array<dealii::Point<3>, 2> &first,
                     const MPI_Comm                         comm)
    {
      const unsigned int n_ranks =
        dealii::Utilities::MPI::n_mpi_processes(comm);
      const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
      const unsigned int total = dealii::Utilities::MPI::sum(local, comm);
      const unsigned int root =
        dealii::Utilities::MPI::min(local > 0 ? rank : n_ranks, comm);
      if (total == 0 || root == n_ranks)
        return {total, first};
      return {total, dealii::Utilities::MPI::broadcast(comm, first, root)};
    }
  } // namespace

  void
  check_cavity_rim(const dealii::Triangulation<3, 3> &tria,
                   const BoundaryNames               &names,
                   const std::string                 &cavity,
                   const std::string                 &base)
  {
    // Every rank holds the whole coarse mesh (serial, p4est), or its part
    // of the mesh and the cells around (fully distributed): there, each edge
    // is counted by one rank.
    const bool whole =
      dynamic_cast<
        const dealii::parallel::fullydistributed::Triangulation<3> *>(&tria) ==
      nullptr;
    const CavityEdges found =
      cavity_edges(tria, whole, names.id(cavity), names.id(base));
    const MPI_Comm                  comm   = tria.get_communicator();
    unsigned int                    n_open = 0, n_non_manifold = 0;
    std::array<dealii::Point<3>, 2> first_open, first_non_manifold;
    for (const auto &[index, edge] : found.edges)
      {
        if (!whole && !edge.first_owned)
          continue;
        const std::array<dealii::Point<3>, 2> ends = {
          {edge.line->vertex(0), edge.line->vertex(1)}};
        if (edge.n_faces > 2 && n_non_manifold++ == 0)
          first_non_manifold = ends;
        if (edge.n_faces == 1 && found.base_lines.count(index) == 0 &&
            n_open++ == 0)
          first_open = ends;
      }
    if (!whole)
      {
        std::tie(n_open, first_open) =
          global_offenders(n_open, first_open, comm);
        std::tie(n_non_manifold, first_non_manifold) =
          global_offenders(n_non_manifold, first_non_manifold, comm);
      }
    const std::string what = "The cavity '" + cavity + "' of " + names.source();
    AssertThrow(n_non_manifold == 0,
                dealii::ExcMessage(
                  what + " is not a manifold surface: " +
                  std::to_string(n_non_manifold) +
                  " of its edges lie in more than two of its faces; the "
                  "first joins " +
                  format_point(first_non_manifold[0]) + " and " +
                  format_point(first_non_manifold[1]) +
                  ". Fix the mesh (duplicate or folded faces) or its tags."));
    AssertThrow(n_open == 0,
                dealii::ExcMessage(
                  what + " is open away from its lid, the part '" + base +
                  "': " + std::to_string(n_open) +
                  " edges of its rim (edges in one of its faces) are not "
                  "edges of '" +
                  base + "'; the first joins " + format_point(first_open[0]) +
                  " and " + format_point(first_open[1]) +
                  ". Part of the cavity's surface is tagged as another part, "
                  "or the surface has a hole: fix the mesh or its tags."));
  }
} // namespace systole::Geometry
