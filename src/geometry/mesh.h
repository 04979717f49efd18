#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include "geometry/boundary_names.h"
#include "geometry/ellipsoid.h"

#include <array>
#include <optional>
#include <string>

namespace dealii
{
  class ParameterHandler;
  template <int dim, int spacedim>
  class Triangulation;
} // namespace dealii

namespace systole::Geometry
{
  /// Which mesh to build and how (subsection "Geometry" of the parameter file).
  struct Parameters
  {
    enum class Type
    {
      ellipsoid,
      box,
      gmsh,
      arostica ///< the ellipsoid generator with LVShape::arostica()
    };

    Type         type               = Type::ellipsoid;
    unsigned int global_refinements = 0;
    /// Refinements near local_refinement_center after the global ones.
    unsigned int                    local_refinements = 0;
    std::optional<dealii::Point<3>> local_refinement_center;       ///< [mm]
    double                          local_refinement_radius = 3.0; ///< [mm]
    /// A generated mesh split into tetrahedra (Cell shape = tetrahedra).
    bool tetrahedra = false;

    LVShape     lv_shape;
    LVMeshCells lv_cells;

    dealii::Point<3>            box_lower;
    dealii::Point<3>            box_upper;
    std::array<unsigned int, 3> box_cells = {{1, 1, 1}};

    std::string
      mesh_file; ///< absolute, resolved against the parameter file's folder
    double mesh_scale = 1.0; ///< [mm per file unit]
    /// Systole's part names -> the file's names or tags; empty: the file's.
    BoundaryNameTable boundary_names;
    /// .vtu: the cell-data array that tags the boundary faces.
    std::string face_tag_array;

    static void
    declare(dealii::ParameterHandler &prm);

    /// @param[in] prm_directory folder of the parameter file, for relative mesh
    /// paths.
    static Parameters
    parse(const dealii::ParameterHandler &prm,
          const std::string              &prm_directory);
  };

  /// Build the coarse mesh described by @p params into @p tria (empty; serial
  /// or distributed: every rank builds the same coarse mesh), attach its
  /// manifolds and refine globally.
  /// @param[in] saved_mesh if not empty (@p tria must be a
  ///   parallel::distributed::Triangulation): instead of refining, load the
  ///   refinement, and the cell data attached there, from this file written
  ///   by its save() (a checkpoint of a mesh built from the same @p params;
  ///   the partition fits the current number of ranks)
  /// @return the names of its boundary parts.
  BoundaryNames
  create_mesh(const Parameters            &params,
              dealii::Triangulation<3, 3> &tria,
              const std::string           &saved_mesh = "");

  /// The plane of a planar boundary part (the base): a point on it and its unit
  /// normal.
  struct Plane
  {
    dealii::Point<3>     point;
    dealii::Tensor<1, 3> normal;
  };

  /// Fit the plane through the vertices of all faces with boundary id @p id
  /// (collective over the triangulation's communicator). Throws if there are no
  /// such faces or they are not planar within @p relative_tolerance of the mesh
  /// diameter.
  Plane
  boundary_plane(const dealii::Triangulation<3, 3> &tria,
                 const dealii::types::boundary_id   id,
                 const std::string                 &name,
                 const double                       relative_tolerance = 1e-6);

  /// The plane that closes the cavity bounded by boundary part @p cavity
  /// (collective): the plane of the base (boundary_plane) where the base is
  /// flat, as for every mesh with one cut plane; otherwise (each surface cut
  /// at its own height, the base a ruled surface: Aróstica et al. 2025) the
  /// plane fitted through the vertices where @p cavity meets the base (its
  /// basal ring), which must then be planar within 1e-6 of the mesh diameter.
  Plane
  cavity_lid(const dealii::Triangulation<3, 3> &tria,
             const BoundaryNames               &names,
             const std::string                 &cavity,
             const std::string                 &base = "base");

  /// Throw unless at least one face of the mesh (on any rank) carries boundary
  /// part @p name. The message names the part, the mesh (its file) and the
  /// parts it has.
  void
  require_boundary(const dealii::Triangulation<3, 3> &tria,
                   const BoundaryNames               &names,
                   const std::string                 &name);
} // namespace systole::Geometry
