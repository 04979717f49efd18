#pragma once

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include "base/archive_fwd.h"
#include "fibres/fibre_field.h"
#include "geometry/boundary_names.h"
#include "geometry/cell_kind.h"
#include "mechanics/parameters.h"

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
}

namespace dealii::PETScWrappers::MPI
{
  class SparseMatrix;
}

namespace systole::Materials
{
  class PassiveLaw;
  class VolumetricLaw;
  class TensionModel;
} // namespace systole::Materials

namespace systole::Mechanics
{
  /// What one Newton solve did.
  struct NewtonReport
  {
    unsigned int iterations = 0; ///< with a new tangent each
    /// Iterations with the factorized tangent of an earlier solve (chord
    /// iterations of solve_cavities(); not counted in iterations).
    unsigned int reused_iterations = 0;
    double       initial_residual  = 0; ///< |R| before the first update
    double       final_residual    = 0; ///< |R| at convergence
    unsigned int linear_iterations = 0; ///< summed over the Newton iterations
    /// Updates the safeguard shortened (step length < 1: the full update
    /// inverted an element or, the first Newton update, raised |R_u| more
    /// than tenfold).
    unsigned int damped_updates = 0;
    /// Whether the chord iterations were Anderson-accelerated.
    bool accelerated = false;

    /// Whether the step was easy for Newton, so that an adaptive load or
    /// time step may grow: at most 4 iterations with a new tangent and,
    /// with accelerated chords, no shortened update. (The accelerated chords
    /// replace Newton iterations also where the predictor was poor, so their
    /// Newton count alone reads a hard step as easy; for plain Newton it is
    /// the measure the load steps were tuned with.)
    bool
    easy() const
    {
      return iterations <= 4 && !(accelerated && damped_updates > 0);
    }

    /// Whether the step was hard, so that the next one should be shorter:
    /// 8 or more iterations with a new tangent.
    bool
    hard() const
    {
      return iterations >= 8;
    }
  };

  using FibreFunction = Fibres::FibreField;

  /// The energy flows of the accepted state of a time integration
  /// (Problem::accepted_powers()) [kPa mm^3/ms = mW].
  struct PowerReport
  {
    /// Dissipated: int eta dE/dt : dE/dt dV + the dashpots' beta |v|^2 (or
    /// (v.N)^2) over their parts + c_M v.Mv (Rayleigh).
    double dissipation = 0.0;
    /// Delivered by the loads: the follower pressures, -p int v . cof(F) N
    /// dA, and the active stress, -int S_a : dE/dt dV.
    double loads = 0.0;
  };

  /// The state of the mechanics at one quadrature point of a locally owned
  /// cell, for the postprocessors (Problem::point_states()).
  struct PointState
  {
    dealii::Point<3>     position; ///< reference position X [mm]
    double               JxW = 0;  ///< reference volume weight [mm^3]
    dealii::Tensor<2, 3> F;        ///< deformation gradient
    Fibres::FibreBasis   basis;    ///< reference fibre frame (f0, s0, n0)
    /// Active tension T_a [kPa]: the uniform one of the last solve plus the
    /// point's (set_active_tension()).
    double active_tension = 0;
    /// Cauchy stress sigma = J^-1 F S F^T of everything at the point
    /// (passive, volumetric or pressure, active) [kPa].
    dealii::SymmetricTensor<2, 3> cauchy_stress;
  };

  /// A vertex of the mesh: its reference and deformed positions [mm].
  struct VertexState
  {
    dealii::Point<3> reference;
    dealii::Point<3> deformed;
  };

