#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/numerics/data_out.h>

#include "base/archive_fwd.h"
#include "electrophysiology/activation.h"
#include "electrophysiology/monodomain.h"
#include "io/results_file.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
  struct RunParameters;

  namespace Geometry
  {
    struct Parameters;
    struct DistributedMesh;
  } // namespace Geometry
  namespace Mechanics
  {
    class Problem;
  }

  /// What create_monodomain() builds a monodomain model from.
  struct MonodomainInputs
  {
    /// the Fibres subsection (read relative to run.parameter_directory)
    const dealii::ParameterHandler      &prm;
    const RunParameters                 &run;
    const Electrophysiology::Parameters &params;
    /// the Geometry subsection @p mesh was built from
    const Geometry::Parameters      &geometry;
    const Geometry::DistributedMesh &mesh;
    const dealii::Mapping<3, 3>     &mapping;
    Logger                          &logger;
    /// [ms]
    double start_time;
  };

  /// The monodomain model of @p in.params on @p in.mesh (with its mapping),
  /// with its own fibre field: the Fibres generator of @p in.prm run on that
  /// mesh (the rule-based one solves its Laplace problems there). The model
  /// starts at @p in.start_time.
  std::unique_ptr<Electrophysiology::Monodomain>
  create_monodomain(const MonodomainInputs &in);

  /// The electrical activation of an electromechanical heartbeat: the
  /// monodomain model (subsection Electrophysiology) on its own mesh, the
  /// mechanics mesh refined Electrophysiology / Mesh refinement times, with
  /// its own fibre field on that mesh (the Fibres generator run there), read
  /// at the quadrature points of the mechanics.
  ///
  /// The coupling is one way: the potential does not depend on the
  /// deformation, so EP only ever advances, on its own grid of times (the
  /// multiples of Electrophysiology / Time step, whatever the mechanics'
  /// steps). After each of those steps the potential is interpolated at the
  /// mechanics quadrature points; a point's upstroke is the crossing of the
  /// activation threshold, located linearly in time between two samples
  /// (the potential is continuous, so this does not depend on which EP cell
  /// holds a point on a cell face, nor on the partition). Every point keeps
  /// its upstrokes (one per beat). A mechanics solve at time t (a stage of
  /// the circulation integrator, which may be rejected and retried shorter)
  /// uses the latest upstroke at or before t, so EP never has to go back.
  ///
  /// The mechanics points are located in the EP mesh once (Utilities::MPI::
  /// RemotePointEvaluation: the two meshes may be partitioned differently).
  ///
  /// Hexahedral meshes (p4est) and tetrahedral ones (fully distributed; the
  /// EP mesh refined by splitting each tetrahedron into 8, P1 elements) alike;
  /// checkpoints only on hexahedra.
  class ElectricalActivation
  {
  public:
    /// What the electrical activation is built from (its constructor and
    /// its Impl's take it whole).
    struct Inputs
    {
      const dealii::ParameterHandler &prm;
      const RunParameters            &run;
      /// the Geometry subsection the mechanics mesh was built from (the EP
      /// mesh is built the same way, refined)
      const Geometry::Parameters &geometry;
      /// the mechanics (kept by reference)
      const dealii::parallel::DistributedTriangulationBase<3, 3>
                               &mechanics_tria;
      const Mechanics::Problem &problem;
      /// beat period [ms]: the Stimulus period (0 there is taken as this
      /// period; another value is an error)
      double   period;
      Logger  &logger;
      MPI_Comm comm;
      /// a checkpoint folder to resume from ("": none): the EP mesh is then
      /// loaded from it (load_checkpoint() reads the rest)
      const std::string &checkpoint;
    };

    /// Throws on a tetrahedral mesh when Inputs::run asks for checkpoints
    /// (Output / Checkpoint interval or wall time interval).
    explicit ElectricalActivation(const Inputs &in);
    ~ElectricalActivation();

    /// Whether save_checkpoint() can be called (hexahedral meshes).
    bool
    checkpointable() const;

    /// Checkpoint: save the EP mesh with the monodomain state to
    /// @p folder/ep.mesh*, attach the upstrokes and samples of every
    /// mechanics quadrature point to the mechanics cells (written by the
    /// mechanics triangulation's next save()), and the rest to @p archive.
    void
    save_checkpoint(boost::archive::text_oarchive &archive,
                    const std::string             &folder);

    /// Read what save_checkpoint() wrote (after the mechanics mesh was
    /// loaded and Mechanics::Problem::load_checkpoint() read its cell data).
    void
    load_checkpoint(boost::archive::text_iarchive &archive);

    /// Advance EP (if needed), one EP time step at a time, to the first
    /// multiple of the EP time step at or after @p t [ms], recording the new
    /// upstrokes at the mechanics points. Collective.
    void
    advance_to(const double t);

    /// The latest upstroke at or before @p t [ms] of every mechanics
    /// quadrature point (the layout of Mechanics::Problem::
    /// quadrature_points()), NaN where none. @p t must not lie after time().
    void
    activation_times(const double                      t,
                     std::vector<std::vector<double>> &times) const;

    /// Time EP has reached [ms].
    double
    time() const;

    /// Keep the intracellular calcium at the mechanics points at every
    /// sample from now on (the input of a calcium-driven tension model).
    /// Throws if the ionic model has no calcium. Collective.
    void
    keep_calcium();

    /// The calcium [µM] of every mechanics quadrature point (the layout of
    /// activation_times()) at @p t [ms], linear in time between the kept
    /// samples: EP may have run ahead of a rejected step, and a shorter
    /// retry reads the calcium of its own time. @p t must lie between the
    /// oldest kept sample (forget_calcium_before()) and time().
    void
    calcium(const double t, std::vector<std::vector<double>> &calcium) const;

    /// Drop the calcium samples no longer needed for times at or after
    /// @p t [ms] (an accepted mechanics time: no step starts before it).
    void
    forget_calcium_before(const double t);

    /// Earliest onset of any stimulus [ms]: no point activates before.
    double
    earliest_stimulus() const;

    /// Add the fields "transmembrane_potential" [mV], "activation_time" (the
    /// first upstroke, the activation map of the run) and
    /// "latest_activation_time" [ms] (-1, Electrophysiology::
    /// not_activated_time, where none) on the mechanics mesh
    /// (interpolated from EP at the nodes of a Q(degree), on tetrahedra
    /// P(degree), field) to
    /// @p data_out, at time() (which may lie up to one step of the
    /// circulation integrator ahead of the mechanics). Collective; call
    /// before build_patches().
    void
    attach_output(dealii::DataOut<3, 3> &data_out);

    /// The Purkinje network of the eikonal models (empty without one).
    const Electrophysiology::PurkinjeNetwork &
    purkinje() const;

    /// Volume fraction of the EP mesh activated at least once [-].
    /// Collective.
    double
    activated_fraction() const;

    /// Whether the pseudo-ECG is computed (Electrophysiology / ECG).
    bool
    has_ecg() const;

    /// The 12 leads of the pseudo-ECG [mV] (Electrophysiology::lead_names())
    /// at @p t [ms], linear in time between the samples of the EP steps
    /// around it (EP may be ahead of the mechanics). @p t must not lie
    /// after time() nor before the last append_ecg_biomarkers()' end.
    std::array<double, 12>
    ecg_leads(const double t) const;

    /// Append the ECG biomarkers of the beat [@p start, @p end] [ms] (from
    /// the samples of every EP step; EcgBeat::append_biomarkers()) to the
    /// /summary row @p row and forget the samples before @p end.
    void
    append_ecg_biomarkers(const double             start,
                          const double             end,
                          std::vector<IO::Column> &row);

    /// Summary of the latest upstrokes (the current beat). Collective.
    Electrophysiology::ActivationSummary
    beat_summary() const;

    /// Counters of the EP time integration.
    Electrophysiology::Statistics
    statistics() const;

    /// Nodes (DoFs) of the EP mesh.
    unsigned long long
    n_nodes() const;

    /// Wall time spent reading EP at the mechanics points [s].
    double
    transfer_seconds() const;

    /// One line for the log: the EP mesh, nodes, stimulus period, the
    /// number of mechanics points read. Collective.
    std::string
    description() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole
