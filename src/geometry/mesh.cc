#include "geometry/mesh.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <filesystem>

namespace systole::Geometry
{
  namespace
  {
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
  } // namespace

  void
  Parameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Double;
    using dealii::Patterns::Integer;
    prm.enter_subsection("Geometry");
    {
      prm.declare_entry(
        "Type",
        "ellipsoid",
        dealii::Patterns::Selection("ellipsoid|box|gmsh"),
        "Which mesh to use: 'ellipsoid', the idealized truncated-ellipsoid left "
        "ventricle (subsection Ellipsoid); 'box', a brick of hexahedra "
        "(subsection Box); 'gmsh', a hexahedral mesh read from a .msh file "
        "(subsection Gmsh).");
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
        "2); other meshes must give it when 'Local refinements' > 0. Units: "
        "mm.");
      prm.declare_entry("Local refinement radius",
                        "3",
                        Double(0.0),
                        "Radius of the locally refined region. Units: mm.");

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

      prm.enter_subsection("Gmsh");
      {
        prm.declare_entry(
          "Mesh file",
          "../meshes/lv_coarse.msh",
          dealii::Patterns::FileName(),
          "Hexahedral gmsh mesh (.msh, format 2 or 4, ASCII). A relative path "
          "is relative to the folder of this parameter file. Physical surface "
          "names become boundary part names (endocardium, epicardium, base, ...).");
        prm.declare_entry(
          "Scale",
          "1",
          Double(0.0),
          "Factor from the file's length unit to mm (e.g. 10 for cm). Units: mm "
          "per file unit.");
      }
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }

  Parameters
  Parameters::parse(const dealii::ParameterHandler &prm,
                    const std::string              &prm_directory)
  {
    Parameters        p;
    const std::string type = prm.get({"Geometry"}, "Type");
    p.type                 = (type == "ellipsoid") ? Type::ellipsoid
                             : (type == "box")     ? Type::box
                                                   : Type::gmsh;
    p.global_refinements = prm.get_integer({"Geometry"}, "Global refinements");
    p.local_refinements  = prm.get_integer({"Geometry"}, "Local refinements");
    p.local_refinement_radius =
      prm.get_double({"Geometry"}, "Local refinement radius");
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
    if (p.type == Type::ellipsoid)
      p.lv_shape.validate();
    if (center.empty() && p.type == Type::ellipsoid)
      p.local_refinement_center =
        dealii::Point<3>(0,
                         0,
                         -0.5 * (p.lv_shape.endo_long_radius +
                                 p.lv_shape.epi_long_radius));
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
          names = read_gmsh(params.mesh_file, params.mesh_scale, tria);
          break;
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

  Plane
  boundary_plane(const dealii::Triangulation<3, 3> &tria,
                 const dealii::types::boundary_id   id,
                 const std::string                 &name,
                 const double                       relative_tolerance)
  {
    const MPI_Comm comm = tria.get_communicator();

    // Area-weighted centroid and normal from the (flat, linear) faces on this
    // rank.
    std::array<double, 8>         sums{}; // area, area*x (3), area*n (3), count
    std::vector<dealii::Point<3>> points;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == id)
            {
              // Two triangle halves of the quad give its vector area.
              const auto a = face->vertex(0), b = face->vertex(1),
                         c = face->vertex(3), d = face->vertex(2);
              const dealii::Tensor<1, 3> vector_area =
                0.5 * dealii::cross_product_3d(c - a, d - b);
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
    MPI_Allreduce(MPI_IN_PLACE,
                  sums.data(),
                  sums.size(),
                  MPI_DOUBLE,
                  MPI_SUM,
                  comm);
    AssertThrow(sums[7] > 0,
                dealii::ExcMessage("The mesh has no faces on boundary part '" +
                                   name + "' (boundary id " +
                                   std::to_string(id) + ")."));

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
    max_distance          = dealii::Utilities::MPI::max(max_distance, comm);
    const double diameter = dealii::GridTools::diameter(tria);
    AssertThrow(max_distance <= relative_tolerance * diameter,
                dealii::ExcMessage(
                  "Boundary part '" + name + "' is not planar: a vertex is " +
                  std::to_string(max_distance) +
                  " mm off its best plane. The cavity is closed by a plane "
                  "lid, so the base must be flat."));
    return plane;
  }

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
                                   ") but no boundary face carries it."));
  }
} // namespace systole::Geometry
