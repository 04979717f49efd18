#pragma once

// Internal to src/mechanics: the state of Mechanics::Problem, shared by its
// translation units (problem.cc, assembly.cc, newton.cc, ...). Not included
// elsewhere.

#include <deal.II/base/quadrature_point_data.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/vector.h>

#include "base/attached_vectors.h"
#include "base/linear_algebra.h"
#include "base/logger.h"
#include "fibres/fibre_basis.h"
#include "materials/isochoric_part.h"
#include "materials/tension_model.h"
#include "mechanics/cavity_volume.h"
#include "mechanics/field_layout.h"
#include "mechanics/linear_solver.h"
#include "mechanics/newton_system.h"
#include "mechanics/problem.h"

#include <functional>
#include <optional>
#include <set>
#include <sstream>

namespace systole::Mechanics
{
  class MatrixFreeTangent;

  /// What the mechanics keeps at one quadrature point of a locally owned
  /// cell (in a CellDataStorage; set up once).
  struct PointData
  {
    Fibres::FibreBasis basis;    ///< fibre frame
    dealii::Point<3>   position; ///< reference position [mm]
    double tension = 0.0; ///< active tension added to the uniform one [kPa]
    /// The tension model's accepted state (Problem::set_tension_model()).
    std::vector<double> tension_state;
    double stretch_n = 1.0; ///< fibre stretch of the accepted state [-]
    double calcium   = 0.0; ///< at the end of the step [µM]
    /// The model's tension of the last assembly [kPa] (for point_states()).
    double model_tension = 0.0;
  };

  /// The state of the elastodynamics (Problem::start_dynamics()): the
  /// generalized-alpha method of Chung and Hulbert (1993) with the averaged
  /// forces, for M a + C v + R(u) = 0 (R the quasi-static residual, with
  /// every load):
  /// @f[ (1 - \alpha_m) M a_{n+1} + \alpha_m M a_n
  ///     + C ((1 - \alpha_f) v_{n+1} + \alpha_f v_n)
  ///     + (1 - \alpha_f) R(u_{n+1}) + \alpha_f R(u_n) = 0, @f]
  /// with Newmark's u_{n+1} = u_n + dt v_n + dt^2 ((1/2 - beta) a_n + beta
  /// a_{n+1}), v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1}) and
  /// alpha_m = (2 rho - 1)/(rho + 1), alpha_f = rho/(rho + 1), gamma = 1/2 -
  /// alpha_m + alpha_f, beta = (1 - alpha_m + alpha_f)^2 / 4 (rho the
  /// spectral radius at infinite frequency): second order, unconditionally
  /// stable, C = c_M M (Rayleigh). The assembly divides this balance by
  /// 1 - alpha_f: residual R(u_{n+1}) + (alpha_f R(u_n) + M A) / (1 -
  /// alpha_f), so that dR/dp_i = -dV_i/du as in the quasi-static solves and
  /// the bordered (volume-constrained) Newton needs no change.
  struct Dynamics
  {
    bool   started   = false;
    double time_step = 0.0; ///< of the next solves [ms]; 0: quasi-static
    double alpha_m = 0, alpha_f = 0, beta = 0, gamma = 0;
    double mass_damping = 0.0; ///< c_M [1/ms]
    /// The consistent mass matrix of the displacement (condensed like the
    /// tangent) [mg]; a mixed formulation's pressure rows hold a positive
    /// diagonal alone (M a = f leaves a = 0 there where f = 0).
    LA::MPI::SparseMatrix mass;
    /// The owned pressure DoFs of a mixed formulation (empty for the
    /// penalty): the pressure has no rates, rates() sets them to 0.
    dealii::IndexSet pressure_dofs;
    /// The accepted state: displacement, velocity, acceleration, and the
    /// quasi-static residual R(u_n) (owned).
    LA::MPI::Vector u_n, v_n, a_n, residual_n;
    /// (1 - alpha_m) a_{n+1} + alpha_m a_n + c_M ((1 - alpha_f) v_{n+1} +
    /// alpha_f v_n) at the current u (ghosted; set by the assembly).
    LA::MPI::Vector effective_acceleration;
    /// The velocity the rate terms (viscosity, dashpots) see: v_{n+1} of the
    /// current u in a time step, v_n while the accepted state's residual is
    /// assembled (ghosted; set by the assembly and accept_time_step()).
    LA::MPI::Vector velocity;
    /// accept_time_step() assembles R(u_n, v_n): the rate terms use v_n.
    bool accepting = false;
    /// The accepted state and the time step of the iterate whose tangent
    /// the linear solver holds (remember_factorized_tension()), so that a
    /// checkpoint can rebuild that tangent (its mass and rate terms).
    double          factorized_time_step = 0.0;
    LA::MPI::Vector factorized_u_n, factorized_v_n, factorized_a_n;