  /// Quasi-static finite-strain mechanics of the myocardium on a distributed
  /// mesh: displacement-based, Q1 or Q2, with a volumetric penalty for the
  /// near-incompressibility, follower pressure, Dirichlet (fixed or sliding)
  /// and Robin boundaries, and a prescribed active tension along the fibres.
  ///
  /// Equilibrium: @f$R(u) = \int_{\Omega_0} P(F) : \nabla\delta u\,dV
  /// - \sum_i p_i\,\frac{dV_i}{du} + R_\mathrm{Robin} = 0@f$, solved by
  /// Newton's method with the consistent tangent. Cheap to include (pimpl).
  ///
  /// The follower pressures act on the parts of Parameters::pressure_boundary,
  /// one pressure p_i each. When the mesh has a boundary part "base", every
  /// pressure part is a cavity closed by the base plane, with the volume V_i
  /// (CavityVolume) whose derivative dV_i/du is the pressure load per unit
  /// pressure; the cavities are numbered as the parts are listed. That
  /// identity (and with it the symmetry of the tangent and the quadratic rate
  /// of the volume-constrained solves) holds while the rim of each part lies
  /// in the base plane (a base held in its plane), as for the endocardia of
  /// a ventricle. Parts that meet off the plane, such as one cavity split in
  /// two, still add up to the whole volume, but dV_i/du then differs from
  /// the load by the motion of their common edge.
  ///
  /// A cavity whose basal ring is not planar (Geometry::cavity_closure: a
  /// ruled or warped base) is closed by the fan from its rim's vertex mean
  /// (CavityVolume::Closure::rim_fan; a warning when the ring is more than
  /// Geometry::rim_warning_fraction of its size off its best plane). Its
  /// V_i is exact for any rim, but the load stays the endocardial flux b_i:
  /// no pressure acts on the lid, which is not a surface of the body. While
  /// the base is fixed the rim does not move and b_i = dV_i/du exactly. When
  /// it moves (a sliding or free base), dV_i/du = b_i + the lid's flux, the
  /// pressure work p dV_i exceeds the load's work by p times that flux, the
  /// tangent is not symmetric (LU is used), and the bordered Newton of
  /// solve_cavities(), which puts b_i in both its load column and its volume
  /// row, has an inexact volume row: it converges to the right (u, p), as
  /// the residuals are exact, but linearly instead of quadratically.
  class ProblemChecks;

  class Problem
  {
  public:
    /// The volumes W(p) [mm^3] the cavities must hold as a function of
    /// their pressures p [kPa] (size n_cavities()), and dW/dp [mm^3/kPa]
    /// (k x k). A fixed volume has dW/dp = 0; a cavity coupled to an
    /// implicit step of a 0D circulation has W(p) = its volume state after
    /// the step.
    ///
    /// Called on every rank with the same p, at every iterate of
    /// solve_cavities(); W and dW_dp arrive sized (k, k x k) and zeroed, and
    /// must come out the same on every rank. W_i must not be zero (the
    /// volume tolerance is relative to it).
    using VolumeTarget = std::function<void(const dealii::Vector<double> &p,
                                            dealii::Vector<double>       &W,
                                            dealii::FullMatrix<double> &dW_dp)>;

    /// What a problem is built from (the problem's constructor and its
    /// Impl's take it whole; the callers brace it in this order).
    struct Inputs
    {
      const Parameters &params;
      /// the mesh (kept by reference; must outlive the problem)
      dealii::parallel::DistributedTriangulationBase<3, 3> &tria;
      /// its boundary parts; every part named in params must exist (clear
      /// error otherwise)
      const Geometry::BoundaryNames &names;
      unsigned int                   degree; ///< of the displacement (1 or 2)
      unsigned int                 mapping_degree; ///< of the geometry mapping
      const Materials::PassiveLaw &passive_law;
      const Materials::VolumetricLaw &volumetric_law;
      /// evaluated once at the quadrature points of every locally owned
      /// cell
      const FibreFunction &fibres;
      Logger              &logger;
      /// Whether the caller solves at given pressures only (solve(), no
      /// solve_volume(); Problem = mechanics): Linear solver = auto may then
      /// pick the matrix-free solver where it applies.
      bool fixed_pressures = false;
    };

    explicit Problem(const Inputs &in);
    ~Problem();

