#pragma once

#include <deal.II/base/types.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace systole::Geometry
{
  /// The name table of a mesh file: pairs (Systole's part name, the file's
  /// name or integer tag of a set of boundary faces), in the order given.
  /// E.g. {{"base", "BASE"}, {"endocardium", "6"}} (see read_mesh_file()).
  using BoundaryNameTable = std::vector<std::pair<std::string, std::string>>;

  /// Names of the boundary parts of a mesh and the boundary ids they carry,
  /// e.g. "endocardium", "epicardium", "base" for a ventricle, "x_min" ...
  /// "z_max" for a box. Components ask for the parts they need by name, so a
  /// mesh without one fails with a message naming it.
  class BoundaryNames
  {
  public:
    /// @param[in] source where the names come from, used in error messages
    ///            (e.g. "the gmsh file meshes/lv.msh").
    explicit BoundaryNames(const std::string &source = "the mesh");

    void
    add(const std::string &name, const dealii::types::boundary_id id);

    bool
    has(const std::string &name) const;

    /// The id of part @p name; throws an error naming the part, the mesh and
    /// the parts it has.
    dealii::types::boundary_id
    id(const std::string &name) const;

    /// All names, sorted.
    std::vector<std::string>
    names() const;

    /// names() joined by ", " ("none" if there are none), for messages.
    std::string
    listed() const;

    const std::string &
    source() const;

  private:
    std::string                                       source_description;
    std::map<std::string, dealii::types::boundary_id> ids;
  };
} // namespace systole::Geometry