    /// a_{n+1} and v_{n+1} of the displacement @p u (owned; 0 at the
    /// pressure_dofs).
    void
    rates(const LA::MPI::Vector &u,
          LA::MPI::Vector       &a,
          LA::MPI::Vector       &v) const;
    /// d(effective acceleration)/du [1/ms^2] (a multiple of the identity).
    double
    effective_mass_coefficient() const;
    /// d v_{n+1} / d u_{n+1} = gamma / (beta dt) [1/ms].
    double
    velocity_coefficient() const;
  };

  /// One step of the tension model @p model at point @p data with
  /// deformation gradient @p F, from the accepted state to @p time over
  /// @p time_step; writes the step's state to @p trial (n_states() values).
  /// Returns T [kPa] and sets @p dT_dstretch and @p stretch (λ = |F f0|).
  inline double
  step_tension_model(const Materials::TensionModel &model,
                     const PointData               &data,
                     const dealii::Tensor<2, 3>    &F,
                     const double                   time,
                     const double                   time_step,
                     double                        *trial,
                     double                        &dT_dstretch,
                     double                        &stretch)
  {
    stretch = (F * data.basis.f).norm();
    Materials::TensionInput in;
    in.time             = time;
    in.time_step        = time_step;
    in.calcium          = data.calcium;
    in.stretch          = stretch;
    in.previous_stretch = data.stretch_n;
    Materials::TensionOutput out;
    model.step(data.tension_state.data(), in, trial, out);
    dT_dstretch = out.dtension_dstretch;
    return out.tension;
  }

  /// The material laws as the assembly sees them, and the constants derived
  /// from them once.
  struct MaterialLaws
  {
    /// Checks the laws against the parameters (a nearly incompressible
    /// formulation needs a bulk modulus, every law a shear stiffness).
    MaterialLaws(const Parameters               &params,
                 const Materials::PassiveLaw    &passive_law,
                 const Materials::VolumetricLaw &volumetric_law);

    /// The law as given (penalty) or its isochoric part (mixed formulations).
    std::optional<Materials::IsochoricPart> isochoric_law;
    const Materials::PassiveLaw            &passive_law;
    const Materials::VolumetricLaw         &volumetric_law;
    /// 1/kappa of the mixed formulations (0 when incompressible).
    double inverse_bulk_modulus = 0.0;
    /// Lower bound of the local shear stiffness in the Schur preconditioner
    /// [kPa] (a tenth of the law's at F = I).
    double reference_shear_stiffness = 0.0;
  };

  struct BoundaryConditions;

  /// The discretization: the fields and their element, the geometry, the
  /// DoFs and their constraints, the quadrature rules.
  struct Discretization
  {
    Discretization(const Parameters                                     &params,
                   dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
                   const unsigned int                                    degree,
                   const unsigned int mapping_degree);

    /// Distributes the DoFs and builds the constraints (zero displacement on
    /// the fixed parts, zero normal displacement on the sliding ones).
    void
    distribute_dofs(const BoundaryConditions &boundaries);
    /// The constraints of the displacement (components 0-2) of @p dofs (a
    /// DoFHandler on this mesh, e.g. the Q1 level of the matrix-free
    /// solver) as distribute_dofs() builds them.
    void
    make_constraints(const dealii::DoFHandler<3>       &dofs,
                     const BoundaryConditions          &boundaries,
                     dealii::AffineConstraints<double> &result) const;
    /// body_volume and n_pressure_dofs (collective).
    void
    measure(const MPI_Comm comm);

