#pragma once

// Internal to src/electrophysiology: the state of Monodomain, shared by its
// translation units (monodomain.cc, assembly.cc, time_stepping.cc). Not
// included elsewhere.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "base/attached_vectors.h"
#include "base/linear_algebra.h"
#include "base/logger.h"
#include "electrophysiology/activation.h"
#include "electrophysiology/arkode_adapter.h"
#include "electrophysiology/ecg.h"
#include "electrophysiology/eikonal.h"
#include "electrophysiology/monodomain.h"
#include "geometry/cell_kind.h"

#include <memory>
#include <optional>
#include <vector>

namespace systole::Electrophysiology
{
  /// Read access to the locally owned entries of a PETSc vector.
  class LocalRead
  {
  public:
    explicit LocalRead(const LA::MPI::Vector &v);
    ~LocalRead();
    const double *
    data() const
    {
      return values;
    }

  private:
    Vec           vec;
    const double *values = nullptr;
  };

  /// Write access to the locally owned entries of a PETSc vector (no
  /// compress() needed; a ghosted vector needs VecGhostUpdateBegin/End
  /// after, as in update_output_vectors(): deal.II 9.4's
  /// update_ghost_values() does nothing for PETSc vectors).
  class LocalWrite
  {
  public:
    explicit LocalWrite(LA::MPI::Vector &v);
    ~LocalWrite();
    double *
    data() const
    {
      return values;
    }

  private:
    Vec     vec;
    double *values = nullptr;
  };


  struct Monodomain::Impl
  {
    Impl(const Parameters                                           &params,
         const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
         const dealii::Mapping<3, 3>                                &mapping,
         Logger                                                     &logger,
         const double start_time);

    // --- monodomain.cc (the set-up of the constructor) ---
    /// The nodes (owned, relevant, ghosts) and the index set of the ARKode
    /// state; stops on a mesh with hanging nodes.
    void
    distribute_nodes();
    /// The sparse matrices and work vectors of the nodes, and the mass.
    void
    setup_matrices();
    /// The lead field of the ECG's electrodes (Parameters::ecg).
    void
    setup_lead_field(const Fibres::FibreField &fibres);
    /// The model, discretization and (eikonal) activation on the log.
    void
    log_setup() const;

    // --- assembly.cc ---
    /// Lumped (nodal quadrature) mass of the owned nodes and their
    /// positions.
    void
    assemble_lumped_mass();
    /// The consistent mass matrix M_ij = ∫ φ_i φ_j (Gauss points) and its
    /// Jacobi preconditioner (Mass matrix = consistent).
    void
    assemble_consistent_mass();
    /// x = M^-1 b with the mass of the stage systems (the lumped or the
    /// consistent one; CG + Jacobi for the latter, from the guess in @p x).
    void
    solve_mass(const LA::MPI::Vector &b, LA::MPI::Vector &x);
    /// Fibre directions at the points of diffusion_quadrature, per owned
    /// cell.
    void
    evaluate_fibres(const Fibres::FibreField &fibres);
    /// Stiffness K_ij = ∫ ∇φ_i · D ∇φ_j with D from the fibres (and the
    /// deformation, if given); invalidates the stage matrix and AMG.
    void
    assemble_stiffness(
      const std::vector<std::vector<dealii::Tensor<2, 3>>> *deformation);
    /// For each stimulus, the owned nodes in its region.
    void
    locate_stimuli(const Geometry::BoundaryNames &names);

    // --- reaction_eikonal.cc (Model = reaction-eikonal or eikonal) ---
    /// Solve the eikonal equation from the stimuli (each stimulus's nodes
    /// start at its start time plus the cell's stimulus latency) and set up
    /// the nodal stimulus of the reaction-eikonal model (which replaces the
    /// stimuli: stimulation.nodes are emptied).
    void
    setup_eikonal(const Fibres::FibreField      &fibres,
                  const Geometry::BoundaryNames &names);
    /// Grow the Purkinje tree (Parameters::purkinje) into #purkinje and
    /// activate it from the His entry at @p his_time [ms].
    void
    grow_purkinje(const Geometry::BoundaryNames &names, const double his_time);
    /// Model = monodomain: replace the stimuli by the junctions' (before
    /// locate_stimuli()).
    void
    setup_purkinje_stimuli(const Geometry::BoundaryNames &names);
    /// Reaction-eikonal: the nodal stimulus rates of the step [@p t0,
    /// @p t1] (the charge of each node's window inside it, spread evenly).
    void
    eikonal_step_stimulus(const double t0, const double t1);
    /// Reaction-eikonal: the times in (@p t0, @p t1) at which steps end so
    /// that steps are at most a quarter of the stimulus long while nodes
    /// are being stimulated.
    std::vector<double>
    eikonal_breakpoints(const double t0, const double t1) const;
    /// Model = eikonal: the activation times and the square-wave potential
    /// at @p t_end.
    void
    advance_eikonal_only(const double t_end);

