#pragma once

#include <deal.II/base/point.h>
#include <deal.II/grid/reference_cell.h>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace systole::Geometry
{
  /// A volume mesh as read from a file, before it becomes a Triangulation: all
  /// tetrahedra or all hexahedra, and tagged boundary faces.
  struct MeshData
  {
    /// A triangle or quadrilateral of the file with its face tag.
    struct TaggedFace
    {
      std::vector<unsigned int> vertices; ///< indices into MeshData::vertices
      int                       tag;      ///< the file's tag (physical group)
      std::size_t               id;       ///< the file's element number
    };

    std::string file; ///< where the mesh came from, for messages

    /// Vertex coordinates. Units: the file's length unit until scaled.
    std::vector<dealii::Point<3>> vertices;
    /// The file's number of each vertex (gmsh node tag, VTK point index).
    std::vector<std::size_t> vertex_ids;

    /// ReferenceCells::Tetrahedron or ReferenceCells::Hexahedron.
    dealii::ReferenceCell cell_type;
    /// Vertex indices of each volume cell in deal.II's order (for hexahedra
    /// lexicographic: gmsh/VTK vertices 0 1 3 2 4 5 7 6).
    std::vector<std::vector<unsigned int>> cells;
    /// The file's number of each cell (gmsh element tag, VTK cell index).
    std::vector<std::size_t> cell_ids;

    /// The file's boundary faces (gmsh: the 2D elements of each 2D physical
    /// group, once per group; VTK: triangle/quad cells with their tag).
    /// A node halfway along an edge of a second-order tetrahedron.
    struct MidEdgeNode
    {
      unsigned int     first;    ///< index of one corner into vertices
      unsigned int     second;   ///< index of the other corner
      dealii::Point<3> position; ///< where the file puts the node
    };

    /// The mid-edge nodes of the 10-node tetrahedra (once per cell, so an
    /// edge shared by cells appears once for each); empty for a linear mesh.
    /// The vertices above are the corners only.
    std::vector<MidEdgeNode> mid_edge_nodes;

    std::vector<TaggedFace> faces;
    /// The file's name of a face tag, where it has one (gmsh physical names).
    std::map<int, std::string> tag_names;

    /// "tetrahedra" or "hexahedra".
    std::string
    cell_kind() const
    {
      return cell_type == dealii::ReferenceCells::Tetrahedron ? "tetrahedra"
                                                              : "hexahedra";
    }
  };
} // namespace systole::Geometry