    /// The fields (u, or u and p) and their blocks.
    FieldLayout                                  layout;
    std::unique_ptr<dealii::FiniteElement<3, 3>> fe;
    /// Reference volume of the body [mm^3] (the scale of the pressure rows).
    double body_volume = 0.0;
    /// Global number of pressure DoFs.
    long n_pressure_dofs = 0;
    /// The geometry (Geometry::CellKind::mapping(): on hexahedra a
    /// MappingQCache of the manifolds, its support points computed once, as
    /// the manifold evaluations would otherwise dominate every assembly; on
    /// tetrahedra affine).
    std::unique_ptr<dealii::Mapping<3, 3>> mapping_storage;
    const dealii::Mapping<3, 3>           &mapping;
    dealii::DoFHandler<3>                  dof_handler;
    unsigned int n_q_1d;             ///< Gauss points per direction (cells)
    unsigned int n_q_face_1d;        ///< Gauss points per direction (faces)
    bool         reduced_volumetric; ///< volumetric term with n_q_1d - 1 points

    /// The quadrature rules of cells and faces (CellKind of the mesh).
    dealii::Quadrature<3>
    cell_quadrature(const unsigned int n_points_1d) const
    {
      return layout.cell_kind().cell_quadrature(n_points_1d);
    }
    dealii::Quadrature<2>
    face_quadrature(const unsigned int n_points_1d) const
    {
      return layout.cell_kind().face_quadrature(n_points_1d);
    }

    /// Calls @p f(cell, fe_values) on every locally owned cell, fe_values
    /// (the cell rule of @p n_points_1d points per direction, @p flags)
    /// reinitialized on it.
    template <typename Function>
    void
    for_each_owned_cell(const unsigned int        n_points_1d,
                        const dealii::UpdateFlags flags,
                        const Function           &f) const
    {
      dealii::FEValues<3> fe_values(mapping,
                                    *fe,
                                    cell_quadrature(n_points_1d),
                                    flags);
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            f(cell, fe_values);
          }
    }

