#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/tria.h>
#include <deal.II/numerics/data_out.h>

#include "base/archive_fwd.h"
#include "electrophysiology/activation.h"
#include "electrophysiology/parameters.h"
#include "fibres/fibre_field.h"
#include "geometry/boundary_names.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
}

namespace systole::Electrophysiology
{
  /// Counters of the EP time integration since construction.
  struct Statistics
  {
    unsigned long steps             = 0; ///< ARKode steps
    unsigned long linear_solves     = 0; ///< implicit stage systems solved
    unsigned long linear_iterations = 0; ///< CG iterations, summed
    unsigned long amg_setups        = 0; ///< BoomerAMG set-ups
    /// Solves with the consistent mass (one per evaluation of the diffusion
    /// term) and their CG iterations, summed; 0 with the lumped mass.
    unsigned long mass_solves = 0, mass_iterations = 0;
    double        seconds = 0; ///< wall time spent in advance() [s]
  };

  /// EP values at a set of points.
  struct PointValues
  {
    std::vector<double> potential; ///< transmembrane potential [mV]
    /// First upstroke [ms]; NaN if not (yet) activated.
    std::vector<double> activation_time;
    /// Most recent upstroke [ms] (the current beat); NaN if none.
    std::vector<double> latest_activation_time;
    /// Free cytosolic calcium [µM] (IonicModel::calcium_uM(), the input of
    /// a calcium-driven tension model); NaN for a model without calcium.
    std::vector<double> calcium_uM;
  };

  /// The monodomain model of cardiac electrophysiology on a distributed mesh,
  /// @f[ \chi\Big(C_m \frac{\partial V}{\partial t} + I_{ion}\Big)
  ///     = \nabla\cdot(\sigma\nabla V) + I_{stim},\qquad
  ///     \sigma = \sigma_t I + (\sigma_l - \sigma_t) f_0\otimes f_0, @f]
  /// with insulated boundaries, in the ionic model's potential units
  /// (IonicModel): dv/dt = ∇·(D∇v) − I_ion(v, s) + I_stim/(χ C_m A),
  /// D = σ/(χ C_m) [mm²/ms].
  ///
  /// Discretization: continuous Q1 or Q2 elements on hexahedra, P1 on
  /// tetrahedra (Geometry::CellKind picks elements, quadratures and the
  /// nodal rule), on the given mesh (its own DoFHandler), a lumped (nodal
  /// quadrature: Gauss-Lobatto on hexahedra, the vertices on tetrahedra)
  /// mass M = M_L or (Mass matrix = consistent) the consistent one, the ionic
  /// model evaluated at the nodes (so the ODE system is M dv/dt = −K v + M f(v,
  /// s)). The state of ARKode holds v and the model's state variables at every
  /// node (interleaved per node); the IMEX ARK method treats −M⁻¹K v implicitly
  /// (linear, time independent; a CG + Jacobi solve with a consistent M) and
  /// the ionic currents, the state ODEs and the stimulus explicitly. Stage
  /// systems (M + γK) x = M b are solved by CG + BoomerAMG; the preconditioner
  /// is rebuilt only when γ changes by more than 20 % (never with fixed steps).
  /// Activation times are sampled every Parameters::time_step
  /// (ActivationTracker).
  ///
  /// The mesh must be conforming (no hanging nodes). Cheap to include
  /// (pimpl).
  class Monodomain
  {
  public:
    /// @param[in] tria the mesh, e.g. the one of the mechanics (kept by
    ///            reference, must outlive this object and not change): a
    ///            p4est mesh of hexahedra or a fully distributed one of
    ///            tetrahedra (degree 1 only)
    /// @param[in] mapping geometry of its cells (kept by reference)
    /// @param[in] fibres fibre field, evaluated once at the quadrature points
    ///            of every locally owned cell
    /// @param[in] names boundary parts of @p tria (surface stimuli)
    /// @param[in] start_time initial time [ms]; the tissue starts at rest
    Monodomain(const Parameters &params,
               const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
               const dealii::Mapping<3, 3>   &mapping,
               const Fibres::FibreField      &fibres,
               const Geometry::BoundaryNames &names,
               Logger                        &logger,
               const double                   start_time = 0.0);
    ~Monodomain();

    /// Integrate to @p t_end [ms] (> time()), sub-cycling with steps of at
    /// most Parameters::time_step (equal steps that end exactly at t_end),
    /// and update the activation times. Collective. Throws
    /// ExcRecoverableStepFailure (on every rank) if a stage solve fails;
    /// restore() then.
    void
    advance(const double t_end);

    /// Current time [ms].
    double
    time() const;

