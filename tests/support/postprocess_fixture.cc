#include "support/postprocess_fixture.h"

#include "geometry/mesh.h"
#include "geometry/mesh_file.h"
#include "support/mechanics_fixture.h"
#include "support/random_tensors.h"

#include <stdexcept>

namespace test_support
{
  namespace
  {
    struct Displacement : public dealii::Function<3>
    {
      explicit Displacement(DisplacementMap u)
        : dealii::Function<3>(3)
        , u(std::move(u))
      {}
      double
      value(const dealii::Point<3> &p, const unsigned int c) const override
      {
        return u(p)[c];
      }
      DisplacementMap u;
    };
  } // namespace

  systole::Fibres::FibreBasis
  PostprocessVentricle::random_basis()
  {
    return random_fibre_basis(3);
  }

  PostprocessVentricle::PostprocessVentricle(
    const std::vector<std::string>    &names,
    const systole::Fibres::FibreBasis &basis,
    const std::string                 &mesh_file)
    : logger(MPI_COMM_WORLD, sink)
    , law(test_guccione_parameters())
    , volumetric(systole::Materials::VolumetricLaw::Form::simo_taylor, 100.0)
    , tria(MPI_COMM_WORLD)
  {
    systole::Geometry::Parameters geometry;
    geometry.lv_shape.endo_short_radius = 23;
    geometry.lv_shape.endo_long_radius  = 84;
    geometry.lv_shape.epi_short_radius  = 33;
    geometry.lv_shape.epi_long_radius   = 92;
    geometry.lv_cells.circumferential   = 16;
    geometry.lv_cells.longitudinal      = 5;
    if (mesh_file.empty())
      {
        boundary_names = systole::Geometry::create_mesh(geometry, tria);
        params.pressure_boundary = "endocardium";
      }
    else
      {
        boundary_names = systole::Geometry::read_gmsh(mesh_file, 1.0, tria);
        params.pressure_boundary = "lv_endocardium, rv_endocardium";
      }
    params.fixed_boundaries = {};
    params.linear_solver    = "direct";
    problem                 = std::make_unique<systole::Mechanics::Problem>(
      systole::Mechanics::Problem::Inputs{
        params,
        tria,
        boundary_names,
        2,
        2,
        law,
        volumetric,
        [basis](const auto &, const auto &points, auto &bases) {
          bases.assign(points.size(), basis);
        },
        logger});
    systole::Postprocess::Parameters p;
    p.postprocessors      = names;
    p.reference_direction = dealii::Tensor<1, 3>({0, 1, 0});
    manager               = std::make_unique<systole::Postprocess::Manager>(p,
                                                              *problem,
                                                              boundary_names);
  }

  std::vector<systole::IO::Column>
  PostprocessVentricle::step(const DisplacementMap &u,
                             const double           volume,
                             const double           time,
                             const unsigned int     beat)
  {
    problem->set_displacement(Displacement(u));
    std::vector<systole::IO::Column> row;
    manager->step(time, beat, 0.0, volume, std::nullopt, row);
    return row;
  }

  double
  column_value(const std::vector<systole::IO::Column> &row,
               const std::string                      &name)
  {
    for (const auto &c : row)
      if (c.name == name)
        return c.value;
    throw std::runtime_error("no column " + name);
  }
} // namespace test_support