    /// Solve for equilibrium under @p pressure [kPa] on every pressure part
    /// and @p active_tension [kPa], starting from the current displacement.
    /// Throws ExcNewtonDidNotConverge (on every rank alike) when Newton
    /// fails; the displacement is then undefined: restore() it.
    NewtonReport
    solve(const double pressure, const double active_tension);

    /// The same with one pressure [kPa] per pressure part (in the order of
    /// Parameters::pressure_boundaries(); the cavities when there is a base).
    NewtonReport
    solve(const dealii::Vector<double> &pressures, const double active_tension);

    /// Solve for equilibrium (u, p) with the cavity volumes on their target:
    /// V_i(u) = W_i(p), i = 1..k (k = n_cavities() >= 1). The pressures p
    /// [kPa] are the Lagrange multipliers. Newton on the bordered system
    /// @f[ \begin{pmatrix} K & -B \\ B^T & -W' \end{pmatrix}
    ///     \begin{pmatrix} \delta u \\ \delta p \end{pmatrix}
    ///   = -\begin{pmatrix} R \\ V(u) - W(p) \end{pmatrix}, @f]
    /// B = [dV_1/du ... dV_k/du], W' = dW/dp: one factorization of K, k + 1
    /// back substitutions (K w_R = -R, K w_j = b_j) and the k x k Schur
    /// complement B^T [w_1 ... w_k] - W'. @p pressures (size k) is the
    /// initial guess on entry and the solution on exit. Converged when the
    /// residual meets the Newton tolerances and |V_i - W_i| <= 2e-9 |W_i| for
    /// every cavity, W evaluated at the current p. Throws like solve().
    ///
    /// While a factorization of an earlier volume-constrained solve exists,
    /// the solve starts with chord iterations on it (the bordered system of
    /// that tangent and its B, with W and W' of the current p; one back
    /// substitution each, residual without tangent); when they converge
    /// slower than a factor 0.3 per iteration, or would need more than three
    /// more, it continues with full Newton.
    /// Consecutive solves of a time integration differ little, so most need
    /// no new factorization.
    NewtonReport
    solve_cavities(const VolumeTarget     &target,
                   const double            active_tension,
                   dealii::Vector<double> &pressures);

    /// solve_cavities() for one cavity and the fixed volume
    /// @p target_volume [mm^3]; @p pressure [kPa] is the initial guess on
    /// entry and the solution on exit. Throws unless n_cavities() == 1.
    NewtonReport
    solve_volume(const double target_volume,
                 const double active_tension,
                 double      &pressure);

    /// Reference positions of the quadrature points of the mechanics, per
    /// locally owned cell (indexed by active cell index; empty for other
    /// cells), in the order set_active_tension() expects.
    void
    quadrature_points(std::vector<std::vector<dealii::Point<3>>> &points) const;

    /// A per-point active tension [kPa] (layout of quadrature_points()),
    /// added to the uniform one of solve(); an empty argument removes it.
    void
    set_active_tension(std::vector<std::vector<double>> tension);

    /// Elastodynamics, part 1: start a time integration with inertia
    /// (density Parameters::density, Rayleigh damping c_M M) from the
    /// current displacement at rest, under the loads @p pressures [kPa] (one
    /// per pressure part) and @p active_tension [kPa] at the start time: the
    /// initial acceleration solves M a_0 = -R(u_0) (zero at an
    /// equilibrium). Assembles the mass matrix on the first call. The
    /// generalized-alpha method (Chung and Hulbert 1993, with the spectral
    /// radius Parameters::spectral_radius; second order) then integrates
    /// M a + C v + R(u) = 0 step by step: set_time_step(), solve() (or
    /// solve_cavities(): the cavity pressures are the multipliers of the
    /// volume constraints at the step's end) at the loads of the step's end,
    /// accept_time_step(). A failed or rejected solve is repeated from the
    /// accepted state (restore() the displacement; the accepted state
    /// changes only in accept_time_step()). Penalty formulation only.
    /// Checkpoints carry the dynamic state.
    /// In motion (@p elapsed > 0): with the velocity v_0 = (u - u_s) /
    /// @p elapsed [ms] of the motion from the last save() u_s to the current
    /// displacement u (e.g. a first quasi-static step, whose velocity is then
    /// consistent with the flow into the cavities), and the acceleration of
    /// the equation of motion, M a_0 = -(R(u_0, v_0) + C v_0) (the rate
    /// terms, viscosity and dashpots, at v_0). Collective.
    void
    start_dynamics(const dealii::Vector<double> &pressures,
                   const double                  active_tension,
                   const double                  elapsed = 0.0);
    /// At rest, with the pressure @p pressure on every pressure part.
    void
    start_dynamics(const double pressure, const double active_tension);

