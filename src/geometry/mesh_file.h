#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/reference_cell.h>
#include <deal.II/grid/tria.h>

#include "geometry/boundary_names.h"
#include "geometry/mesh_data.h"

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace systole::Geometry
{
  /// Parse a name table written "part: file name; part: tag; ..." (e.g.
  /// "base: BASE; endocardium: ENDO; epicardium: 7"). Blanks around names are
  /// dropped; an empty @p text is the empty table. Throws, naming @p entry (the
  /// parameter it came from), on an entry without ':', an empty name or a part
  /// named twice.
  BoundaryNameTable
  parse_boundary_name_table(const std::string &text, const std::string &entry);

  /// The file @p name given in a parameter file whose folder is
  /// @p base_directory: a relative name is taken from there (unless
  /// @p base_directory is empty), then normalised; an empty name stays
  /// empty (no file).
  std::string
  file_in_directory(const std::string &name, const std::string &base_directory);

  /// How to read a mesh file (read_mesh_file()).
  struct MeshFileOptions
  {
    /// Factor from the file's length unit to mm. Units: mm per file unit.
    double scale = 1.0;
    /// Which face tags of the file become which boundary parts. Empty: every
    /// face tag becomes a part, named by the file's name for it (a gmsh
    /// physical name) or else by the tag's number ("5").
    BoundaryNameTable boundary_names;
    /// .vtu only: name of the integer cell-data array that gives the
    /// triangle/quad cells of the file their face tag. Empty: the file's faces
    /// are not used and every boundary face gets the default id.
    std::string face_tag_array;
  };

  /// Read a gmsh .msh file (format 2.2 or 4.1, ASCII or binary) through the
  /// gmsh API: its nodes, its 3D elements (linear tetrahedra, type 4, or
  /// hexahedra, type 5; anything else, or both, is an error) and the triangles
  /// (type 2) and quadrilaterals (type 3) of its 2D physical groups. Point,
  /// curve and volume groups are ignored. Note: gmsh drops the nodes no element
  /// uses when it reads format 2.2.
  MeshData
  read_gmsh_data(const std::string &file);

  /// Read a VTK XML unstructured grid (.vtu): points, VTK_TETRA or
  /// VTK_HEXAHEDRON cells (anything else but vertex and line cells is an
  /// error), and, if @p face_tag_array is not empty, the VTK_TRIANGLE /
  /// VTK_QUAD cells with their tags from that integer cell-data array. A file
  /// with only volume cells cannot tag faces (a volume tag array does not say
  /// which faces are which): asking for a face tag array there is an error.
  MeshData
  read_vtu_data(const std::string &file, const std::string &face_tag_array);

  /// Per-cell unit vectors (e.g. fibre directions) from the 3-component array
  /// @p array of the .vtu file @p file, one per volume cell in the order of
  /// the cells that read_mesh_file() makes of the same file (its coarse cells:
  /// cell->index() on level 0). A cell array gives each cell its vector; a
  /// point array (used only if there is no cell array of that name) gives
  /// each cell the dominant direction of its vertices' vectors (the
  /// eigenvector of the largest eigenvalue of the sum of a a^T, so vertex
  /// vectors of opposite sign do not cancel), signed like the vector at the
  /// cell's first vertex. All normalised; a zero vector is an error naming
  /// the cell and its centre. Units: -.
  std::vector<dealii::Tensor<1, 3>>
  read_vtu_cell_vectors(const std::string &file, const std::string &array);

  /// Build @p tria (empty; serial, or parallel::distributed for hexahedra) from
  /// @p mesh: every boundary face (a face of one cell) that is a face of the
  /// file in a tag the table uses gets that tag as boundary id; the other
  /// boundary faces get default_boundary_id(). A table entry whose file name
  /// or tag names no boundary face, a boundary face in two used tags, and a
  /// tagged face that is no face of any cell are errors; tagged faces between
  /// two cells are ignored.
  /// @return the parts: the table's names, or with an empty table every face
  /// tag of the file (named as in MeshFileOptions::boundary_names).
  BoundaryNames
  build_triangulation(const MeshData              &mesh,
                      const BoundaryNameTable     &table,
                      dealii::Triangulation<3, 3> &tria);

  /// The boundary id of boundary faces that carry no tag the table uses: 0
  /// unless a used tag is 0, else the smallest id no used tag has.
  unsigned int
  default_boundary_id(const MeshData &mesh, const BoundaryNameTable &table);

  /// Read a mesh file into @p tria (empty): a gmsh .msh or a VTK .vtu file,
  /// chosen by extension. The lengths are multiplied by @p options.scale, the
  /// mesh is checked (check_mesh_data(): inverted or flat cells, duplicate and
  /// unused nodes) and built by build_triangulation().
  BoundaryNames
  read_mesh_file(const std::string           &file,
                 const MeshFileOptions       &options,
                 dealii::Triangulation<3, 3> &tria);

  /// read_mesh_file() of a gmsh file with the empty name table: physical
  /// surface tags become boundary ids and physical surface names boundary
  /// names. Lengths are multiplied by @p scale.
  BoundaryNames
  read_gmsh(const std::string           &file,
            const double                 scale,
            dealii::Triangulation<3, 3> &tria);

  /// Holds the gmsh API initialised (quietly: General.Terminal = 0, no
  /// configuration files). Sessions nest: the first initialises gmsh, the last
  /// to end finalises it, so gmsh::initialize / finalize are called once per
  /// outermost session. Code that calls the gmsh API itself while it also
  /// uses read_gmsh_data() must hold a session (and not call
  /// gmsh::initialize / finalize itself). Not for concurrent use from several
  /// threads (gmsh is not thread-safe).
  class GmshSession
  {
  public:
    GmshSession();
    ~GmshSession();
    GmshSession(const GmshSession &) = delete;
    GmshSession &
    operator=(const GmshSession &) = delete;
  };
} // namespace systole::Geometry
