#pragma once

#include <deal.II/base/point.h>

#include <string>
#include <utility>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace systole::Mechanics
{
  /// A named reference point whose deformed position is reported
  /// ("beam_tip: 10, 0.5, 1" gives the columns beam_tip_x, _y, _z).
  struct TrackedPoint
  {
    std::string      name;
    dealii::Point<3> position; ///< reference position [mm]
  };

  /// Settings of the quasi-static mechanics (subsection "Mechanics").
  struct Parameters
  {
    /// Boundary parts with all displacement components fixed to zero.
    std::vector<std::string> fixed_boundaries;
    /// Flat boundary parts on which only the normal displacement is zero.
    std::vector<std::string> sliding_boundaries;

    /// Boundary part that carries the follower pressure ("" for none).
    std::string pressure_boundary;
    /// Pressure at the end of the load ramp [kPa].
    double pressure = 0.0;

    /// Boundary parts held by Robin springs.
    std::vector<std::string> robin_boundaries;
    /// Spring stiffness per reference area [kPa/mm].
    double robin_stiffness = 0.0;
    /// Whether the springs act on the normal component only.
    bool robin_normal_only = true;

    /// Prescribed active tension at the end of the load ramp [kPa] (2nd
    /// Piola-Kirchhoff, along the reference fibre).
    double active_tension = 0.0;
    /// Fraction of the active tension acting across the fibres [-].
    double active_transverse_fraction = 0.0;

    /// Integrate the volumetric penalty with one Gauss point less per
    /// direction than the rest (Q2 only).
    bool reduced_volumetric_integration = false;

    /// The first load increment is 1 / load_steps; later ones adapt.
    unsigned int load_steps = 5;
    /// How often a load step may be halved when Newton fails.
    unsigned int max_step_cuts = 8;

    /// Newton converges when |R| <= this * (largest |R| of the load step),
    /// or |R| <= the absolute tolerance, or |du| <= 1e-12 |u|.
    double       newton_relative_tolerance = 1e-9;
    double       newton_absolute_tolerance = 1e-12;
    unsigned int max_newton_iterations     = 12;

    /// "auto", "direct" (MUMPS) or "iterative" (GMRES + GAMG with rigid-body
    /// modes).
    std::string linear_solver = "auto";
    /// Above this many DOFs "auto" picks the iterative solver.
    unsigned int direct_solver_limit = 200000;
    /// Relative tolerance of the iterative linear solver.
    double linear_tolerance = 1e-8;

    std::vector<TrackedPoint> tracked_points;

    static void
    declare(dealii::ParameterHandler &prm);

    static Parameters
    parse(const dealii::ParameterHandler &prm);
  };
} // namespace systole::Mechanics
