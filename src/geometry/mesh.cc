#include "geometry/mesh.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include "geometry/mesh_file.h"

#include <filesystem>
#include <limits>
#include <set>

namespace systole::Geometry
{
  namespace
  {
    using dealii::Patterns::Double;
    using dealii::Patterns::Integer;

    /// Sums @p values over the ranks of @p comm, in place (deal.II 9.4's
    /// library has no Utilities::MPI::sum of a std::array).
    template <std::size_t n>
    void
    sum_in_place(std::array<double, n> &values, const MPI_Comm comm)
    {
      MPI_Allreduce(MPI_IN_PLACE,
                    values.data(),
                    values.size(),
                    MPI_DOUBLE,
                    MPI_SUM,
                    comm);
    }

    dealii::Point<3>
    parse_point(const std::string &text, const std::string &entry)
    {
      const auto values = dealii::Utilities::string_to_double(
        dealii::Utilities::split_string_list(text, ','));
      AssertThrow(values.size() == 3,
                  dealii::ExcMessage(
                    entry + " must have three comma-separated values, not '" +
                    text + "'."));
      return dealii::Point<3>(values[0], values[1], values[2]);
    }

    /// Geometry / Ellipsoid: the truncated-ellipsoid ventricle.
    void
    declare_ellipsoid(dealii::ParameterHandler &prm)
    {
      prm.enter_subsection("Ellipsoid");
      {
        prm.declare_entry(
          "Endocardium short radius",
          "7",
          Double(0.0),
          "Short (equatorial) radius r_s of the endocardium. Units: mm. "
          "Default: Land et al. 2015 benchmark ventricle.");
        prm.declare_entry(
          "Endocardium long radius",
          "17",
          Double(0.0),
          "Long (apex-base) radius r_l of the endocardium. Units: mm. "
          "Default: Land et al. 2015.");
        prm.declare_entry(
          "Epicardium short radius",
          "10",
          Double(0.0),
          "Short radius of the epicardium; the radii vary linearly through "
          "the wall. Units: mm. Default: Land et al. 2015.");
        prm.declare_entry(
          "Epicardium long radius",
          "20",
          Double(0.0),
          "Long radius of the epicardium. Units: mm. Default: Land et al. 2015.");
        prm.declare_entry(
          "Base height",
          "5",
          Double(),
          "z of the base plane that truncates the ellipsoid (the apex points "
          "to -z). Units: mm. Default: Land et al. 2015.");
        prm.declare_entry(
          "Cells around circumference",
          "8",
          Integer(8),
          "Coarse cells around the long axis; a multiple of 8. Units: -.");
        prm.declare_entry(
          "Cells from apex to base",
          "3",
          Integer(2),
          "Coarse cells along a meridian from apex to base; more than "
          "(cells around circumference)/8. Units: -.");
        prm.declare_entry("Cells through wall",
                          "1",
                          Integer(1),
                          "Coarse cells across the wall. Units: -.");
      }
      prm.leave_subsection();
    }


    /// Geometry / Box: a brick of hexahedra.
    void
    declare_box(dealii::ParameterHandler &prm)
    {
      prm.enter_subsection("Box");
      {
        prm.declare_entry("Lower corner",
                          "0, 0, 0",
                          dealii::Patterns::List(Double(), 3, 3),
                          "Corner with the smallest coordinates. Units: mm.");
        prm.declare_entry(
          "Upper corner",
          "10, 1, 1",
          dealii::Patterns::List(Double(), 3, 3),
          "Corner with the largest coordinates. Default: Land et al. 2015 "
          "problem 1 beam. Units: mm.");
        prm.declare_entry(
          "Cells",
          "10, 1, 1",
          dealii::Patterns::List(Integer(1), 3, 3),
          "Coarse cells along x, y, z. Boundary parts are named x_min, x_max, "
          "y_min, y_max, z_min, z_max. Units: -.");
      }
      prm.leave_subsection();
    }


