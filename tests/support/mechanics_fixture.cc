#include "support/mechanics_fixture.h"

#include "geometry/mesh.h"
#include "geometry/mesh_file.h"
#include "mechanics/problem_checks.h"

#include <cmath>

namespace test_support
{
  systole::Fibres::FibreField
  rotating_fibres()
  {
    return [](const auto &, const auto &points, auto &bases) {
      bases.resize(points.size());
      for (unsigned int i = 0; i < points.size(); ++i)
        {
          const double a = 0.3 * points[i][2];
          bases[i].f     = dealii::Tensor<1, 3>({std::cos(a), std::sin(a), 0});
          bases[i].s     = dealii::Tensor<1, 3>({-std::sin(a), std::cos(a), 0});
          bases[i].n     = dealii::Tensor<1, 3>({0, 0, 1});
        }
    };
  }

  Wobble::Wobble()
    : dealii::Function<3>(3)
  {}

  double
  Wobble::value(const dealii::Point<3> &p, const unsigned int c) const
  {
    return 0.6 * std::sin(0.3 * p[0] + 0.2 * c) *
           std::cos(0.25 * p[1] - 0.1 * p[2] + c);
  }

  systole::Materials::Guccione::Parameters
  test_guccione_parameters()
  {
    systole::Materials::Guccione::Parameters g;
    g.C    = 2;
    g.b_f  = 8;
    g.b_t  = 2;
    g.b_fs = 4;
    return g;
  }

  GuccioneBox::GuccioneBox(const dealii::Point<3>               &upper,
                           const std::array<unsigned int, 3>    &cells,
                           const systole::Mechanics::Parameters &params,
                           const double                          kappa)
    : logger(MPI_COMM_WORLD, sink)
    , law([] {
      auto p = test_guccione_parameters(); // C = 2 kPa
      p.b_f = p.b_t = p.b_fs = 1;
      return p;
    }())
    , volumetric(systole::Materials::VolumetricLaw::Form::quadratic, kappa)
    , tria(MPI_COMM_WORLD)
  {
    using namespace systole;
    Geometry::Parameters geometry;
    geometry.type      = Geometry::Parameters::Type::box;
    geometry.box_upper = upper;
    geometry.box_cells = cells;
    const auto names   = Geometry::create_mesh(geometry, tria);
    fibres             = [](const auto &, const auto &points, auto &bases) {
      bases.resize(points.size());
      for (auto &b : bases)
        {
          b.f = dealii::Tensor<1, 3>({1, 0, 0});
          b.s = dealii::Tensor<1, 3>({0, 1, 0});
          b.n = dealii::Tensor<1, 3>({0, 0, 1});
        }
    };
    problem = std::make_unique<Mechanics::Problem>(
      Mechanics::Problem::Inputs{params,
                                 tria,
                                 names,
                                 2,
                                 1,
                                 law,
                                 volumetric,
                                 fibres,
                                 logger});
  }

  VentricleMechanics::VentricleMechanics(const MPI_Comm comm)
    : logger(comm, sink)
    , law(test_guccione_parameters())
    , volumetric(systole::Materials::VolumetricLaw::Form::simo_taylor, 100.0)
    , tria(comm)
  {
    using namespace systole;
    names = Geometry::create_mesh(Geometry::Parameters(), tria);
    params.fixed_boundaries          = {"base"};
    params.pressure_boundary         = "endocardium";
    params.linear_solver             = "direct";
    params.newton_absolute_tolerance = 1e-10;
    fibres                           = rotating_fibres();
  }

  void
  VentricleMechanics::split_endocardium()
  {
    using namespace systole;
    const auto                 endocardium = names.id("endocardium");
    dealii::types::boundary_id new_id      = 0;
    Geometry::BoundaryNames    split(names.source() + " (endocardium split)");
    for (const auto &name : names.names())
      {
        new_id =
          std::max<dealii::types::boundary_id>(new_id, names.id(name) + 1);
        if (name != "endocardium")
          split.add(name, names.id(name));
      }
    split.add("endocardium_a", new_id);
    split.add("endocardium_b", endocardium);
    // Every rank's cells, owned or not, so that all copies agree.
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() == endocardium)
          {
            const double x = face->center()[0];
            AssertThrow(std::abs(x) > 1e-6,
                        dealii::ExcMessage("split_endocardium: a face centre "
                                           "lies on the plane x = 0."));
            if (x > 0)
              face->set_boundary_id(new_id);
          }
    names                    = split;
    params.pressure_boundary = "endocardium_a, endocardium_b";
  }

  void
  VentricleMechanics::use_two_cavities()
  {
    params.pressure_boundary = "endocardium, epicardium";
  }

  void
  VentricleMechanics::use_biventricular_mesh(const std::string &file)
  {
    tria.clear();
    names                    = systole::Geometry::read_gmsh(file, 1.0, tria);
    params.pressure_boundary = "lv_endocardium, rv_endocardium";
  }

  std::unique_ptr<systole::Mechanics::Problem>
  VentricleMechanics::problem(const unsigned int degree)
  {
    return std::make_unique<systole::Mechanics::Problem>(
      systole::Mechanics::Problem::Inputs{params,
                                          tria,
                                          names,
                                          degree,
                                          degree,
                                          law,
                                          volumetric,
                                          fibres,
                                          logger,
                                          fixed_pressures});
  }

  systole::Mechanics::Problem::VolumeTarget
  linear_compliance(const dealii::Vector<double> &V0,
                    const std::vector<double>    &dV,
                    const std::vector<double>    &c)
  {
    return [=](const dealii::Vector<double> &p,
               dealii::Vector<double>       &W,
               dealii::FullMatrix<double>   &dW_dp) {
      for (unsigned int i = 0; i < p.size(); ++i)
        {
          W[i]        = V0[i] + dV[i] + c[i] * p[i];
          dW_dp(i, i) = c[i];
        }
    };
  }

  std::array<std::array<double, 2>, 2>
  bordered_jacobian_errors(systole::Mechanics::Problem  &problem,
                           const dealii::Vector<double> &pressures)
  {
    return {
      {systole::Mechanics::ProblemChecks::bordered_jacobian_error(problem,
                                                                  pressures,
                                                                  10.0,
                                                                  1e-3),
       systole::Mechanics::ProblemChecks::bordered_jacobian_error(problem,
                                                                  pressures,
                                                                  10.0,
                                                                  5e-4)}};
  }

  std::array<std::array<double, 2>, 2>
  two_cavity_jacobian_errors(const MPI_Comm comm)
  {
    VentricleMechanics s(comm);
    s.use_two_cavities();
    const auto problem = s.problem();
    problem->set_displacement(Wobble());
    dealii::Vector<double> pressures(2);
    pressures[0] = 2.0;
    pressures[1] = 0.5;
    return bordered_jacobian_errors(*problem, pressures);
  }

  std::array<std::array<double, 2>, 2>
  biventricular_jacobian_errors(const std::string &file,
                                const MPI_Comm     comm,
                                const unsigned int degree)
  {
    VentricleMechanics s(comm);
    s.use_biventricular_mesh(file);
    const auto problem = s.problem(degree);
    problem->set_displacement(Wobble());
    dealii::Vector<double> pressures(2);
    pressures[0] = 2.0;
    pressures[1] = 0.5;
    return bordered_jacobian_errors(*problem, pressures);
  }
} // namespace test_support