    /// Part 2: the solves until the next call are time steps of
    /// @p time_step [ms] from the accepted state (0: quasi-static solves
    /// again, the state is kept).
    void
    set_time_step(const double time_step);

    /// Part 3: after a converged solve, the displacement becomes the
    /// accepted state (with its velocity and acceleration from Newmark's
    /// formulas); @p pressures and @p active_tension are the loads the step
    /// was solved with. With a tension model, call it before
    /// accept_tension_step() (the residual of the accepted state uses the
    /// step's tension). Collective.
    void
    accept_time_step(const dealii::Vector<double> &pressures,
                     const double                  active_tension);
    void
    accept_time_step(const double pressure, const double active_tension);

    /// Kinetic energy (1/2) int rho |v|^2 dV of the accepted state [mN mm =
    /// µJ] (0 before start_dynamics(); collective).
    double
    kinetic_energy() const;

    /// Energy stored in the springs of the Robin supports, (1/2) alpha int
    /// |u|^2 dA (or (u.N)^2; u less its end-diastolic reference where the
    /// support is referred to it) at the current displacement [µJ]
    /// (collective).
    double
    support_energy() const;

    /// The supports referred to end-diastole (Robin supports, option
    /// end-diastole) take the current displacement as their rest position,
    /// at once or, with a release time, moving there from their present one
    /// from @p time [ms] on: the heartbeat calls it at every end-diastole,
    /// after the step is accepted. Nothing without such a support.
    /// Collective.
    void
    refer_supports_to_end_diastole(double time);

    /// The supports' rest position at @p time [ms] during a release
    /// (refer_supports_to_end_diastole()); call it before each solve.
    /// Collective.
    void
    set_support_time(double time);

    /// The powers of the accepted state (u_n, v_n) of the time integration
    /// under @p pressures [kPa] (one per pressure part) and the uniform
    /// @p active_tension [kPa] (plus the per-point tensions): kinetic +
    /// strain + support energy change at the rate loads - dissipation.
    /// Zero before start_dynamics(). Collective.
    PowerReport
    accepted_powers(const dealii::Vector<double> &pressures,
                    const double                  active_tension) const;

    /// Stored energy int (psi + U(J)) dV at the current displacement [µJ]:
    /// the passive law and the volumetric penalty; in a mixed formulation
    /// int (psi(Fbar) - p (J - 1) - p^2 / (2 kappa)) dV, its value at
    /// solutions (the active tension and the loads do no part of it;
    /// collective).
    double
    strain_energy() const;

    /// Two-way coupling with a tension model (Materials::TensionModel,
    /// e.g. Land): every assembly evaluates @p model at each quadrature
    /// point from the point's accepted state, its calcium
    /// (set_calcium()), the fibre stretch λ = |F f0| of the current
    /// iterate and the rate dλ/dt = (λ - λ_n)/Δt (λ_n: the stretch of the
    /// accepted state), over the step of set_tension_step(); its tension
    /// adds to the others and dT/dλ enters the tangent, dS/dE +=
    /// (dT/dλ / λ) f0 x f0 x f0 x f0 (Mechanics / Active transverse
    /// fraction must be 0: throws otherwise). Newton
    /// iterations and cut steps repeat the step from the accepted state;
    /// accept_tension_step() commits it. Initializes every point's state
    /// to the model's resting state and λ_n = 1 (the reference
    /// configuration); nullptr removes the model. @p model must outlive
    /// the problem (or the next call). Checkpoints do not hold the model's
    /// states yet.
    void
    set_tension_model(const Materials::TensionModel *model);

