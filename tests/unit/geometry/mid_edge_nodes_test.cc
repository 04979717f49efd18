#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>

#include "geometry/cell_kind.h"
#include "geometry/mesh_file.h"
#include "geometry/mid_edge_nodes.h"

#include <catch2/catch.hpp>
#include <gmsh.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

using namespace systole;

namespace
{
  /// A file in the working directory (the build tree under ctest), removed at
  /// the end of the test.
  struct ScratchFile
  {
    explicit ScratchFile(const std::string &name)
      : name("mid_edge_nodes_test_" + name)
    {}
    ~ScratchFile()
    {
      std::filesystem::remove(name);
    }
    std::string name;
  };

  /// The unit sphere meshed by gmsh with tetrahedra of size @p h and order
  /// @p order (its mid-edge nodes on the sphere), surface tag 1, msh
  /// @p version.
  void
  write_sphere(const std::string &file,
               const double       h,
               const int          order,
               const double       version)
  {
    const Geometry::GmshSession session;
    gmsh::model::add("mid_edge_nodes_test");
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::option::setNumber("Mesh.RandomSeed", 1);
    const int sphere = gmsh::model::occ::addSphere(0, 0, 0, 1.0);
    gmsh::model::occ::synchronize();
    gmsh::vectorpair boundary;
    gmsh::model::getBoundary({{3, sphere}}, boundary, false, false, false);
    std::vector<int> surfaces;
    for (const auto &[dim, tag] : boundary)
      surfaces.push_back(tag);
    gmsh::model::addPhysicalGroup(2, surfaces, 1);
    gmsh::model::addPhysicalGroup(3, {sphere}, 2);
    gmsh::option::setNumber("Mesh.MeshSizeMin", h);
    gmsh::option::setNumber("Mesh.MeshSizeMax", h);
    gmsh::model::mesh::generate(3);
    gmsh::model::mesh::setOrder(order);
    gmsh::option::setNumber("Mesh.MshFileVersion", version);
    gmsh::write(file);
    gmsh::model::remove();
  }

  double
  volume(const dealii::Triangulation<3> &tria,
         const dealii::Mapping<3>       &mapping)
  {
    const dealii::FE_SimplexP<3> fe(1);
    dealii::FEValues<3>          fe_values(mapping,
                                  fe,
                                  dealii::QGaussSimplex<3>(3),
                                  dealii::update_JxW_values);
    double                       v = 0;
    for (const auto &cell : tria.active_cell_iterators())
      {
        fe_values.reinit(cell);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          v += fe_values.JxW(q);
      }
    return v;
  }
} // namespace

TEST_CASE("A file of 10-node tetrahedra keeps its mid-edge nodes",
          "[geometry][mesh_file]")
{
  for (const double version : {2.2, 4.1})
    {
      ScratchFile file("sphere.msh");
      write_sphere(file.name, 0.6, 2, version);
      dealii::Triangulation<3> tria;
      Geometry::read_mesh_file(file.name, {}, tria);
      const Geometry::MidEdgeManifold *nodes = Geometry::mid_edge_nodes(tria);
      REQUIRE(nodes != nullptr);
      CHECK(nodes->n_nodes() == tria.n_lines());
      const Geometry::CellKind kind(tria);
      CHECK(kind.curved_tetrahedra());
      CHECK(kind.mapping_degree(2) == 2);
      CHECK(kind.mapping_degree(1) == 1);
      // Every boundary edge's node is on the sphere; its corners too.
      for (const auto &cell : tria.active_cell_iterators())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            for (unsigned int l = 0; l < 3; ++l)
              {
                const auto             line = cell->face(f)->line(l);
                const dealii::Point<3> a = line->vertex(0), b = line->vertex(1);
                const std::vector<dealii::Point<3>> points = {a, b};
                const std::vector<double>           half   = {0.5, 0.5};
                const dealii::Point<3> mid = nodes->get_new_point(points, half);
                CHECK(mid.norm() == Approx(1.0).epsilon(1e-6));
                CHECK(a.norm() == Approx(1.0).epsilon(1e-6));
              }
    }
}

TEST_CASE("A file of 4-node tetrahedra stays affine", "[geometry][mesh_file]")
{
  ScratchFile file("sphere1.msh");
  write_sphere(file.name, 0.6, 1, 4.1);
  dealii::Triangulation<3> tria;
  Geometry::read_mesh_file(file.name, {}, tria);
  CHECK(Geometry::mid_edge_nodes(tria) == nullptr);
  const Geometry::CellKind kind(tria);
  CHECK(!kind.curved_tetrahedra());
  CHECK(kind.mapping_degree(2) == 1);
}

TEST_CASE("The quadratic mapping of a sphere of 10-node tetrahedra converges "
          "faster in volume than the affine one",
          "[geometry][convergence]")
{
  const double              exact = 4.0 / 3.0 * M_PI;
  const std::vector<double> sizes = {0.4, 0.2, 0.1};
  std::vector<double>       affine_error, quadratic_error;
  for (const double h : sizes)
    {
      ScratchFile file("sphere_h.msh");
      write_sphere(file.name, h, 2, 4.1);
      dealii::Triangulation<3> tria;
      Geometry::read_mesh_file(file.name, {}, tria);
      const Geometry::CellKind kind(tria);
      affine_error.push_back(
        std::abs(volume(tria, *kind.mapping(tria, 1)) - exact) / exact);
      quadratic_error.push_back(
        std::abs(volume(tria, *kind.mapping(tria, 2)) - exact) / exact);
      std::cout << "sphere h = " << h << ": " << tria.n_active_cells()
                << " cells, relative volume error affine "
                << affine_error.back() << ", quadratic "
                << quadratic_error.back() << std::endl;
    }
  for (unsigned int i = 1; i < sizes.size(); ++i)
    {
      const double ratio = std::log(sizes[i - 1] / sizes[i]);
      const double affine_order =
        std::log(affine_error[i - 1] / affine_error[i]) / ratio;
      const double quadratic_order =
        std::log(quadratic_error[i - 1] / quadratic_error[i]) / ratio;
      std::cout << "observed order h = " << sizes[i] << ": affine "
                << affine_order << ", quadratic " << quadratic_order
                << std::endl;
      CHECK(affine_order == Approx(2.0).margin(0.3));
      CHECK(quadratic_order > 3.5);
      CHECK(quadratic_error[i] < 0.01 * affine_error[i]);
    }
}
