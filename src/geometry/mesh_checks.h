#pragma once

#include <deal.II/base/types.h>
#include <deal.II/grid/tria.h>

#include "geometry/boundary_names.h"
#include "geometry/mesh_data.h"

#include <string>

namespace systole::Geometry
{
  /// Every check of a mesh as read, in this order: check_coordinates(),
  /// check_vertex_references(), check_unused_vertices(),
  /// check_duplicate_vertices(), check_cell_orientation(), check_connected().
  /// Each throws one line naming the file, how many offenders there are, the
  /// first one with its coordinates, and the fix.
  void
  check_mesh_data(const MeshData &mesh);

  /// Throw if a vertex has a coordinate that is not a finite number (NaN,
  /// infinity) or whose magnitude exceeds @p max_coordinate (a corrupt or
  /// mis-scaled file: the other checks would fail on it with misleading
  /// messages). Units: the file's, as read (default 1e9: 1000 km in mm).
  void
  check_coordinates(const MeshData &mesh, const double max_coordinate = 1e9);

  /// Throw if the cells form more than one piece (cells connected through
  /// shared vertices): a stray cell or a second body would be a separate,
  /// unsupported solid. Names the number of pieces and a cell of the
  /// smallest one with its centre.
  void
  check_connected(const MeshData &mesh);

  /// Throw unless every cell refers to existing vertices, each at most once.
  void
  check_vertex_references(const MeshData &mesh);

  /// Throw if a vertex belongs to no volume cell (a node used only by faces,
  /// lines or nothing).
  void
  check_unused_vertices(const MeshData &mesh);

  /// Throw if two vertices lie within @p relative_tolerance times the mesh
  /// diameter (the diagonal of its bounding box) of each other: the cells on
  /// either side would not be connected. O(n log n): sorted by x.
  void
  check_duplicate_vertices(const MeshData &mesh,
                           const double    relative_tolerance = 1e-10);

  /// Throw if a cell is inverted or flat. Tetrahedra: the signed volume
  /// det(x1 - x0, x2 - x0, x3 - x0) / 6 (positive for gmsh's and VTK's vertex
  /// order) must exceed @p relative_tolerance times the cube of the cell's
  /// longest edge. Hexahedra: the Jacobian of the trilinear map at each of the
  /// 8 vertices (the determinant of the three edges along the reference
  /// directions there), likewise.
  void
  check_cell_orientation(const MeshData &mesh,
                         const double    relative_tolerance = 1e-12);

  /// The topology of the surface formed by the faces of one boundary part.
  struct SurfaceTopology
  {
    unsigned int n_faces = 0;
    unsigned int n_edges = 0;
    /// Edges in exactly one face of the part (its rim).
    unsigned int n_rim_edges = 0;
    /// Edges in more than two faces of the part.
    unsigned int n_non_manifold_edges = 0;
    /// Rim vertices with other than two rim edges (the rim is not a set of
    /// disjoint closed loops there, e.g. two loops touch at the vertex).
    unsigned int n_rim_junctions = 0;
    /// Connected components of the rim (closed loops when n_rim_junctions is
    /// 0): 0 for a closed surface, 1 for a disc (the endocardium of a
    /// ventricle: its basal ring), 2 for an annulus (the base of a ventricle).
    unsigned int n_rim_loops = 0;
  };

  /// The topology of the boundary faces with id @p id of the coarse mesh
  /// (level 0: refinement does not change it; on a
  /// parallel::distributed::Triangulation every rank has the whole coarse mesh,
  /// so all ranks get the same).
  SurfaceTopology
  surface_topology(const dealii::Triangulation<3, 3> &tria,
                   const dealii::types::boundary_id   id);

  /// Throw (one line: the part, the mesh, the count, the first offending edge
  /// or vertex with coordinates) unless boundary part @p part is a manifold
  /// surface with @p n_rim_loops closed rim loops: every edge of its faces lies
  /// in one face (a rim edge) or two faces of the part, never more; every rim
  /// vertex has exactly two rim edges; the rim edges form @p n_rim_loops
  /// loops. A part that must close a cavity with a plane lid (an endocardium)
  /// has 1; a hole in it adds one. Orientation is not checked.
  void
  check_part_surface(const dealii::Triangulation<3, 3> &tria,
                     const BoundaryNames               &names,
                     const std::string                 &part,
                     const unsigned int                 n_rim_loops);

  /// Throw (one line: the cavity, the mesh, the count, the first offending
  /// edge with coordinates) unless boundary part @p cavity is a surface that
  /// the part @p base closes: every edge of its faces lies in at most two of
  /// them, and each edge in only one (its rim) is an edge of a face of
  /// @p base. A cavity with part of its surface tagged as another part, or
  /// with a hole, fails. Counts are global on a distributed mesh (each edge
  /// counted by the rank owning its first face's cell); collective.
  void
  check_cavity_rim(const dealii::Triangulation<3, 3> &tria,
                   const BoundaryNames               &names,
                   const std::string                 &cavity,
                   const std::string                 &base);
} // namespace systole::Geometry