    /// The step of the tension model: from the accepted state to @p time
    /// [ms], of length @p time_step [ms] (> 0).
    void
    set_tension_step(const double time, const double time_step);

    /// The calcium at the end of the step [µM] per point (layout of
    /// quadrature_points()), or one value for every point (@p uniform).
    void
    set_calcium(const std::vector<std::vector<double>> &calcium);
    void
    set_calcium(const double uniform);

    /// Accept the tension model's step at the current displacement: every
    /// point's state becomes the step's result and λ_n its current stretch.
    void
    accept_tension_step();

    /// The tension model's tension at every point for the current
    /// displacement and step [kPa] (layout of quadrature_points(); does not
    /// change the states).
    std::vector<std::vector<double>>
    model_tensions() const;

    /// The net force of the cavity pressures @p pressures [kPa] on the wall
    /// at the current u, the sum over the nodes of their load (the
    /// residual's change from zero pressures) [kPa mm^2 = mN]: about -p
    /// times the lid's vector area with the pressure on the endocardium
    /// only, zero with Lid pressure (the closed cavity). Collective.
    dealii::Tensor<1, 3>
    net_pressure_force(const dealii::Vector<double> &pressures);

    /// Remember the current displacement (a converged state); the two saved
    /// before become the earlier states for predict().
    void
    save();

    /// Extrapolate from the last two saved states: u = u_s + ratio (u_s -
    /// u_prev), the predictor of the next load step (ratio = next increment /
    /// last increment). Before the second save(): u_s.
    void
    predict(const double ratio);

    /// u = w_0 u_s + w_1 u_prev + w_2 u_before, the last three saved states
    /// (latest first; the weights of a polynomial extrapolation sum to 1).
    /// A nonzero weight needs that many saves.
    void
    predict(const std::array<double, 3> &weights);
    /// The largest nodal displacement [mm] between the current state and
    /// the last predict(ratio): after a converged solve, how far its
    /// predictor missed (the heartbeat's step-size control keeps it small;
    /// HeartbeatStepper::Settings::displacement_tolerance). 0 before the
    /// first predict(). Collective.
    double
    predictor_error() const;

    /// predict(@p ratio), kept only if the residual under the loads of the
    /// next step (@p pressure [kPa], @p active_tension [kPa]) is smaller there
    /// than at the last saved state; otherwise the saved state (whose first
    /// Newton step is the tangent predictor). The secant extrapolation
    /// overshoots where the exponential laws stiffen. Collective; two
    /// residual assemblies.
    void
    predict(const double ratio,
            const double pressure,
            const double active_tension);
    /// Go back to the displacement of the last save().
    void
    restore();

    /// Checkpoint, part 1 (after save(), before the triangulation's save()):
    /// attach to the cells of the mesh, for the next save() of the
    /// distributed mesh (p4est or fully distributed), the last two saved
    /// displacements and the iterate whose tangent the linear solver holds
    /// factorized (SolutionTransfer), and the active tension of that
    /// iterate per quadrature point; write the small state (saves, the
    /// factorization's pressures) to @p archive. With the factorization
    /// rebuilt from them, the solves after a restart repeat the chord
    /// iterations of the uninterrupted run.
    void
    prepare_checkpoint(boost::archive::text_oarchive &archive);

    /// Checkpoint, part 2 (for a problem built on a mesh loaded by
    /// Triangulation::load() from a checkpoint, the attached data read in
    /// the order written): read what prepare_checkpoint() wrote, make the
    /// last saved state current and refactorize the tangent the solver held.
    /// Collective.
    void
    load_checkpoint(boost::archive::text_iarchive &archive);