    /// The eikonal activation (Model = eikonal or reaction-eikonal).
    struct EikonalActivation
    {
      /// Activation time of the first beat at the owned nodes [ms] (+inf:
      /// not reached).
      std::vector<double> times;
      /// Reaction-eikonal: the nodal stimulus onsets T - latency in
      /// ascending order and their nodes; its duration and dv/dt.
      std::vector<double>       onsets;
      std::vector<unsigned int> onset_nodes;
      double                    duration = 0, rate = 0;
      /// The onset time's span over all ranks (first, last) [ms].
      double first_onset = 0, last_onset = 0;
      /// Nodes stimulated during the current step and their dv/dt.
      std::vector<std::pair<unsigned int, double>> stimulus;
      EikonalStatistics                            statistics;
    } eikonal;
    /// The Purkinje network (Parameters::purkinje; empty when off).
    PurkinjeNetwork purkinje;

    /// Whether the potential diffuses (not with RE-).
    bool
    diffusion() const
    {
      return params.model != Parameters::Model::reaction_eikonal ||
             params.reaction_eikonal_diffusion;
    }

    // --- time_stepping.cc ---
    /// The ImexIntegrator's callbacks on the interleaved state.
    void
    explicit_rhs(const double t, const LA::MPI::Vector &y, LA::MPI::Vector &f);
    void
    implicit_rhs(const LA::MPI::Vector &y, LA::MPI::Vector &f);
    void
    solve_stage(const double           gamma,
                const LA::MPI::Vector &b,
                LA::MPI::Vector       &x);
    /// The stiffness of the explicit part at @p y: the largest dI_ion/dv
    /// over the nodes [1/ms] (0 if none is positive). Collective.
    double
    explicit_stiffness(const LA::MPI::Vector &y) const;
    /// One step (one ImexIntegrator::evolve) from t to @p t_next, with the
    /// stimuli switched as at the step's midpoint; samples the activation
    /// (@p v_new is scratch space).
    void
    step(const double t_next, std::vector<double> &v_new);
    /// The resting state, interleaved.
    void
    initialize_state();
    /// Copy the potential of the state into @p v (owned nodes).
    void
    extract_potential(std::vector<double> &v) const;
    /// Refresh the ghosted output vectors from the state and the tracker.
    void
    update_output_vectors();
    std::unique_ptr<ImexIntegrator>
    create_integrator(const double t0);

    Parameters                                                  params;
    const IonicModel                                           &model;
    const dealii::parallel::DistributedTriangulationBase<3, 3> &tria;
    const dealii::Mapping<3, 3>                                &mapping;
    MPI_Comm                                                    comm;
    Logger                                                     &logger;

    /// The finite element space of the potential: element, nodes, their
    /// index sets and positions, and the fibres at the quadrature points.
    struct FESpace
    {
      FESpace(const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
              const unsigned int degree,
              const unsigned int n_components);

      /// Hexahedra or tetrahedra: the element, the rules.
      Geometry::CellKind                           kind;
      std::unique_ptr<dealii::FiniteElement<3, 3>> fe;
      dealii::DoFHandler<3>                        dof_handler;
      dealii::Quadrature<3> quadrature; ///< of the stiffness
      dealii::IndexSet      owned, relevant;
      /// Relevant but not owned nodes (the ghosts, in local-form order).
      dealii::IndexSet ghosts;
      dealii::IndexSet state_owned;  ///< interleaved layout
      unsigned int     n_owned = 0;  ///< owned nodes
      unsigned int     n_components; ///< 1 + model.n_states()
      /// Positions [mm] of the owned nodes.
      std::vector<dealii::Point<3>> node_positions;
      /// Fibre direction per owned cell (active_cell_index) and point.
      std::vector<std::vector<dealii::Tensor<1, 3>>> fibre_directions;