    /// Geometry / Gmsh: a mesh read from a file.
    void
    declare_gmsh(dealii::ParameterHandler &prm)
    {
      prm.enter_subsection("Gmsh");
      {
        prm.declare_entry(
          "Mesh file",
          "../meshes/lv_coarse.msh",
          dealii::Patterns::FileName(),
          "The mesh, chosen by extension: a gmsh file (.msh, format 2.2 or "
          "4.1, ASCII or binary; linear tetrahedra or hexahedra, with the "
          "boundary faces as triangles or quadrilaterals in physical surfaces) "
          "or a VTK XML unstructured grid (.vtu; VTK_TETRA or VTK_HEXAHEDRON "
          "cells, the boundary faces as VTK_TRIANGLE or VTK_QUAD cells tagged "
          "by 'Face tag array'). All cells of one kind. A relative path is "
          "relative to the folder of this parameter file. The mesh is checked: "
          "inverted or flat cells, duplicate or unused nodes stop the run. "
          "Boundary ids are the file's face tags; boundary faces without a "
          "used tag get id 0, or the smallest id no used tag has. Default: the "
          "shipped hexahedral ventricle.");
        prm.declare_entry(
          "Scale",
          "1",
          Double(0.0),
          "Factor from the file's length unit to mm (e.g. 10 for cm). Units: mm "
          "per file unit.");
        prm.declare_entry(
          "Boundary names",
          "",
          dealii::Patterns::Anything(),
          "Which faces of the file are which boundary parts: 'part: file name "
          "or tag' entries separated by ';', e.g. 'base: BASE; endocardium: "
          "ENDO; epicardium: 7'. A file name is a gmsh physical surface name; "
          "a tag is the integer of a gmsh physical surface or a value of the "
          "Face tag array of a .vtu file (a physical name is looked up first). "
          "Only the parts listed are set; an entry that names no boundary face "
          "is an error. Empty: every face tag becomes a part named by its "
          "physical name, or by its number where it has none (.vtu files: "
          "\"5\"). Units: -. Default: empty.");
        prm.declare_entry(
          "Shape",
          "none",
          dealii::Patterns::Selection("none|arostica"),
          "The analytic ventricle the file's mesh discretizes, for the fibre "
          "generators defined in its ellipsoidal coordinates (Fibres / "
          "Generator = analytic or arostica): 'none', no such shape (those "
          "generators are refused); 'arostica', the truncated ellipsoid of "
          "Arostica et al. 2025 in the benchmark's frame (as Geometry / Type = "
          "arostica), e.g. for the benchmark's own tetrahedral mesh "
          "meshes/arostica_benchmark_tet.msh. Units: -. Default: none.");
        prm.declare_entry(
          "Face tag array",
          "",
          dealii::Patterns::Anything(),
          "For .vtu files only: the name of the integer cell-data array that "
          "tags the triangle or quadrilateral cells of the file (its boundary "
          "faces). A file with volume cells only cannot tag faces this way. "
          "Empty: the file's faces are not read and every boundary face has "
          "id 0. Units: -. Default: empty.");
      }
      prm.leave_subsection();
    }

  } // namespace

  void
  Parameters::declare(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Geometry");
    {
      prm.declare_entry(
        "Type",
        "ellipsoid",
        dealii::Patterns::Selection("arostica|ellipsoid|box|gmsh"),
        "Which mesh to use: 'ellipsoid', the idealized truncated-ellipsoid left "
        "ventricle (subsection Ellipsoid); 'box', a brick of hexahedra "
        "(subsection Box); 'gmsh', a mesh read from a file (subsection Gmsh): "
        "a gmsh .msh or a VTK .vtu file, all hexahedra or all tetrahedra; "
        "'arostica', the monoventricular geometry of "
        "Arostica et al. 2025 in the benchmark's frame (long axis x, apex at "
        "-x, mm): endocardium r_s = 25, r_l = 90 cut at x = 26.47, epicardium "
        "r_s = 35, r_l = 97 cut at x = 24.25, the base the ruled surface "
        "between the two cut rings; the ellipsoid generator with these radii "
        "(the radii and Base height of subsection Ellipsoid are not used, its "
        "cell counts are).");
      prm.declare_entry(
        "Global refinements",
        "0",
        Integer(0, 8),
        "How many times every cell of the coarse mesh is split in 8. Curved "
        "generated meshes stay on their exact surfaces. Units: -.");
      prm.declare_entry(
        "Local refinements",
        "0",
        Integer(0, 8),
        "After the global refinements, how many more times the cells near "
        "'Local refinement center' are split in 8 (a cell is refined when a "
        "vertex lies within 'Local refinement radius'; neighbours differ by "
        "at most one level, with hanging nodes between them). For a "
        "singularity such as the apex of a ventricle with helical fibres. "
        "Units: -.");
      prm.declare_entry(
        "Local refinement center",
        "",
        dealii::Patterns::Anything(),
        "Center x, y, z of the locally refined region. Empty: the ellipsoid's "
        "apex at mid-wall, (0, 0, -(endocardium + epicardium long radius) / "
        "2) (for arostica (-93.5, 0, 0)); other meshes must give it when "
        "'Local refinements' > 0. Units: mm.");
      prm.declare_entry("Local refinement radius",
                        "3",
                        Double(0.0),
                        "Radius of the locally refined region. Units: mm.");
      prm.declare_entry(
        "Cell shape",
        "hexahedra",
        dealii::Patterns::Selection("hexahedra|tetrahedra"),
        "Cells of a generated mesh (ellipsoid, box, arostica): 'hexahedra', or "
        "'tetrahedra': after the global refinements every hexahedron is split "
        "into 24 tetrahedra (GridGenerator::convert_hypercube_to_simplex_mesh; "
        "flat facets through the vertices of the curved hexahedral mesh) and "
        "the mesh is fully distributed. A mesh file keeps its own cells. "
        "Units: -.");

      declare_ellipsoid(prm);

      declare_box(prm);

      declare_gmsh(prm);
    }
    prm.leave_subsection();
  }

