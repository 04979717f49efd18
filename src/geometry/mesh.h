#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "geometry/boundary_names.h"
#include "geometry/ellipsoid.h"

#include <array>
#include <optional>
#include <string>

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

  /// How the cavity bounded by a boundary part is closed (see
  /// Mechanics::CavityVolume): by a plane where its rim is planar, otherwise
  /// by the fan (cone) over its rim.
  struct CavityClosure
  {
    /// The lid plane, if the rim is planar: the plane of the base
    /// (boundary_plane) where the base is flat, as for every mesh with one
    /// cut plane; otherwise (each surface cut at its own height, the base a
    /// ruled surface: Aróstica et al. 2025) the plane fitted through the
    /// vertices where the cavity meets the base (its basal ring), if they lie
    /// within 1e-6 of the mesh diameter of it. Empty: close by the rim fan.
    std::optional<Plane> plane;
    /// Largest distance of a basal-ring vertex from the ring's best plane
    /// [mm] (0 where the base is flat).
    double off_plane = 0.0;
    /// Size of the basal ring: the diagonal of the bounding box of its
    /// vertices [mm] (0 where the base is flat).
    double rim_size = 0.0;
  };

  /// A rim farther than this fraction of its size (CavityClosure::rim_size)
  /// from its best plane is worth a warning: its fan lid differs much from
  /// a valve plane.
  constexpr double rim_warning_fraction = 0.05;

  /// The closure of the cavity bounded by boundary part @p cavity
  /// (collective). Throws if the base is not flat and meets the cavity in
  /// fewer than 3 vertices.
  CavityClosure
  cavity_closure(const dealii::Triangulation<3, 3> &tria,
                 const BoundaryNames               &names,
                 const std::string                 &cavity,
                 const std::string                 &base = "base");

  /// The plane that closes the cavity bounded by boundary part @p cavity
  /// (collective): cavity_closure()'s plane; throws if the rim is not planar
  /// (within 1e-6 of the mesh diameter).
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

  /// require_boundary() for each of @p parts, after checking that @p names
  /// has it; a part it lacks throws "<needs>; <mesh> has no part '<part>' (it
  /// has: <its parts>)." @p needs says who needs which parts, e.g. "Fibres /
  /// Generator = arostica needs the boundary parts endocardium and
  /// epicardium".
  void
  require_boundaries(const dealii::Triangulation<3, 3> &tria,
                     const BoundaryNames               &names,
                     const std::vector<std::string>    &parts,
                     const std::string                 &needs);
} // namespace systole::Geometry
