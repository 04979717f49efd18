#include "support/lv_fixture.h"

#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/linear_algebra.h"
#include "geometry/ellipsoid.h"
#include "mechanics/cavity_volume.h"

#include <cmath>

namespace test_support
{
  systole::Geometry::Parameters
  arostica_geometry(const unsigned int refinements)
  {
    systole::Geometry::Parameters p;
    p.type               = systole::Geometry::Parameters::Type::arostica;
    p.lv_shape           = systole::Geometry::LVShape::arostica();
    p.global_refinements = refinements;
    return p;
  }

  double
  land_cavity_volume()
  {
    const double rs = 7.0, rl = 17.0, zb = 5.0;
    const auto   primitive = [&](const double z) {
      return rl * rl * z - z * z * z / 3.0;
    };
    return M_PI * rs * rs / (rl * rl) * (primitive(zb) - primitive(-rl));
  }

  double
  stretched_land_cavity_volume(const unsigned int refinements,
                               const double       lambda,
                               const unsigned int degree,
                               const unsigned int mapping_degree,
                               const MPI_Comm     comm)
  {
    using namespace systole;
    Geometry::Parameters params; // defaults: the Land 2015 ventricle
    params.global_refinements = refinements;
    dealii::parallel::distributed::Triangulation<3> tria(comm);
    const auto names = Geometry::create_mesh(params, tria);
    const auto lid   = Geometry::boundary_plane(tria, names.id("base"), "base");

    const dealii::FESystem<3> fe(dealii::FE_Q<3>(degree), 3);
    dealii::DoFHandler<3>     dof_handler(tria);
    dof_handler.distribute_dofs(fe);
    const dealii::MappingQ<3> mapping(mapping_degree);

    dealii::IndexSet relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    LA::MPI::Vector owned(dof_handler.locally_owned_dofs(), comm);
    LA::MPI::Vector u(dof_handler.locally_owned_dofs(), relevant, comm);

    const dealii::Point<3>                 centre = lid.point;
    dealii::FunctionFromFunctionObjects<3> stretch(
      {[&](const dealii::Point<3> &p) {
         return (lambda - 1.0) * (p[0] - centre[0]);
       },
       [&](const dealii::Point<3> &p) {
         return (lambda - 1.0) * (p[1] - centre[1]);
       },
       [&](const dealii::Point<3> &p) {
         return (lambda - 1.0) * (p[2] - centre[2]);
       }});
    dealii::VectorTools::interpolate(mapping, dof_handler, stretch, owned);
    u = owned;

    const Mechanics::CavityVolume cavity(names.id("endocardium"), lid);
    return cavity.volume(mapping, dof_handler, u, degree + mapping_degree + 1);
  }
} // namespace test_support