  Parameters
  Parameters::parse(const dealii::ParameterHandler &prm,
                    const std::string              &prm_directory)
  {
    Parameters        p;
    const std::string type = prm.get({"Geometry"}, "Type");
    p.type                 = (type == "ellipsoid")  ? Type::ellipsoid
                             : (type == "box")      ? Type::box
                             : (type == "arostica") ? Type::arostica
                                                    : Type::gmsh;
    p.global_refinements = prm.get_integer({"Geometry"}, "Global refinements");
    p.local_refinements  = prm.get_integer({"Geometry"}, "Local refinements");
    p.local_refinement_radius =
      prm.get_double({"Geometry"}, "Local refinement radius");
    p.tetrahedra = prm.get({"Geometry"}, "Cell shape") == "tetrahedra";
    const std::string center = prm.get({"Geometry"}, "Local refinement center");
    if (!center.empty())
      p.local_refinement_center =
        parse_point(center, "Geometry / Local refinement center");

    const std::vector<std::string> e = {"Geometry", "Ellipsoid"};
    p.lv_shape.endo_short_radius =
      prm.get_double(e, "Endocardium short radius");
    p.lv_shape.endo_long_radius = prm.get_double(e, "Endocardium long radius");
    p.lv_shape.epi_short_radius = prm.get_double(e, "Epicardium short radius");
    p.lv_shape.epi_long_radius  = prm.get_double(e, "Epicardium long radius");
    p.lv_shape.base_height      = prm.get_double(e, "Base height");
    p.lv_cells.circumferential =
      prm.get_integer(e, "Cells around circumference");
    p.lv_cells.longitudinal = prm.get_integer(e, "Cells from apex to base");
    p.lv_cells.transmural   = prm.get_integer(e, "Cells through wall");
    if (p.type == Type::arostica)
      p.lv_shape = LVShape::arostica();
    const bool generated =
      p.type == Type::ellipsoid || p.type == Type::arostica;
    if (generated)
      p.lv_shape.validate();
    if (center.empty() && generated)
      p.local_refinement_center = p.lv_shape.from_generator_frame(
        dealii::Point<3>(0,
                         0,
                         -0.5 * (p.lv_shape.endo_long_radius +
                                 p.lv_shape.epi_long_radius)));
    AssertThrow(p.local_refinements == 0 || p.local_refinement_center,
                dealii::ExcMessage(
                  "Geometry / Local refinements > 0 needs Geometry / Local "
                  "refinement center (x, y, z in mm) for this mesh type."));

    const std::vector<std::string> b = {"Geometry", "Box"};
    p.box_lower =
      parse_point(prm.get(b, "Lower corner"), "Geometry / Box / Lower corner");
    p.box_upper =
      parse_point(prm.get(b, "Upper corner"), "Geometry / Box / Upper corner");
    const auto cells = dealii::Utilities::string_to_int(
      dealii::Utilities::split_string_list(prm.get(b, "Cells"), ','));
    for (unsigned int d = 0; d < 3; ++d)
      {
        p.box_cells[d] = cells[d];
        if (p.type == Type::box)
          AssertThrow(p.box_upper[d] > p.box_lower[d],
                      dealii::ExcMessage(
                        "Geometry / Box / Upper corner must be larger than "
                        "Lower corner in every coordinate."));
      }

    const std::vector<std::string> g = {"Geometry", "Gmsh"};
    std::filesystem::path          file(prm.get(g, "Mesh file"));
    if (file.is_relative() && !prm_directory.empty())
      file = std::filesystem::path(prm_directory) / file;
    p.mesh_file  = file.lexically_normal().string();
    p.mesh_scale = prm.get_double(g, "Scale");
    p.boundary_names =
      parse_boundary_name_table(prm.get(g, "Boundary names"),
                                "Geometry / Gmsh / Boundary names");
    p.face_tag_array = prm.get(g, "Face tag array");
    if (p.type == Type::gmsh && prm.get(g, "Shape") == "arostica")
      p.lv_shape = LVShape::arostica();
    if (p.type == Type::gmsh)
      AssertThrow(std::filesystem::is_regular_file(p.mesh_file),
                  dealii::ExcMessage(
                    "Geometry / Gmsh / Mesh file: cannot open '" + p.mesh_file +
                    "' (no such file). A relative path is taken from the "
                    "folder of the parameter file."));
    return p;
  }