    /// After the triangulation's save(): release what prepare_checkpoint()
    /// attached.
    void
    finish_checkpoint();

    /// Set the displacement to the interpolant of @p displacement (3
    /// components, mm), then apply the constraints (a mixed formulation's
    /// pressure becomes zero).
    void
    set_displacement(const dealii::Function<3> &displacement);

    /// Number of cavities: the pressure parts when the mesh has a base, else
    /// 0.
    unsigned int
    n_cavities() const;

    /// The boundary part names of the cavities, in order.
    std::vector<std::string>
    cavity_names() const;

    /// Cavity volumes V_i [mm^3]: each pressure part closed by the plane of
    /// the base (size n_cavities(); collective).
    dealii::Vector<double>
    cavity_volumes() const;

    /// The cavity volume [mm^3] of a problem with exactly one cavity (throws
    /// otherwise; collective).
    double
    cavity_volume() const;

    /// Whether the pressure acts on cavities (n_cavities() > 0): the mesh
    /// has a base and a pressure boundary.
    bool
    has_cavity() const;

    /// Deformed positions X + u(X) of reference points [mm] (collective;
    /// throws if a point lies outside the mesh).
    std::vector<dealii::Point<3>>
    deformed_positions(const std::vector<dealii::Point<3>> &points) const;

    /// Add the displacement field to @p data_out (the DoF handler is attached
    /// here; call before build_patches).
    void
    attach_output(dealii::DataOut<3, 3> &data_out) const;

    /// The mapping of the curved geometry, for build_patches.
    const dealii::Mapping<3, 3> &
    mapping() const;

    dealii::types::global_dof_index
    n_dofs() const;

    /// "direct (MUMPS)" or "iterative (GMRES + GAMG)".
    std::string
    linear_solver_name() const;

    /// The fields and elements, e.g. "Q2-P1disc (u-p, incompressible)".
    std::string
    discretization_name() const;

    /// Global DoFs of the displacement and of the pressure (0 for penalty).
    std::array<dealii::types::global_dof_index, 2>
    n_block_dofs() const;

    /// Total wall times [s] of the mechanics' timer sections so far
    /// ("Mechanics / Newton", and inside it "Mechanics / assembly",
    /// "Mechanics / linear solver", "Mechanics / cavity volume"; inside the
    /// linear solver's, "Mechanics / linear solver set-up": factorizations
    /// or preconditioner set-ups of the Newton updates; inside the
    /// assembly's, "Mechanics / matrix-free tangent update"), on this rank.
    std::map<std::string, double>
    timings() const;

    /// The state at every quadrature point of the locally owned cells, indexed
    /// by active cell index (empty for other cells), in the order of
    /// quadrature_points(), at the current displacement. Not collective.
    void
    point_states(std::vector<std::vector<PointState>> &states) const;

    /// The vertices of the mesh whose displacement DoFs this rank owns (every
    /// vertex on exactly one rank). The displacement at a vertex is its nodal
    /// value, exact for an interpolated displacement.
    std::vector<VertexState>
    vertex_states() const;

    /// Area of boundary part @p part [mm^2] in the current (deformed)
    /// configuration, int |cof(F) N| dA over the reference faces
    /// (collective); with @p cells (per active cell index) only the faces
    /// of the cells it marks. Throws if the mesh has no such part.
    double
    deformed_area(const std::string       &part,
                  const std::vector<bool> *cells = nullptr) const;

    /// Gauss points per direction of the cells (quadrature_points() uses
    /// QGauss<3> of this order).
    unsigned int
    n_quadrature_points_1d() const;

    /// The mesh.
    const dealii::Triangulation<3, 3> &
    triangulation() const;

    /// The cell shape of the mesh and the elements, rules and output patches
    /// that go with it.
    const Geometry::CellKind &
    cell_kind() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
    /// The verification hooks (problem_checks.h) work on the Impl.
    friend class ProblemChecks;
  };
} // namespace systole::Mechanics
