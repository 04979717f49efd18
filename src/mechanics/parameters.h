#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include "materials/active_stress.h"

#include <string>
#include <utility>
#include <vector>

namespace systole::Mechanics
{
  /// A named reference point whose deformed position is reported
  /// ("beam_tip: 10, 0.5, 1" gives the columns beam_tip_x, _y, _z).
  struct TrackedPoint
  {
    std::string      name;
    dealii::Point<3> position; ///< reference position [mm]
  };

  /// A spring-dashpot (Robin) support on one boundary part: the traction
  /// -(alpha u + beta v) per reference area, on the normal component only
  /// ((u.N) N), on the tangential ones (u - (u.N) N) or on all components.
  struct RobinSupport
  {
    std::string boundary;
    double      stiffness   = 0.0;  ///< alpha [kPa/mm]
    double      damping     = 0.0;  ///< beta [kPa ms/mm]
    bool        normal_only = true; ///< normal component only
    /// The tangential components only (a base that may descend along its
    /// normal but not slide or turn); normal_only is false then.
    bool tangential_only = false;
    /// For a full support: the normal stiffness and damping as a fraction of
    /// the tangential ones ('full r'; 1: the same in every direction).
    double normal_fraction = 1.0;
    /// The projection onto the supported components at unit normal @p N:
    /// N x N, I - N x N, or I - (1 - r) N x N.
    dealii::Tensor<2, 3>
    projection(const dealii::Tensor<1, 3> &N) const;

    /// Apex-to-base taper (a pericardium that holds the apex and lets the
    /// base move, after Strocchi et al. 2020, J Biomech 101:109645): alpha
    /// and beta are scaled by s(h) = 1 for h <= taper_start, falling
    /// linearly to base_scale at h = 1, with h in [0, 1] the height above
    /// the apex as a fraction of the apex's distance from the base plane.
    double taper_start = 1.0;
    double base_scale  = 1.0; ///< s at the base (1: no taper)
    /// The springs pull toward the displacement at the last end-diastole
    /// (Problem::refer_supports_to_end_diastole()), not the unloaded state.
    bool from_end_diastole = false;
    /// The time over which their rest position moves from the last one to
    /// the new end-diastolic displacement (a smooth step; 0: at once) [ms].
    double release_time = 0.0;
    bool
    tapered() const
    {
      return base_scale != 1.0;
    }
    /// Where h is measured from (set by the Problem from the mesh for a
    /// tapered support): a point of the base plane, the unit normal from the
    /// apex toward the base, the apex's distance from the plane [mm].
    dealii::Point<3>     base_point   = {};
    dealii::Tensor<1, 3> apex_to_base = {};
    double               height       = 1.0;
    /// s(h(X)) at reference position @p X (1 if not tapered).
    double
    scale(const dealii::Point<3> &X) const;
  };

  /// How the near-incompressibility of the myocardium is imposed
  /// ("Material / Incompressibility").
  enum class Incompressibility
  {
    /// Displacement only, with the volumetric penalty U(J) of
    /// Materials::VolumetricLaw added to the stress.
    penalty,
    /// Mixed u-p: a pressure field p with the energy
    /// @f$-p(J-1) - p^2/(2\kappa)@f$ (eliminated, the quadratic penalty
    /// @f$\frac\kappa2(J-1)^2@f$).
    nearly_incompressible,
    /// Mixed u-p with @f$1/\kappa = 0@f$: J = 1 in the weak sense of the
    /// pressure space.
    incompressible
  };

  /// The pressure space of the mixed formulations ("Discretization /
  /// Pressure element").
  enum class PressureElement
  {
    /// Q_k - P_{k-1} discontinuous (Q2-P1disc, Q1-P0): element-wise
    /// incompressibility, a block-diagonal pressure mass matrix.
    discontinuous,
    /// Taylor-Hood Q_k - Q_{k-1} (k >= 2), continuous pressure.
    continuous
  };

  /// The preconditioner of the displacement (block) in the iterative linear
  /// solvers ("Mechanics / Displacement preconditioner").
  enum class DisplacementPreconditioner
  {
    /// One PETSc GAMG V-cycle on the Q_k displacement.
    amg,
    /// Two-level p-multigrid: smoothing on Q_k, one GAMG V-cycle on the
    /// Galerkin Q1 operator (Q2 only; Q1 falls back to amg).
    p_multigrid
  };