    /// Calls @p f(face, fe_face) on every boundary face of the locally owned
    /// cells whose boundary id @p on_part(id) accepts, fe_face (the face rule
    /// of n_q_face_1d points per direction, @p flags) reinitialized on it.
    template <typename Predicate, typename Function>
    void
    for_each_owned_boundary_face(const dealii::UpdateFlags flags,
                                 const Predicate          &on_part,
                                 const Function           &f) const
    {
      dealii::FEFaceValues<3> fe_face(mapping,
                                      *fe,
                                      face_quadrature(n_q_face_1d),
                                      flags);
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && cell->at_boundary())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && on_part(face->boundary_id()))
              {
                fe_face.reinit(cell, face);
                f(face, fe_face);
              }
    }

    dealii::IndexSet                  owned, relevant;
    dealii::AffineConstraints<double> constraints; ///< homogeneous
  };

  /// Where the displacement is held: the boundary parts by their role.
  struct BoundaryConditions
  {
    /// The parts named by the parameters (each must exist and carry faces;
    /// tapered supports located).
    BoundaryConditions(const Parameters                  &params,
                       const dealii::Triangulation<3, 3> &tria,
                       const Geometry::BoundaryNames     &names);

    /// The boundary parts of the mesh (deformed_area()).
    Geometry::BoundaryNames              boundary_names;
    std::set<dealii::types::boundary_id> fixed_ids, sliding_ids;
    /// The spring-dashpot supports by boundary id (Parameters::
    /// all_robin_supports()).
    std::map<dealii::types::boundary_id, RobinSupport> robin_supports;
    /// Ghosted: the displacement the supports referred to end-diastole
    /// (RobinSupport::from_end_diastole) pull toward at the time of the
    /// last Problem::set_support_time(), zero until the first
    /// Problem::refer_supports_to_end_diastole(); empty without such a
    /// support.
    LA::MPI::Vector support_reference;
    /// Their release: the rest position moves from @p from to @p to (owned)
    /// over @p time from @p start [ms] (RobinSupport::release_time; with 0,
    /// at once to @p to).
    struct Release
    {
      LA::MPI::Vector from, to;
      double          start = 0, time = 0;
      /// The fraction of the way from @p from to @p to support_reference
      /// holds (-1: not set since the last reference).
      double applied = -1;
    } release;

    /// Whether a support is referred to end-diastole.
    bool
    any_from_end_diastole() const;

    /// The displacement the springs of @p support stretch at the quadrature
    /// points of @p fe_face into @p values: @p u, less support_reference for
    /// a support referred to end-diastole (@p scratch holds it).
    void
    support_stretch(const dealii::FEFaceValues<3>            &fe_face,
                    const dealii::FEValuesExtractors::Vector &displacement,
                    const LA::MPI::Vector                    &u,
                    const RobinSupport                       &support,
                    std::vector<dealii::Tensor<1, 3>>        &values,
                    std::vector<dealii::Tensor<1, 3>>        &scratch) const;
  };

  /// The pressure loads and the cavities they fill: the parts, the cavity
  /// volumes, the volume rows of the bordered Newton system and the low-rank
  /// coupling of loaded lids.
  struct CavityLoads
  {
    /// The pressure parts of the parameters and, when the mesh has a base,
    /// their cavities (close_cavities()).
    CavityLoads(const Parameters                  &params,
                const dealii::Triangulation<3, 3> &tria,
                const BoundaryConditions          &boundaries,
                Logger                            &logger);
    /// One cavity per pressure part, closed by the base plane, its planar
    /// rim or the fan over the rim (moving when the base is not held in its
    /// plane); a warning for a rim far from a plane.
    void
    close_cavities(const dealii::Triangulation<3, 3> &tria,
                   const BoundaryConditions          &boundaries,
                   Logger                            &logger);

    /// The pressure parts (Parameters::pressure_boundaries()), in order.
    std::vector<std::string>                pressure_names;
    std::vector<dealii::types::boundary_id> pressure_ids;
    /// One per pressure part when the mesh has a base, else none.
    std::vector<CavityVolume> cavities;
    /// Owned: the endocardial flux of every cavity (the load per unit
    /// pressure), condensed; dV_i/du unless the cavity's lid moves.
    std::vector<LA::MPI::Vector> volume_derivatives;
    /// Owned: dV_i/du exactly, condensed: the volume rows of the bordered
    /// Newton system. volume_derivatives[i] except for a cavity with a
    /// moving lid, whose dV_i/du has the lid's flux too
    /// (CavityVolume::derivative).
    std::vector<LA::MPI::Vector> volume_rows;
    /// Per cavity: closed by the fan over a rim that moves (the base is not
    /// held in its plane), so that dV/du is not the endocardial flux.
    std::vector<bool> moving_lid;
    /// The part of the tangent the sparse matrix does not hold: K = tangent
    /// + sum_j low_rank_u[j] low_rank_v[j]^T (owned, condensed): the rank-6
    /// coupling of each loaded lid's rim to its wall (Lid pressure), of the
    /// last assembly with the matrix. Empty without.
    std::vector<LA::MPI::Vector> low_rank_u, low_rank_v;
  };

  /// The state at the quadrature points and the inputs of the active
  /// tension.
  struct QuadraturePoints
  {
    /// The fibre frame and position of every quadrature point of the
    /// locally owned cells.
    void
    initialize(const Discretization &discretization,
               const FibreFunction  &fibres);

    /// Fibre frame, position and active tension at the quadrature points of
    /// the locally owned cells.
    dealii::CellDataStorage<dealii::Triangulation<3, 3>::cell_iterator,
                            PointData>
      point_data;
    /// The two-way coupled tension model (none: nullptr) and its step.
    const Materials::TensionModel *tension_model     = nullptr;
    double                         tension_time      = 0.0;
    double                         tension_time_step = 0.0;
    /// The uniform active tension of the last assembly [kPa] (for
    /// point_states()).
    double last_active_tension = 0.0;
  };

  /// The linear system of a Newton iteration and its solver.
  struct LinearSystem
  {
    LA::MPI::SparseMatrix tangent;
    LA::MPI::Vector       residual; ///< owned
    /// The Schur-complement preconditioner of the mixed iterative solver.
    std::unique_ptr<PressureMatrix> pressure_matrix;
    /// The augmented Lagrangian of the mixed iterative solver with a
    /// discontinuous pressure (null otherwise): G = gamma B^T W^-1
    /// (displacement rows, pressure columns), with which the tangent holds
    /// T K, T = [I, G; 0, I] (the linear solver applies T to its right-hand
    /// sides; tangent_vmult() undoes it).
    std::unique_ptr<LA::MPI::SparseMatrix> augmentation;
    /// gamma of the augmented Lagrangian (Mechanics / Augmented Lagrangian
    /// factor; 0 when there is no augmentation).
    double augmented_lagrangian = 0.0;

    std::unique_ptr<LinearSolver> linear_solver;
    /// "direct", "iterative" or "matrix-free" (auto resolved), and whether
    /// the tangent is
    /// symmetric (the direct solver's LDL^T, the iterative one's CG).
    std::string linear_solver_name;
    bool        symmetric_tangent = true;
  };

  /// A checkpoint being written: the attached vectors (alive until the
  /// triangulation's save()), and the packed cell data, by active cell index.
  struct CheckpointBuffers
  {
    AttachedVectors                vectors;
    std::vector<std::vector<char>> cell_data;
  };

  struct Problem::Impl : public NewtonSystem
  {
    /// (Problem's constructor then sets up the fibres and the solver.)
    explicit Impl(const Inputs &in);

    /// Residual (and, if @p with_matrix, tangent) at the current u for the
    /// given loads (@p pressures: one per pressure part). Returns the l2 norm
    /// of the constrained residual. Throws ExcInvertedElement collectively
    /// when J <= 0 somewhere. If @p with_volume_derivative, also assembles
    /// dV_i/du of every cavity into volume_derivatives (condensed like the
    /// residual).
    double
    assemble(const dealii::Vector<double> &pressures,
             const double                  active_tension,
             const bool                    with_matrix,
             const bool with_volume_derivative = false) override;

    /// assemble() for the matrix-free linear solver: the residual, then
    /// @p tangent's point data (the kernel again) instead of a sparse matrix.
    double
    assemble_matrix_free(MatrixFreeTangent            &tangent,
                         const dealii::Vector<double> &pressures,
                         const double                  active_tension,
                         const bool                    with_volume_derivative);

    /// Refill the general matrix-free @p tangent (on this problem's
    /// mapping, DoFs and constraints) with dP/dF of the bulk term at the
    /// current u under @p active_tension (and the per-point tensions, the
    /// tension model): evaluate_point() and first_elasticity_tangent(), the
    /// kernel of assemble() (with a tension model it sets each point's
    /// model_tension, as an assembly at this u does). Throws where the
    /// formulation has terms it cannot hold (assembly.cc) and
    /// ExcInvertedElement collectively.
    /// With @p pressures (one per pressure part) the follower pressure on
    /// the boundary faces (MatrixFreeTangent::set_follower_pressure(); not
    /// for a loaded lid or Robin supports: throws).
    void
    update_matrix_free_tangent(MatrixFreeTangent            &tangent,
                               const dealii::Vector<double> &pressures,
                               const double                  active_tension);
    /// Throws unless the formulation suits update_matrix_free_tangent()
    /// (the penalty formulation; @p allow_mixed: or a mixed one, for
    /// MatrixFreeMixedSolver).
    void
    check_matrix_free_tangent(const bool allow_mixed = false) const;
    /// Whether Linear solver = matrix-free covers this problem at fixed
    /// cavity pressures (Q2 hexahedra, no pressure or a discontinuous one,
    /// quasi-static, no springs, no loaded lid, ...): what `auto` asks.
    bool
    matrix_free_applies() const;

    /// @p pressure on every pressure part.
    dealii::Vector<double>
    uniform_pressures(const double pressure) const;

    /// Newton's method for R(u; p) = 0 at fixed @p pressures (one per
    /// pressure part), or, with a @p target, for (u, p) with the cavity
    /// volume constraints V_i(u) = W_i(p) (p are then the Lagrange
    /// multipliers, updated in place).
    NewtonReport
    newton(dealii::Vector<double> &pressures,
           const double            active_tension,
           const VolumeTarget     *target);

    /// Cavity volumes at the current u (collective; not timed).
    dealii::Vector<double>
    cavity_volumes_now() const override;

    /// Solve tangent x = b (the tangent as last assembled) and distribute
    /// the constraints; wraps linear solver failures as Newton failures.
    /// An iterative solver stops at the relative residual @p tolerance if
    /// it is > 0 (Newton's forcing term), else at Linear solver tolerance.
    unsigned int
    linear_solve(LA::MPI::Vector       &x,
                 const LA::MPI::Vector &b,
                 const unsigned int     iteration,
                 const double           relative,
                 const double           tolerance = 0.0) override;

    Parameters                                            params;
    dealii::parallel::DistributedTriangulationBase<3, 3> &tria;
    MPI_Comm                                              comm;
    Logger                                               &logger;

    MaterialLaws       material;
    Discretization     discretization;
    BoundaryConditions boundaries;
    CavityLoads        loads;
    QuadraturePoints   points;
    LinearSystem       system;

    /// The sparse tangent (@p sparse_tangent: not for the matrix-free
    /// solvers) and the vectors of the solution and the system (after
    /// Discretization::distribute_dofs()).
    void
    reinit_system(const bool sparse_tangent);

    /// dst = K src with the tangent as last assembled (T K when augmented:
    /// then K src = T^-1 (T K src) = (T K src) - G (T K src)); with a
    /// matrix-free solver its operator's product.
    void
    tangent_vmult(LA::MPI::Vector &dst, const LA::MPI::Vector &src) const;
    /// Whether cavity @p i's pressure loads its lid (Parameters::
    /// lid_pressure, and the lid moves).
    bool
    lid_loaded(const unsigned int i) const
    {
      return params.lid_pressure && loads.moving_lid[i];
    }
    /// volume_rows from volume_derivatives and the moving lids (after an
    /// assembly with the volume derivatives; collective).
    void
    update_volume_rows();

    /// In assemble(), for every cavity whose lid is loaded: the lid's
    /// force on the rim vertices into the residual (@p lid_area: this
    /// rank's int cof(F) N dA of its wall) and, @p with_matrix, low_rank_u/v
    /// from @p lid_alpha (this rank's int da[phi] dA, compressed here).
    void
    add_lid_rim_terms(const dealii::Vector<double>                &pressures,
                      const std::vector<dealii::Tensor<1, 3>>     &lid_area,
                      std::vector<std::array<LA::MPI::Vector, 3>> &lid_alpha,
                      const bool                                   with_matrix);
    /// After linear_solver->setup(): the factorized low-rank data
    /// (collective; nothing without a low-rank part).
    void
    factorize_low_rank() override;

    LA::MPI::Vector u_owned; ///< owned
    LA::MPI::Vector u;       ///< ghosted copy of u_owned
    SolutionHistory history;

    /// (Re)creates linear_solver (no factorization held afterwards).
    void
    create_linear_solver(const bool symmetric);

    /// Elastodynamics (time_step > 0: the assembly adds the inertia).
    Dynamics dynamics;

    /// Sets @p value of every point of the locally owned cells to its entry
    /// of @p values (one vector per cell by active cell index, one value per
    /// point: the layout of Problem::quadrature_points()), or to 0 if
    /// @p values is empty and @p allow_empty. Errors name @p caller.
    void
    set_point_values(const std::vector<std::vector<double>> &values,
                     double PointData::*value,
                     const bool         allow_empty,
                     const std::string &caller);

    /// Calls @p f(active cell index, q, data, F, JxW) at every quadrature
    /// point of the locally owned cells, F of the current displacement.
    void
    for_each_point(const std::function<void(const unsigned int,
                                            const unsigned int,
                                            PointData &,
                                            const dealii::Tensor<2, 3> &,
                                            const double)> &f);

    /// Wall times of assembly and linear solves (sections "Mechanics /
    /// ..."), summed over the run.
    /// Sections: "Mechanics / Newton" (whole solves), "Mechanics /
    /// assembly", "Mechanics / linear solver", "Mechanics / cavity volume"
    /// (the latter three inside the first), and inside "Mechanics / linear
    /// solver" the preconditioner's or factorization's "Mechanics / linear
    /// solver set-up" of the Newton updates, inside "Mechanics / assembly"
    /// the matrix-free solvers' "Mechanics / matrix-free tangent update".
    std::ostringstream          timer_sink;
    mutable dealii::TimerOutput timer;

    /// Total wall time of a timer section so far [s] (0 before its first
    /// use).
    double
    seconds_in(const std::string &section) const override;

    /// The factorization the linear solver holds.
    Factorization factorized;

    /// Copy the per-point active tension (and the tension model's inputs)
    /// into factorized.tension (factorized.model_inputs), and in a time
    /// integration the accepted dynamic state and the time step into
    /// Dynamics::factorized_*.
    void
    remember_factorized_tension() override;

    /// The coefficients of the generalized-alpha method from the parameters
    /// and, on the first call, the mass matrix and the vectors of the
    /// dynamic state (zero). Collective.
    void
    setup_dynamics();

    /// This rank's int (-p (J - 1) - p^2 / (2 kappa)) dV of a mixed
    /// formulation [µJ] (strain_energy()'s volumetric part).
    double
    multiplier_energy() const;

    /// A checkpoint being written.
    CheckpointBuffers pending_checkpoint;

    /// After a checkpoint's data are read: the tangent of the factorized
    /// iterate assembled and factorized again (and for a @p bordered solve
    /// W0 = K^-1 B0), so that the resumed run reuses it as the original
    /// did.
    void
    rebuild_factorization(const bool bordered);

    /// What a checkpoint stores of a locally owned @p cell: the tension of
    /// the factorized iterate per point, the tension model's accepted state
    /// of every point (its states, the stretch, the tension), and the model
    /// inputs of the factorized iterate.
    std::vector<std::vector<double>>
    checkpoint_data_of(
      const dealii::Triangulation<3, 3>::cell_iterator &cell) const;

    // The rest of NewtonSystem (newton_system.h): views of the members.
    const Parameters &
    parameters() const override
    {
      return params;
    }
    const FieldLayout &
    layout() const override
    {
      return discretization.layout;
    }
    double
    body_volume() const override
    {
      return discretization.body_volume;
    }
    unsigned int
    n_cavities() const override
    {
      return loads.cavities.size();
    }
    const std::vector<std::string> &
    pressure_names() const override
    {
      return loads.pressure_names;
    }
    void
    reinit_vector(LA::MPI::Vector &v) const override
    {
      v.reinit(discretization.owned, comm);
    }
    dealii::ConditionalOStream &
    log() const override
    {
      return logger.detail();
    }
    dealii::TimerOutput &
    timers() const override
    {
      return timer;
    }
    const LA::MPI::Vector &
    iterate() const override
    {
      return u_owned;
    }
    void
    set_iterate(const LA::MPI::Vector &v) override
    {
      u_owned = v;
      u       = u_owned;
    }
    void
    add_to_iterate(const double a, const LA::MPI::Vector &du) override
    {
      u_owned.add(a, du);
      u = u_owned;
    }
    const SolutionHistory &
    solution_history() const override
    {
      return history;
    }
    LA::MPI::Vector &
    residual() override
    {
      return system.residual;
    }
    const std::vector<LA::MPI::Vector> &
    volume_derivatives() const override
    {
      return loads.volume_derivatives;
    }
    const std::vector<LA::MPI::Vector> &
    volume_rows() const override
    {
      return loads.volume_rows;
    }
    const LinearSolver &
    linear_solver() const override
    {
      return *system.linear_solver;
    }
    void
    setup_linear_solver() override
    {
      system.linear_solver->setup(system.tangent,
                                  system.pressure_matrix.get(),
                                  system.augmentation.get());
    }
    Factorization &
    factorization() override
    {
      return factorized;
    }
  };
} // namespace systole::Mechanics