  BoundaryNames
  create_mesh(const Parameters            &params,
              dealii::Triangulation<3, 3> &tria,
              const std::string           &saved_mesh)
  {
    BoundaryNames names("the generated mesh");
    switch (params.type)
      {
        case Parameters::Type::ellipsoid:
          names = BoundaryNames("the generated ellipsoidal ventricle");
          create_lv_mesh(tria, params.lv_shape, params.lv_cells, names);
          break;
        case Parameters::Type::arostica:
          names =
            BoundaryNames("the generated ventricle of Arostica et al. 2025");
          create_lv_mesh(tria, params.lv_shape, params.lv_cells, names);
          break;
        case Parameters::Type::box:
          {
            names = BoundaryNames("the generated box");
            std::vector<unsigned int> repetitions(params.box_cells.begin(),
                                                  params.box_cells.end());
            dealii::GridGenerator::subdivided_hyper_rectangle(
              tria,
              repetitions,
              params.box_lower,
              params.box_upper,
              /*colorize=*/true);
            const char *face_names[6] =
              {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
            for (unsigned int i = 0; i < 6; ++i)
              names.add(face_names[i], i);
            break;
          }
        case Parameters::Type::gmsh:
          {
            MeshFileOptions options;
            options.scale          = params.mesh_scale;
            options.boundary_names = params.boundary_names;
            options.face_tag_array = params.face_tag_array;
            names = read_mesh_file(params.mesh_file, options, tria);
            break;
          }
      }
    if (!saved_mesh.empty())
      {
        auto *distributed =
          dynamic_cast<dealii::parallel::distributed::Triangulation<3, 3> *>(
            &tria);
        AssertThrow(distributed != nullptr,
                    dealii::ExcMessage("create_mesh: a saved mesh can only be "
                                       "loaded into a distributed mesh."));
        distributed->load(saved_mesh);
        return names;
      }
    tria.refine_global(params.global_refinements);
    for (unsigned int i = 0; i < params.local_refinements; ++i)
      {
        const dealii::Point<3> center = *params.local_refinement_center;
        for (const auto &cell : tria.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned int v : cell->vertex_indices())
              if (cell->vertex(v).distance(center) <
                  params.local_refinement_radius)
                {
                  cell->set_refine_flag();
                  break;
                }
        tria.execute_coarsening_and_refinement();
      }
    return names;
  }

  namespace
  {
    /// The plane of boundary part @p id and the largest distance of one of its
    /// vertices from it (all ranks).
    std::pair<Plane, double>
    fit_boundary_plane(const dealii::Triangulation<3, 3> &tria,
                       const dealii::types::boundary_id   id,
                       const std::string                 &name);
  } // namespace

  Plane
  boundary_plane(const dealii::Triangulation<3, 3> &tria,
                 const dealii::types::boundary_id   id,
                 const std::string                 &name,
                 const double                       relative_tolerance)
  {
    const auto [plane, max_distance] = fit_boundary_plane(tria, id, name);
    const double diameter            = dealii::GridTools::diameter(tria);
    AssertThrow(max_distance <= relative_tolerance * diameter,
                dealii::ExcMessage(
                  "Boundary part '" + name + "' is not planar: a vertex is " +
                  std::to_string(max_distance) +
                  " mm off its best plane. The cavity is closed by a plane "
                  "lid, so the base must be flat."));
    return plane;
  }

  Plane
  cavity_lid(const dealii::Triangulation<3, 3> &tria,
             const BoundaryNames               &names,
             const std::string                 &cavity,
             const std::string                 &base)
  {
    const CavityClosure closure = cavity_closure(tria, names, cavity, base);
    AssertThrow(closure.plane.has_value(),
                dealii::ExcMessage(
                  "The cavity '" + cavity +
                  "' is closed by the plane of its "
                  "basal ring (the base is not flat), but the ring is not "
                  "planar: a vertex is " +
                  std::to_string(closure.off_plane) +
                  " mm off its best plane. Cut the cavity's surface by a "
                  "plane."));
    return *closure.plane;
  }

  CavityClosure
  cavity_closure(const dealii::Triangulation<3, 3> &tria,
                 const BoundaryNames               &names,
                 const std::string                 &cavity,
                 const std::string                 &base)
  {
    const auto base_id            = names.id(base);
    const auto [plane, off_plane] = fit_boundary_plane(tria, base_id, base);
    const double diameter         = dealii::GridTools::diameter(tria);
    const double tolerance        = 1e-6 * diameter;
    if (off_plane <= tolerance)
      return {plane, 0.0, 0.0};

    // A ruled base: the plane of the basal ring of the cavity, the vertices
    // of the owned cells' base faces that are also vertices of a cavity face
    // (of an owned or ghost cell: on tetrahedra the ring's base and cavity
    // faces are often of different cells). Least squares: the centroid and
    // the eigenvector of the smallest eigenvalue of the scatter matrix.
    const auto             cavity_id = names.id(cavity);
    const MPI_Comm         comm      = tria.get_communicator();
    std::array<double, 10> sums{}; // count, sum x (3), sum x x^T (6)
    std::set<unsigned int> cavity_vertices;
    for (const auto &cell : tria.active_cell_iterators())
      if (!cell->is_artificial())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == cavity_id)
            for (const unsigned int i : face->vertex_indices())
              cavity_vertices.insert(face->vertex_index(i));
    std::vector<dealii::Point<3>> ring;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == base_id)
            for (const unsigned int i : face->vertex_indices())
              if (cavity_vertices.count(face->vertex_index(i)) > 0)
                ring.push_back(face->vertex(i));
    for (const auto &x : ring)
      {
        sums[0] += 1;
        for (unsigned int k = 0; k < 3; ++k)
          sums[1 + k] += x[k];
        sums[4] += x[0] * x[0];
        sums[5] += x[1] * x[1];
        sums[6] += x[2] * x[2];
        sums[7] += x[0] * x[1];
        sums[8] += x[0] * x[2];
        sums[9] += x[1] * x[2];
      }
    sum_in_place(sums, comm);
    AssertThrow(sums[0] >= 3,
                dealii::ExcMessage(
                  "Boundary part '" + base + "' is not planar (a vertex is " +
                  std::to_string(off_plane) +
                  " mm off its best plane) and "
                  "meets boundary part '" +
                  cavity +
                  "' in fewer than 3 "
                  "vertices: the cavity has no basal ring to close it by a "
                  "plane lid."));
    Plane lid;
    for (unsigned int k = 0; k < 3; ++k)
      lid.point[k] = sums[1 + k] / sums[0];
    dealii::SymmetricTensor<2, 3> scatter;
    scatter[0][0] = sums[4] / sums[0] - lid.point[0] * lid.point[0];
    scatter[1][1] = sums[5] / sums[0] - lid.point[1] * lid.point[1];
    scatter[2][2] = sums[6] / sums[0] - lid.point[2] * lid.point[2];
    scatter[0][1] = sums[7] / sums[0] - lid.point[0] * lid.point[1];
    scatter[0][2] = sums[8] / sums[0] - lid.point[0] * lid.point[2];
    scatter[1][2] = sums[9] / sums[0] - lid.point[1] * lid.point[2];
    // Sorted by descending eigenvalue: the last is the normal.
    lid.normal = dealii::eigenvectors(scatter)[2].second;
    lid.normal /= lid.normal.norm();

