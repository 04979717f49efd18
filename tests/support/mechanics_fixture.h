#pragma once

#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "base/logger.h"
#include "fibres/fibre_field.h"
#include "geometry/boundary_names.h"
#include "materials/guccione.h"
#include "materials/volumetric_law.h"
#include "mechanics/parameters.h"
#include "mechanics/problem.h"

#include <mpi.h>

#include <array>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

/// @file
/// Set-ups of the mechanics tests: a fibre field and a displacement that are
/// not aligned with the mesh, and the default (Land 2015) ventricle as the
/// bordered (volume-constrained) tests use it: Guccione law, Simo-Taylor
/// penalty, base fixed, pressure on the endocardium, the direct solver; and
/// the endocardium split into two cavities.

namespace test_support
{
  /// The Guccione law of the mechanics tests: C = 2 kPa, b_f = 8, b_t = 2,
  /// b_fs = 4.
  systole::Materials::Guccione::Parameters
  test_guccione_parameters();

  /// A fibre frame that rotates about z with the height (f at the angle
  /// 0.3 z [rad/mm] from x, n = z), so that the anisotropy is not aligned
  /// with the mesh.
  systole::Fibres::FibreField
  rotating_fibres();

  /// A box [0, upper] of @p cells hexahedra of an isotropic Guccione
  /// material (C = 2 kPa, b_f = b_t = b_fs = 1), fibres along x, the
  /// quadratic volumetric law of bulk modulus @p kappa [kPa], Q2 on a linear
  /// mapping, with the supports and loads of @p params. The log goes to
  /// sink.
  struct GuccioneBox
  {
    GuccioneBox(const dealii::Point<3>               &upper,
                const std::array<unsigned int, 3>    &cells,
                const systole::Mechanics::Parameters &params,
                const double                          kappa);

    std::ostringstream                              sink;
    systole::Logger                                 logger;
    const systole::Materials::Guccione              law;
    const systole::Materials::VolumetricLaw         volumetric;
    dealii::parallel::distributed::Triangulation<3> tria;
    systole::Fibres::FibreField                     fibres;
    std::unique_ptr<systole::Mechanics::Problem>    problem;
  };

  /// A smooth displacement of a few tenths of a mm (3 components).
  class Wobble : public dealii::Function<3>
  {
  public:
    Wobble();

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override;
  };

  /// Everything a Mechanics::Problem on the ventricle needs, on the
  /// communicator @p comm. The log goes to sink.
  struct VentricleMechanics
  {
    explicit VentricleMechanics(const MPI_Comm comm = MPI_COMM_WORLD);

    /// Give the endocardial faces whose centre has x > 0 a new boundary id:
    /// the boundary parts "endocardium_a" (x > 0) and "endocardium_b" (x < 0)
    /// replace "endocardium", and they become the pressure boundary (two
    /// cavities). Throws if a face centre lies on the plane x = 0.
    void
    split_endocardium();

    /// Make the endocardium and the epicardium the pressure boundary: two
    /// cavities whose rims lie in the base plane (the epicardial one is the
    /// volume inside the epicardium, negative by the orientation of its
    /// normal).
    void
    use_two_cavities();

    /// Replace the mesh by the biventricular gmsh mesh @p file (parts
    /// lv_endocardium, rv_endocardium, epicardium, base) and make both
    /// endocardia the pressure boundary: two cavities, each closed by its lid
    /// in the base plane.
    void
    use_biventricular_mesh(const std::string &file);

    /// The problem (Q@p degree on a MappingQ@p degree).
    std::unique_ptr<systole::Mechanics::Problem>
    problem(const unsigned int degree = 2);

    /// Problem::Inputs::fixed_pressures of problem().
    bool fixed_pressures = false;

    std::ostringstream                              sink;
    systole::Logger                                 logger;
    systole::Materials::Guccione                    law;
    systole::Materials::VolumetricLaw               volumetric;
    dealii::parallel::distributed::Triangulation<3> tria;
    systole::Geometry::BoundaryNames                names;
    systole::Mechanics::Parameters                  params;
    systole::Fibres::FibreField                     fibres;
  };

  /// W_i(p) = V0_i + dV_i + c_i p_i: a linear compliance c_i [mm^3/kPa]
  /// around the volumes V0_i + dV_i [mm^3].
  systole::Mechanics::Problem::VolumeTarget
  linear_compliance(const dealii::Vector<double> &V0,
                    const std::vector<double>    &dV,
                    const std::vector<double>    &c);

  /// ProblemChecks::bordered_jacobian_error at @p pressures [kPa] and an active
  /// tension of 10 kPa, at the steps h = 1e-3 and h/2.
  std::array<std::array<double, 2>, 2>
  bordered_jacobian_errors(systole::Mechanics::Problem  &problem,
                           const dealii::Vector<double> &pressures);

  /// bordered_jacobian_errors() of the two-cavity problem
  /// (VentricleMechanics::use_two_cavities()) on @p comm at the displacement
  /// Wobble and the pressures 2 kPa (endocardium), 0.5 kPa (epicardium).
  std::array<std::array<double, 2>, 2>
  two_cavity_jacobian_errors(const MPI_Comm comm);

  /// bordered_jacobian_errors() of both ventricles of the biventricular mesh
  /// @p file (VentricleMechanics::use_biventricular_mesh()) on @p comm, Q@p
  /// degree, at the displacement Wobble and the pressures 2 kPa (LV),
  /// 0.5 kPa (RV).
  std::array<std::array<double, 2>, 2>
  biventricular_jacobian_errors(const std::string &file,
                                const MPI_Comm     comm,
                                const unsigned int degree = 1);
} // namespace test_support