  /// Newton's method of the mechanics (Parameters: entries "Newton ...",
  /// "Maximum Newton iterations", "Reuse factorization", "Chord acceleration
  /// depth").
  struct NewtonSettings
  {
    /// Newton converges when |R| <= this * (largest |R| of the load step),
    /// or |R| <= the absolute tolerance, or |du| <= 1e-12 |u|.
    double newton_relative_tolerance = 1e-9;
    double newton_absolute_tolerance = 1e-12;
    /// A volume-constrained solve also needs every cavity volume within
    /// this fraction of its target (the entry "Cavity volume tolerance").
    double       cavity_volume_tolerance = 2e-9;
    unsigned int max_newton_iterations   = 12;
    /// Chord iterations on the last factorized tangent where they are
    /// cheaper than a new one (the entry "Reuse factorization").
    bool reuse_factorization = true;
    /// Differences kept by the Anderson acceleration of the chord iterations
    /// of the direct solver (0: plain chord iterations; the entry "Chord
    /// acceleration depth").
    unsigned int chord_acceleration_depth = 0;
    /// "Chord acceleration depth = auto": depth 5 with the direct solver on
    /// at least auto_acceleration_dofs DOFs, 0 (plain chords) below; resolved
    /// into chord_acceleration_depth when the problem is set up.
    bool chord_acceleration_auto = true;
    /// Where auto starts accelerating. Land problem 2, 10 equal steps, 2
    /// ranks, plain against accelerated: 129k DOFs 89-98 s and 66-78 s (the
    /// factorizations dominate); 17.9k 5.8-6.2 s and 5.1-6.2 s, 2.7k 0.9 s
    /// and 0.7-1.1 s (within the noise; below, the plain path keeps 1 and 2
    /// ranks equal to round-off).
    static constexpr unsigned int auto_acceleration_dofs = 50000;
    /// The depth auto takes there (8 factorizations instead of 13 at 129k).
    static constexpr unsigned int auto_acceleration_depth = 5;
  };

  /// The linear solver of the mechanics and its preconditioners.
  struct LinearSolverSettings
  {
    /// "auto", "direct" (MUMPS), "matrix-free" (MatrixFreeSolver) or
    /// "iterative" (FGMRES + p-multigrid, or
    /// GMRES + GAMG with rigid-body modes; for the mixed formulations FGMRES
    /// with a block preconditioner: that V-cycle on the displacement block, the
    /// scaled pressure mass matrix for the Schur complement).
    std::string linear_solver = "auto";
    /// Above this many DOFs "auto" picks the iterative solver.
    unsigned int direct_solver_limit = 200000;
    /// Relative tolerance of the iterative linear solver (with
    /// inexact_newton: the tightest of its solves).
    double linear_tolerance = 1e-8;
    /// The iterative and matrix-free solvers solve each Newton update only
    /// as accurately as Newton's convergence needs (ForcingTerm).
    bool inexact_newton = true;
    /// Preconditioner of the displacement (block) of the iterative solver.
    DisplacementPreconditioner displacement_preconditioner =
      DisplacementPreconditioner::p_multigrid;
    /// Augmented-Lagrangian factor gamma [-] of the iterative solver of the
    /// mixed formulations with a discontinuous pressure: it solves T K x =
    /// T b, T = [I, gamma B^T W^-1; 0, I] (W the pressure mass matrix
    /// weighted by 1/kappa + 1/mu), whose displacement block A + gamma B^T
    /// W^-1 B holds the volume as a bulk modulus of about gamma mu would
    /// (0: the plain saddle-point system).
    double augmented_lagrangian = 1.0;
  };

  /// The inertia and damping of time integrations (Problem::set_time_step()).
  struct InertiaSettings
  {
    /// Elastodynamics (Problem::set_time_step()): the inertia M a of the
    /// density, integrated by the generalized-alpha method.
    /// Density rho [mg/mm^3] (1 mg/mm^3 = 1000 kg/m^3; the entry is in
    /// kg/m^3).
    double density = 1.0;
    /// Spectral radius rho_inf in [0, 1] of the generalized-alpha method at
    /// infinite frequency (1: no numerical dissipation).
    double spectral_radius = 0.8;
    /// Rayleigh damping proportional to the mass, C = c_M M [1/ms] (the
    /// entry is in 1/s).
    double rayleigh_mass_damping = 0.0;
    /// Kelvin-Voigt viscosity eta [kPa ms]: S_visc = eta dE/dt in time
    /// integrations (the entry is in kPa s).
    double viscosity = 0.0;
  };