    double                max_distance = 0;
    std::array<double, 6> box{}; // -min (3), max (3)
    box.fill(-std::numeric_limits<double>::max());
    for (const auto &x : ring)
      {
        max_distance =
          std::max(max_distance, std::abs((x - lid.point) * lid.normal));
        for (unsigned int k = 0; k < 3; ++k)
          {
            box[k]     = std::max(box[k], -x[k]);
            box[3 + k] = std::max(box[3 + k], x[k]);
          }
      }
    max_distance = dealii::Utilities::MPI::max(max_distance, comm);
    dealii::Utilities::MPI::max(dealii::ArrayView<const double>(box),
                                comm,
                                dealii::ArrayView<double>(box));
    dealii::Tensor<1, 3> diagonal;
    for (unsigned int k = 0; k < 3; ++k)
      diagonal[k] = box[3 + k] + box[k];
    CavityClosure closure;
    if (max_distance <= tolerance)
      closure.plane = lid;
    closure.off_plane = max_distance;
    closure.rim_size  = diagonal.norm();
    return closure;
  }

  namespace
  {
    std::pair<Plane, double>
    fit_boundary_plane(const dealii::Triangulation<3, 3> &tria,
                       const dealii::types::boundary_id   id,
                       const std::string                 &name)
    {
      const MPI_Comm comm = tria.get_communicator();

      // Area-weighted centroid and normal from the (flat, linear) faces on this
      // rank.
      std::array<double, 8> sums{}; // area, area*x (3), area*n (3), count
      std::vector<dealii::Point<3>> points;
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == id)
              {
                // Two triangle halves of the quad give its vector area; a
                // triangle's is half the cross product of two edges.
                const bool triangle = face->n_vertices() == 3;
                const auto a = face->vertex(0), b = face->vertex(1),
                           c = face->vertex(triangle ? 2 : 3),
                           d = triangle ? a : face->vertex(2);
                const dealii::Tensor<1, 3> vector_area =
                  triangle ? 0.5 * dealii::cross_product_3d(b - a, c - a)
                           : 0.5 * dealii::cross_product_3d(c - a, d - b);
                const double area = vector_area.norm();
                const auto   mid  = face->center();
                sums[0] += area;
                for (unsigned int k = 0; k < 3; ++k)
                  {
                    sums[1 + k] += area * mid[k];
                    sums[4 + k] += vector_area[k];
                  }
                sums[7] += 1;
                for (const unsigned int v : face->vertex_indices())
                  points.push_back(face->vertex(v));
              }
      sum_in_place(sums, comm);
      AssertThrow(sums[7] > 0,
                  dealii::ExcMessage(
                    "The mesh has no faces on boundary part '" + name +
                    "' (boundary id " + std::to_string(id) + ")."));

      Plane plane;
      for (unsigned int k = 0; k < 3; ++k)
        {
          plane.point[k]  = sums[1 + k] / sums[0];
          plane.normal[k] = sums[4 + k];
        }
      AssertThrow(plane.normal.norm() > 1e-12 * sums[0],
                  dealii::ExcMessage(
                    "Boundary part '" + name +
                    "' has no net orientation: it is not a plane."));
      plane.normal /= plane.normal.norm();

      double max_distance = 0;
      for (const auto &p : points)
        max_distance =
          std::max(max_distance, std::abs((p - plane.point) * plane.normal));
      max_distance = dealii::Utilities::MPI::max(max_distance, comm);
      return {plane, max_distance};
    }
  } // namespace

  void
  require_boundary(const dealii::Triangulation<3, 3> &tria,
                   const BoundaryNames               &names,
                   const std::string                 &name)
  {
    const auto   id    = names.id(name);
    unsigned int found = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == id)
            {
              found = 1;
              break;
            }
    found = dealii::Utilities::MPI::max(found, tria.get_communicator());
    AssertThrow(found > 0,
                dealii::ExcMessage(names.source() + " names boundary part '" +
                                   name + "' (id " + std::to_string(id) +
                                   ") but no boundary face carries it (its "
                                   "parts: " +
                                   names.listed() + ")."));
  }

  void
  require_boundaries(const dealii::Triangulation<3, 3> &tria,
                     const BoundaryNames               &names,
                     const std::vector<std::string>    &parts,
                     const std::string                 &needs)
  {
    for (const std::string &part : parts)
      {
        AssertThrow(names.has(part),
                    dealii::ExcMessage(needs + "; " + names.source() +
                                       " has no part '" + part +
                                       "' (it has: " + names.listed() + ")."));
        require_boundary(tria, names, part);
      }
  }
} // namespace systole::Geometry