    /// Potential, activation times and calcium at the points @p quadrature (in
    /// reference-cell coordinates, e.g. the mechanics' quadrature rule) of
    /// @p cell, a locally owned (or ghost) cell of the triangulation given
    /// to the constructor. The activation times are the Q1/Q2 interpolants
    /// of the nodal ones: NaN until every node of the cell has activated
    /// (the cell is then active within one cell-crossing time of the front).
    /// With a Stimulus period, the latest activation time is also NaN while
    /// the cell's nodes hold upstrokes more than half a period apart (the
    /// current beat's wave is crossing the cell).
    /// Not collective; cheap (no mapping, one vector read per cell).
    void
    evaluate(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
             const dealii::Quadrature<3> &quadrature,
             PointValues                 &values) const;

    /// The shape functions of the element at the reference points
    /// @p reference: n_dofs_per_cell values per point (for the evaluate()
    /// below).
    std::vector<double>
    shape_values(const std::vector<dealii::Point<3>> &reference) const;

    /// evaluate() at the points whose shape_values() are @p shape_values:
    /// the same values, without evaluating the polynomials again (points
    /// read at every step). Not collective.
    void
    evaluate(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
             const std::vector<double> &shape_values,
             PointValues               &values) const;

    /// Values at reference points anywhere in the mesh, on every rank (NaN
    /// for a point outside the mesh). Collective.
    PointValues
    values_at_points(const std::vector<dealii::Point<3>> &points) const;

    /// Whether the pseudo-ECG is computed (Parameters::ecg.enabled).
    bool
    has_ecg() const;

    /// The pseudo-ECG potential [mV] at the electrodes of Parameters::ecg
    /// (the order of electrode_names()) at time(): one dot product of the
    /// nodal potential with each electrode's lead field (LeadField,
    /// assembled once on the reference mesh with the conductivity of the
    /// potential equation). Empty without the ECG. Collective.
    std::vector<double>
    electrode_potentials() const;

    /// The 12 leads [mV] (lead_names()) at time(). Throws without the ECG.
    /// Collective.
    std::array<double, 12>
    ecg_leads() const;

    /// Volume fraction of the mesh activated so far (first upstroke
    /// recorded) [-]. Collective.
    double
    activated_fraction() const;

    /// Activated volume fraction, first/last/total activation time and the
    /// time by which @p fraction of the volume is active, of the first
    /// upstrokes (the activation map of the run) or, with @p latest, of the
    /// most recent ones (the current beat). Collective.
    ActivationSummary
    activation_summary(const double fraction = 0.9,
                       const bool   latest   = false) const;

    /// Pull the conductivity back through the deformation: σ_0 = J F⁻¹ σ(f)
    /// F⁻ᵀ, f = F f_0/|F f_0|, and reassemble the stiffness. @p F holds, per
    /// locally owned cell (indexed by active_cell_index), either one
    /// deformation gradient (used at all points) or one per point of
    /// diffusion_quadrature(); empty entries mean F = I. A no-op unless
    /// Parameters::pull_back. Collective. (A hook for coupled problems; the
    /// heartbeat does not call it yet.)
    void
    set_deformation_gradients(
      const std::vector<std::vector<dealii::Tensor<2, 3>>> &F);

    /// Quadrature rule of the stiffness matrix (reference cell).
    const dealii::Quadrature<3> &
    diffusion_quadrature() const;

    /// Remember the current state (potential, states, activation times);
    /// restore() returns to it.
    void
    save();

    /// Checkpoint, part 1 (before the triangulation's save()): attach the
    /// potential, the ionic states and the first and latest activation of
    /// every node to the cells (SolutionTransfer, so that a restart may use
    /// another number of ranks), and write the time, the counters and the
    /// stage-solver set-up (the gamma of the stage matrix and of its AMG) to
    /// @p archive. Hexahedral meshes only: throws on tetrahedra.
    void
    prepare_checkpoint(boost::archive::text_oarchive &archive);

    /// Checkpoint, part 2 (on a mesh loaded from the checkpoint): read the
    /// state back, set the stage matrix and its preconditioner up as they
    /// were, and restart ARKode at the checkpoint's time. Collective.
    void
    load_checkpoint(boost::archive::text_iarchive &archive);

    /// After the triangulation's save(): release the attached vectors.
    void
    finish_checkpoint();

    /// Return to the state of the last save() (or the initial state).
    void
    restore();

    /// Add the potential [mV] ("transmembrane_potential"), the first
    /// activation time [ms] ("activation_time", not_activated_time = -1 where
    /// none yet) and, for
    /// a model with calcium, the calcium [µM] ("calcium") to
    /// @p data_out, through this object's DoFHandler (so the DataOut may
    /// carry other DoFHandlers on the same mesh too). Call before
    /// build_patches.
    void
    attach_output(dealii::DataOut<3, 3> &data_out) const;

    /// Number of nodes (potential DoFs).
    dealii::types::global_dof_index
    n_dofs() const;

    /// Counters of the time integration.
    Statistics
    statistics() const;

    const IonicModel &
    ionic_model() const;

    /// The Purkinje network that activated the eikonal models (empty
    /// without one: Parameters::purkinje).
    const PurkinjeNetwork &
    purkinje() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Electrophysiology
