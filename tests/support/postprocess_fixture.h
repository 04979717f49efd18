#pragma once

#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>

#include "base/logger.h"
#include "fibres/fibre_basis.h"
#include "geometry/boundary_names.h"
#include "io/results_file.h"
#include "materials/guccione.h"
#include "materials/volumetric_law.h"
#include "mechanics/parameters.h"
#include "mechanics/problem.h"

#include "postprocess/manager.h"

#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

/// @file
/// The postprocessors on the ventricle of the default run, with prescribed
/// displacements.

namespace test_support
{
  /// A displacement u(X) as a deal.II function.
  using DisplacementMap =
    std::function<dealii::Tensor<1, 3>(const dealii::Point<3> &)>;

  /// The ventricle of the default run (parameters/lv_heartbeat.prm: 16 x 5
  /// cells, Q2 on MappingQ2), or the gmsh mesh @p mesh_file (e.g. both
  /// ventricles of meshes/biv_hex_coarse.msh, Q2 on its flat cells), with
  /// one uniform fibre frame, no Dirichlet boundary (the prescribed
  /// displacements stay exact), and the postprocessors @p names.
  struct PostprocessVentricle
  {
    explicit PostprocessVentricle(
      const std::vector<std::string>    &names,
      const systole::Fibres::FibreBasis &basis     = random_basis(),
      const std::string                 &mesh_file = "");

    /// Set the displacement to @p u and run one step of beat @p beat at
    /// @p time [ms] with cavity volume @p volume [mm^3]; returns the
    /// /timeseries row.
    std::vector<systole::IO::Column>
    step(const DisplacementMap &u,
         const double           volume = 0.0,
         const double           time   = 0.0,
         const unsigned int     beat   = 0);

    /// The fibre frame of the default: random_fibre_basis(3).
    static systole::Fibres::FibreBasis
    random_basis();

    std::ostringstream                              sink;
    systole::Logger                                 logger;
    systole::Materials::Guccione                    law;
    systole::Materials::VolumetricLaw               volumetric;
    dealii::parallel::distributed::Triangulation<3> tria;
    systole::Geometry::BoundaryNames                boundary_names;
    systole::Mechanics::Parameters                  params;
    std::unique_ptr<systole::Mechanics::Problem>    problem;
    std::unique_ptr<systole::Postprocess::Manager>  manager;
  };

  /// The value of column @p name of @p row (throws if there is none).
  double
  column_value(const std::vector<systole::IO::Column> &row,
               const std::string                      &name);
} // namespace test_support