  /// Settings of the quasi-static mechanics (subsection "Mechanics", plus
  /// "Material / Incompressibility" and "Discretization / Pressure element").
  /// The settings of Newton's method, the linear solver and the inertia are
  /// grouped in the bases (one job each), read as params.density etc.
  struct Parameters : NewtonSettings, LinearSolverSettings, InertiaSettings
  {
    Incompressibility incompressibility = Incompressibility::penalty;
    PressureElement   pressure_element  = PressureElement::discontinuous;

    /// Whether the formulation has a pressure field.
    bool
    mixed() const
    {
      return incompressibility != Incompressibility::penalty;
    }

    /// Boundary parts with all displacement components fixed to zero.
    std::vector<std::string> fixed_boundaries;
    /// Flat boundary parts on which only the normal displacement is zero.
    std::vector<std::string> sliding_boundaries;

    /// Boundary parts that carry a follower pressure each, as written in
    /// "Mechanics / Pressure boundary": comma-separated names ("" for none).
    /// With a boundary part "base" in the mesh every one is a cavity.
    std::string pressure_boundary;

    /// The parts of pressure_boundary, in order (empty for none).
    std::vector<std::string>
    pressure_boundaries() const;

    /// Pressure at the end of the load ramp [kPa].
    double pressure = 0.0;

    /// Boundary parts held by Robin springs.
    std::vector<std::string> robin_boundaries;
    /// Spring stiffness per reference area [kPa/mm].
    double robin_stiffness = 0.0;
    /// Whether the springs act on the normal component only.
    bool robin_normal_only = true;
    /// Dashpot coefficient per reference area of robin_boundaries [kPa
    /// ms/mm] (acts on the velocity of time integrations only).
    double robin_damping = 0.0;
    /// Further supports, each with its own values ("Robin supports").
    std::vector<RobinSupport> robin_supports;

    /// Every support: robin_boundaries with the uniform values, then
    /// robin_supports.
    std::vector<RobinSupport>
    all_robin_supports() const;

    /// The supports of the entry "Robin supports" (its syntax; throws
    /// ExcMessage naming a malformed item).
    static std::vector<RobinSupport>
    parse_robin_supports(const std::string &text);

    /// Prescribed active tension at the end of the load ramp [kPa] (2nd
    /// Piola-Kirchhoff, along the reference fibre).
    double active_tension = 0.0;
    /// Fractions of the active tension along the sheet and the normal [-].
    Materials::CrossFibreFractions active_cross_fibre;

    /// With a base not held in its plane: the cavity pressures act on the
    /// lids too (the load is p dV/du of the closed cavity).
    bool lid_pressure = false;

    /// Integrate the volumetric penalty with one Gauss point less per
    /// direction than the rest (Q2 only).
    bool reduced_volumetric_integration = false;

    /// The first load increment is 1 / load_steps; later ones adapt.
    unsigned int load_steps = 5;
    /// Whether the load increments adapt to the Newton iterations (otherwise
    /// all are 1 / load_steps, cut only when Newton fails).
    bool adaptive_load_steps = true;
    /// How often a load step may be halved when Newton fails.
    unsigned int max_step_cuts = 8;

    std::vector<TrackedPoint> tracked_points;

    static void
    declare(dealii::ParameterHandler &prm);

    /// Reads subsection Mechanics and the two entries above; throws naming
    /// the entry when a value or a combination is invalid.
    static Parameters
    parse(const dealii::ParameterHandler &prm);

    /// Declares "Incompressibility" in the current subsection (Material).
    static void
    declare_incompressibility(dealii::ParameterHandler &prm);

    /// Declares "Pressure element" in the current subsection
    /// (Discretization).
    static void
    declare_pressure_element(dealii::ParameterHandler &prm);
  };
} // namespace systole::Mechanics
