// Checkpoints of Monodomain: the interleaved ARKode state is split into one
// node vector per component (potential, each ionic state) plus the first
// and latest activation times, which travel with the cells of the mesh
// (SolutionTransfer), so a run can resume on another number of ranks.

#include "electrophysiology/monodomain_impl.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>

namespace systole::Electrophysiology
{
  namespace
  {
    template <class Archive>
    void
    serialize_statistics(Archive &archive, Statistics &stats)
    {
      archive &stats.steps &stats.linear_solves &stats.linear_iterations;
      archive &stats.amg_setups &stats.seconds;
    }

    /// Throws on a tetrahedral mesh: a fully distributed mesh reloads only
    /// on the ranks that saved it, and the mechanics on tetrahedra does not
    /// resume either.
    void
    require_hexahedra(const Geometry::CellKind &kind)
    {
      AssertThrow(!kind.simplex(),
                  dealii::ExcMessage(
                    "The electrophysiology on a tetrahedral mesh cannot be "
                    "checkpointed yet: set Output / Checkpoint interval = 0 "
                    "and Output / Checkpoint wall time interval = 0."));
    }
  } // namespace


  void
  Monodomain::prepare_checkpoint(boost::archive::text_oarchive &archive)
  {
    Impl &m = *impl;
    require_hexahedra(m.space.kind);
    const unsigned int           n = m.space.n_components + 2;
    std::vector<LA::MPI::Vector> owned(n);
    {
      const LocalRead y(m.state);
      for (unsigned int c = 0; c < n; ++c)
        {
          owned[c].reinit(m.space.owned, m.comm);
          const LocalWrite v(owned[c]);
          for (unsigned int i = 0; i < m.space.n_owned; ++i)
            v.data()[i] = c < m.space.n_components
                            ? y.data()[i * m.space.n_components + c]
                          : c == m.space.n_components ? m.tracker.first()[i]
                                                      : m.tracker.latest()[i];
        }
    }
    std::vector<const LA::MPI::Vector *> sources;
    for (const auto &v : owned)
      sources.push_back(&v);
    m.checkpoint.attach(m.space.dof_handler, m.space.relevant, sources);
    archive &m.t &m.matrices.gamma_stage &m.matrices.gamma_amg;
    serialize_statistics(archive, m.stats);
    // Whether the gates' opening Rush-Larsen half step is still to come.
    archive &m.gate_half_step_pending;
  }


  void
  Monodomain::load_checkpoint(boost::archive::text_iarchive &archive)
  {
    Impl &m = *impl;
    require_hexahedra(m.space.kind);
    double   gamma_stage = -1, gamma_amg = -1;
    archive &m.t &gamma_stage &gamma_amg;
    serialize_statistics(archive, m.stats);
    archive &m.gate_half_step_pending;

    const unsigned int                 n = m.space.n_components + 2;
    const std::vector<LA::MPI::Vector> out =
      read_attached_vectors(m.space.dof_handler, m.space.owned, n);
    std::vector<double> first(m.space.n_owned), latest(m.space.n_owned);
    {
      const LocalWrite y(m.state);
      for (unsigned int c = 0; c < n; ++c)
        {
          const LocalRead v(out[c]);
          for (unsigned int i = 0; i < m.space.n_owned; ++i)
            if (c < m.space.n_components)
              y.data()[i * m.space.n_components + c] = v.data()[i];
            else if (c == m.space.n_components)
              first[i] = v.data()[i];
            else
              latest[i] = v.data()[i];
        }
    }
    m.tracker.set(first, latest);
    m.extract_potential(m.v_sample);

    // The stage matrix and its preconditioner as they were: the AMG
    // hierarchy of gamma_amg (it is kept while gamma stays within 20 %), the
    // stage matrix of gamma_stage.
    const Statistics counters = m.stats;
    m.matrices.preconditioner.reset();
    m.matrices.gamma_stage = m.matrices.gamma_amg = -1;
    if (gamma_amg > 0)
      m.prepare_stage(gamma_amg);
    if (gamma_stage > 0)
      m.prepare_stage(gamma_stage);
    m.stats = counters;

    // ARKode restarts at the checkpoint's time (its steps are one-step
    // methods: the state is all it needs).
    m.steps_before = m.stats.steps;
    m.integrator   = m.create_integrator(m.t);
    m.update_output_vectors();
    save();
  }


  void
  Monodomain::finish_checkpoint()
  {
    impl->checkpoint.clear();
  }
} // namespace systole::Electrophysiology