      /// Position of the locally relevant node @p dof in the local form
      /// (owned nodes, then ghosts).
      unsigned int
      local_index(const dealii::types::global_dof_index dof) const
      {
        return owned.is_element(dof) ? owned.index_within_set(dof)
                                     : n_owned + ghosts.index_within_set(dof);
      }
    } space;

    /// The matrices of the diffusion, the solvers of the mass and stage
    /// systems and their work vectors.
    struct Matrices
    {
      /// Lumped mass [mm³] of the owned nodes.
      std::vector<double> lumped_mass;
      LA::MPI::Vector     lumped_mass_vector; ///< owned

      LA::MPI::SparseMatrix stiffness;  ///< K
      LA::MPI::SparseMatrix stage;      ///< M + gamma_stage K
      LA::MPI::SparseMatrix amg_matrix; ///< M + gamma_amg K
      /// The consistent mass (Mass matrix = consistent; empty otherwise: M
      /// is then M_L) and its Jacobi preconditioner.
      LA::MPI::SparseMatrix                                      mass;
      std::unique_ptr<dealii::PETScWrappers::PreconditionJacobi> mass_jacobi;
      /// M^-1 K v of the last implicit_rhs(): the guess of the next one.
      LA::MPI::Vector MinvKv_work;
      double          gamma_stage = -1, gamma_amg = -1;
      /// BoomerAMG of amg_matrix, or Jacobi of stage.
      std::unique_ptr<dealii::PETScWrappers::PreconditionBase> preconditioner;

      LA::MPI::Vector v_work, Kv_work, rhs_work; ///< owned, node layout
    } matrices;

    /// v_local = model units; activation threshold in model units.
    double threshold;

    /// The stimuli of Parameters::stimuli.
    struct Stimulation
    {
      /// dv/dt of a unit stimulus current density: 1/(χ C_m A).
      double scale;
      /// Owned nodes of each stimulus.
      std::vector<std::vector<unsigned int>> nodes;
      /// Whether each stimulus is on during the current step.
      std::vector<bool> on;
    } stimulation;

    LA::MPI::Vector                 state; ///< interleaved layout
    double                          t;
    std::unique_ptr<ImexIntegrator> integrator;
    ActivationTracker               tracker;
    std::vector<double>             v_sample; ///< v at time t, owned nodes

    /// The first step starts with a Rush-Larsen half step of the gates
    /// (the opening half of Strang's splitting, see create_integrator()).
    bool gate_half_step_pending = true;

    struct Saved
    {
      LA::MPI::Vector     state;
      double              t = 0;
      std::vector<double> first, latest, v_sample;
      bool                gate_half_step_pending = true;
    } saved;

    /// What evaluate() and values_at_points() read.
    struct Outputs
    {
      /// The four vectors below at the locally relevant nodes, interleaved
      /// (potential, first, latest, calcium), in the order of PETSc's local
      /// form (owned nodes, then ghosts; FESpace::local_index()): cheaper
      /// than a PETSc access per node.
      std::vector<double> values;

      /// Ghosted, node layout: potential [mV], first and latest activation
      /// (NaN where none), calcium [µM] (NaN without calcium); the first
      /// activation as the field output writes it (not_activated_time where
      /// none).
      LA::MPI::Vector potential_mV, activation_first, activation_latest,
        calcium_uM, activation_field;

      /// values_at_points(): the cells around the last points asked for.
      struct PointCache
      {
        std::vector<dealii::Point<3>> points;
        std::vector<unsigned int>     owner; ///< evaluating rank per point
        std::vector<std::pair<dealii::DoFHandler<3>::active_cell_iterator,
                              dealii::Point<3>>>
          cells; ///< cell and reference point (on the owner)
      } mutable point_cache;
    } outputs;

    /// The pseudo-ECG's lead field (Parameters::ecg enabled; null
    /// otherwise).
    std::unique_ptr<LeadField> lead_field;

    Statistics stats;
    /// ARKode steps before the integrator was last created (a restart).
    unsigned long steps_before = 0;

    /// A checkpoint being written: the node vectors.
    AttachedVectors checkpoint;

    /// The stage matrix M_L + gamma K and its preconditioner for @p gamma
    /// (kept when gamma changes little; see solve_stage()).
    void
    prepare_stage(const double gamma);

    /// values_at_points() on tetrahedra: fill outputs.point_cache's owners and
    /// cells for @p points (collective).
    void
    locate_on_tetrahedra(const std::vector<dealii::Point<3>> &points) const;
  };
} // namespace systole::Electrophysiology
