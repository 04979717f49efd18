#include "electrophysiology/monodomain.h"

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/data_out.h>

#include "electrophysiology/monodomain_impl.h"
#include "geometry/point_location.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole::Electrophysiology
{
  namespace
  {
    /// The Lagrange element of @p degree on cells of @p kind; P1 only on
    /// tetrahedra.
    std::unique_ptr<dealii::FiniteElement<3, 3>>
    element(const Geometry::CellKind &kind, const unsigned int degree)
    {
      AssertThrow(!kind.simplex() || degree == 1,
                  dealii::ExcMessage(
                    "Electrophysiology / Polynomial degree = " +
                    std::to_string(degree) +
                    " needs hexahedra: on tetrahedra the lumped mass of P2 "
                    "gives the vertices zero weight. Set it to 1."));
      return kind.lagrange(degree);
    }
  } // namespace


  Monodomain::Impl::FESpace::FESpace(
    const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
    const unsigned int                                          degree,
    const unsigned int                                          n_components)
    : kind(tria)
    , fe(element(kind, degree))
    , dof_handler(tria)
    , quadrature(kind.cell_quadrature(degree + 1))
    , n_components(n_components)
  {}


  Monodomain::Impl::Impl(
    const Parameters                                           &params,
    const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
    const dealii::Mapping<3, 3>                                &mapping,
    Logger                                                     &logger,
    const double                                                start_time)
    : params(params)
    , model(*params.ionic_model)
    , tria(tria)
    , mapping(mapping)
    , comm(tria.get_communicator())
    , logger(logger)
    , space(tria, params.degree, 1 + params.ionic_model->n_states())
    , threshold(params.ionic_model->from_mV(params.activation_threshold_mV))
    , stimulation{1.0 / (params.chi * params.C_m *
                         params.ionic_model->potential_scale_mV()),
                  {},
                  {}}
    , t(start_time)
    , tracker(0, threshold)
  {}


  void
  Monodomain::Impl::distribute_nodes()
  {
    space.dof_handler.distribute_dofs(*space.fe);
    space.owned = space.dof_handler.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(space.dof_handler,
                                                    space.relevant);
    space.n_owned = space.owned.n_elements();
    space.ghosts  = space.relevant;
    space.ghosts.subtract_set(space.owned);
    AssertThrow(space.owned.is_contiguous(), dealii::ExcInternalError());
    {
      dealii::AffineConstraints<double> hanging(space.relevant);
      dealii::DoFTools::make_hanging_node_constraints(space.dof_handler,
                                                      hanging);
      AssertThrow(dealii::Utilities::MPI::max(hanging.n_constraints(), comm) ==
                    0,
                  dealii::ExcMessage(
                    "Electrophysiology needs a conforming mesh (no hanging "
                    "nodes): refine it globally."));
    }

    // The ARKode state: v and the model's states of every owned node,
    // interleaved, in the same rank order as the nodes.
    const auto n_global   = space.dof_handler.n_dofs() * space.n_components;
    const auto first_node = space.n_owned > 0 ? *space.owned.begin() : 0;
    space.state_owned     = dealii::IndexSet(n_global);
    space.state_owned.add_range(first_node * space.n_components,
                                (first_node + space.n_owned) *
                                  space.n_components);
  }


  void
  Monodomain::Impl::setup_matrices()
  {
    dealii::DynamicSparsityPattern dsp(space.relevant);
    dealii::DoFTools::make_sparsity_pattern(space.dof_handler, dsp);
    dealii::SparsityTools::distribute_sparsity_pattern(dsp,
                                                       space.owned,
                                                       comm,
                                                       space.relevant);
    matrices.stiffness.reinit(space.owned, space.owned, dsp, comm);
    matrices.stage.reinit(space.owned, space.owned, dsp, comm);
    matrices.amg_matrix.reinit(space.owned, space.owned, dsp, comm);
    matrices.v_work.reinit(space.owned, comm);
    matrices.Kv_work.reinit(space.owned, comm);
    matrices.rhs_work.reinit(space.owned, comm);
    outputs.potential_mV.reinit(space.owned, space.relevant, comm);
    outputs.activation_first.reinit(space.owned, space.relevant, comm);
    outputs.activation_latest.reinit(space.owned, space.relevant, comm);
    outputs.activation_field.reinit(space.owned, space.relevant, comm);
    outputs.calcium_uM.reinit(space.owned, space.relevant, comm);

    assemble_lumped_mass();
    if (params.consistent_mass)
      {
        matrices.mass.reinit(space.owned, space.owned, dsp, comm);
        assemble_consistent_mass();
      }
  }


  void
  Monodomain::Impl::setup_lead_field(const Fibres::FibreField &fibres)
  {
    std::vector<dealii::Point<3>> electrodes;
    for (const auto &e : params.ecg.electrodes)
      electrodes.push_back(e.position);
    AssertThrow(electrodes.size() == electrode_names().size(),
                dealii::ExcMessage("Electrophysiology / ECG electrodes: "
                                   "the 12 leads need nine electrodes."));
    // One Gauss point more than the stiffness: 1/r varies over the
    // cells of a coarse mesh near an electrode.
    lead_field =
      std::make_unique<LeadField>(space.dof_handler,
                                  mapping,
                                  space.kind.cell_quadrature(params.degree + 2),
                                  fibres,
                                  params.sigma_l,
                                  params.sigma_t,
                                  electrodes,
                                  params.ecg.bath_conductivity);
  }


  void
  Monodomain::Impl::log_setup() const
  {
    std::ostringstream o;
    if (params.model != Parameters::Model::monodomain)
      {
        const double last = dealii::Utilities::MPI::max(
          eikonal.times.empty()
            ? 0.0
            : *std::max_element(eikonal.times.begin(), eikonal.times.end()),
          comm);
        o << "Electrophysiology: "
          << (params.model == Parameters::Model::eikonal
                ? "eikonal"
                : (params.reaction_eikonal_diffusion ? "reaction-eikonal RE+"
                                                     : "reaction-eikonal RE-"))
          << ",\n  conduction velocities " << params.eikonal.velocity_fibre
          << " / " << params.eikonal.velocity_sheet << " / "
          << params.eikonal.velocity_normal
          << " mm/ms (fibre / sheet / normal),\n  last activation " << last
          << " ms, eikonal solve " << eikonal.statistics.seconds << " s ("
          << eikonal.statistics.rounds << " exchange rounds)";
        logger.line(o.str());
        o.str("");
      }
    o << "Electrophysiology: monodomain, " << model.name() << ", "
      << (space.kind.simplex() ? "P" : "Q") << params.degree << ", "
      << space.dof_handler.n_dofs()
      << " nodes,\n  D = " << params.diffusivity_l() << " / "
      << params.diffusivity_t()
      << " mm^2/ms (along / across fibres),\n  IMEX ARK order " << params.order
      << ", " << (params.adaptive ? "adaptive steps <= " : "fixed steps ")
      << params.time_step << " ms, CG + " << params.preconditioner << ", "
      << (params.consistent_mass ? "consistent" : "lumped") << " mass";
    logger.line(o.str());
  }


  Monodomain::Monodomain(
    const Parameters                                           &params,
    const dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
    const dealii::Mapping<3, 3>                                &mapping,
    const Fibres::FibreField                                   &fibres,
    const Geometry::BoundaryNames                              &names,
    Logger                                                     &logger,
    const double                                                start_time)
  {
    AssertThrow(params.ionic_model != nullptr,
                dealii::ExcMessage("Monodomain: no ionic model given."));
    impl    = std::make_unique<Impl>(params, tria, mapping, logger, start_time);
    Impl &m = *impl;

    m.distribute_nodes();
    m.setup_matrices();
    m.evaluate_fibres(fibres);
    m.assemble_stiffness(nullptr);
    if (params.ecg.enabled)
      m.setup_lead_field(fibres);
    if (params.purkinje.enabled &&
        params.model == Parameters::Model::monodomain)
      m.setup_purkinje_stimuli(names);
    m.locate_stimuli(names);
    if (params.model != Parameters::Model::monodomain)
      m.setup_eikonal(fibres, names);
    m.stimulation.on.assign(m.params.stimuli.size(), false);

    m.initialize_state();
    m.tracker = ActivationTracker(m.space.n_owned, m.threshold);
    m.extract_potential(m.v_sample);
    m.integrator = m.create_integrator(m.t);
    m.update_output_vectors();
    m.saved.state.reinit(m.space.state_owned, m.comm);
    save();
    m.log_setup();
  }


  Monodomain::~Monodomain() = default;


  bool
  Monodomain::has_ecg() const
  {
    return impl->lead_field != nullptr;
  }


  std::vector<double>
  Monodomain::electrode_potentials() const
  {
    const Impl &m = *impl;
    if (!m.lead_field)
      return {};
    const LocalRead v(m.outputs.potential_mV);
    return m.lead_field->potentials(
      dealii::ArrayView<const double>(v.data(), m.space.n_owned));
  }


  std::array<double, 12>
  Monodomain::ecg_leads() const
  {
    AssertThrow(has_ecg(),
                dealii::ExcMessage("Monodomain::ecg_leads(): Electrophysiology "
                                   "/ ECG is false."));
    return leads_from_electrodes(electrode_potentials());
  }


  double
  Monodomain::time() const
  {
    return impl->t;
  }


  std::vector<double>
  Monodomain::shape_values(const std::vector<dealii::Point<3>> &reference) const
  {
    const auto         &fe = *impl->space.fe;
    const unsigned int  n  = fe.n_dofs_per_cell();
    std::vector<double> phi(reference.size() * n);
    for (unsigned int q = 0; q < reference.size(); ++q)
      for (unsigned int i = 0; i < n; ++i)
        phi[q * n + i] = fe.shape_value(i, reference[q]);
    return phi;
  }


  void
  Monodomain::evaluate(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const dealii::Quadrature<3>                             &quadrature,
    PointValues                                             &values) const
  {
    evaluate(cell, shape_values(quadrature.get_points()), values);
  }


  void
  Monodomain::evaluate(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<double>                               &shape_values,
    PointValues                                             &values) const
  {
    const Impl &m = *impl;
    Assert(&cell->get_triangulation() == &m.tria,
           dealii::ExcMessage("Monodomain::evaluate: the cell belongs to "
                              "another triangulation."));
    Assert(!cell->is_artificial(), dealii::ExcInternalError());
    const dealii::DoFHandler<3>::active_cell_iterator
      dof_cell(&m.tria, cell->level(), cell->index(), &m.space.dof_handler);
    const unsigned int     n = m.space.fe->n_dofs_per_cell();
    dealii::Vector<double> V(n), first(n), latest(n), calcium(n);
    std::vector<dealii::types::global_dof_index> indices(n);
    dof_cell->get_dof_indices(indices);
    for (unsigned int i = 0; i < n; ++i)
      {
        const double *at =
          &m.outputs.values[4 * m.space.local_index(indices[i])];
        V[i]       = at[0];
        first[i]   = at[1];
        latest[i]  = at[2];
        calcium[i] = at[3];
      }

    // With repeated stimulation, the nodes of a cell that the current beat's
    // wave is crossing hold upstrokes of two beats: their interpolant would
    // be a time in between. The latest activation is NaN there until every
    // node has its upstroke of this beat.
    bool mixed_beats = false;
    if (m.params.stimulus_period > 0)
      {
        const auto [lowest, highest] =
          std::minmax_element(latest.begin(), latest.end());
        mixed_beats = *highest - *lowest > 0.5 * m.params.stimulus_period;
      }

    const unsigned int n_q = shape_values.size() / n;
    values.potential.assign(n_q, 0.0);
    values.activation_time.assign(n_q, 0.0);
    values.latest_activation_time.assign(n_q, 0.0);
    values.calcium_uM.assign(n_q, 0.0);
    for (unsigned int q = 0; q < n_q; ++q)
      for (unsigned int i = 0; i < n; ++i)
        {
          // NaN (not activated) at any node propagates to every point.
          const double phi = shape_values[q * n + i];
          values.potential[q] += phi * V[i];
          values.activation_time[q] += phi * first[i];
          values.latest_activation_time[q] += phi * latest[i];
          values.calcium_uM[q] += phi * calcium[i];
        }
    if (mixed_beats)
      values.latest_activation_time
        .assign(n_q, std::numeric_limits<double>::quiet_NaN());
  }


  PointValues
  Monodomain::values_at_points(
    const std::vector<dealii::Point<3>> &points) const
  {
    const Impl        &m     = *impl;
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(m.comm);
    const unsigned int ranks = dealii::Utilities::MPI::n_mpi_processes(m.comm);
    const unsigned int n     = points.size();

    // Each point is evaluated by the lowest rank that owns a cell around it.
    // The search is cached for the last set of points (the probes of a run
    // are asked for every step); every rank makes the same calls.
    auto &cache = m.outputs.point_cache;
    if (cache.points != points)
      {
        cache.points = points;
        cache.owner.assign(n, ranks);
        cache.cells.assign(n, {});
        if (m.space.kind.simplex())
          m.locate_on_tetrahedra(points);
        else
          for (unsigned int p = 0; p < n; ++p)
            {
              try
                {
                  for (const auto &[cell, reference] :
                       dealii::GridTools::find_all_active_cells_around_point(
                         m.mapping,
                         m.space.dof_handler,
                         points[p],
                         1e-10))
                    if (cell->is_locally_owned())
                      {
                        cache.owner[p] = rank;
                        cache.cells[p] = {cell, reference};
                        break;
                      }
                }
              catch (const std::exception &)
                {
                  // Not in any cell this rank knows.
                }
            }
        if (!m.space.kind.simplex())
          dealii::Utilities::MPI::min(
            dealii::ArrayView<const unsigned int>(cache.owner),
            m.comm,
            dealii::ArrayView<unsigned int>(cache.owner));
      }
    const auto &owner = cache.owner;
    const auto &found = cache.cells;

    constexpr unsigned int n_values = 4;
    std::vector<double>    local(n_values * n, 0.0);
    PointValues            at_point;
    for (unsigned int p = 0; p < n; ++p)
      if (owner[p] == rank)
        {
          const dealii::Quadrature<3> one(found[p].second);
          evaluate(found[p].first, one, at_point);
          local[n_values * p]     = at_point.potential[0];
          local[n_values * p + 1] = at_point.activation_time[0];
          local[n_values * p + 2] = at_point.latest_activation_time[0];
          local[n_values * p + 3] = at_point.calcium_uM[0];
        }
      else if (owner[p] == ranks && rank == 0)
        for (unsigned int c = 0; c < n_values; ++c)
          local[n_values * p + c] = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> global(n_values * n);
    dealii::Utilities::MPI::sum(dealii::ArrayView<const double>(local),
                                m.comm,
                                dealii::ArrayView<double>(global));

    PointValues values;
    for (unsigned int p = 0; p < n; ++p)
      {
        values.potential.push_back(global[n_values * p]);
        values.activation_time.push_back(global[n_values * p + 1]);
        values.latest_activation_time.push_back(global[n_values * p + 2]);
        values.calcium_uM.push_back(global[n_values * p + 3]);
      }
    return values;
  }


  void
  Monodomain::Impl::locate_on_tetrahedra(
    const std::vector<dealii::Point<3>> &points) const
  {
    // Each point is evaluated by the rank holding it least outside a cell,
    // the lowest among equals (deal.II 9.4's searches test the unit cube,
    // not the tetrahedron).
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
    const auto         located =
      Geometry::locate_in_owned_cells(tria, mapping, points, 1e-10);
    auto &cache = outputs.point_cache;
    cache.owner = Geometry::evaluating_ranks(located, comm);
    for (unsigned int p = 0; p < points.size(); ++p)
      if (cache.owner[p] == rank)
        {
          const auto &cell = located[p].cell;
          cache.cells[p]   = {
              dealii::DoFHandler<3>::active_cell_iterator(&tria,
                                                        cell->level(),
                                                        cell->index(),
                                                        &space.dof_handler),
              located[p].reference};
        }
  }


  double
  Monodomain::activated_fraction() const
  {
    double active = 0, total = 0;
    for (unsigned int i = 0; i < impl->space.n_owned; ++i)
      {
        total += impl->matrices.lumped_mass[i];
        if (!std::isnan(impl->tracker.first()[i]))
          active += impl->matrices.lumped_mass[i];
      }
    return dealii::Utilities::MPI::sum(active, impl->comm) /
           dealii::Utilities::MPI::sum(total, impl->comm);
  }


  ActivationSummary
  Monodomain::activation_summary(const double fraction, const bool latest) const
  {
    return summarize_activation(latest ? impl->tracker.latest()
                                       : impl->tracker.first(),
                                impl->matrices.lumped_mass,
                                fraction,
                                impl->comm);
  }


  void
  Monodomain::set_deformation_gradients(
    const std::vector<std::vector<dealii::Tensor<2, 3>>> &F)
  {
    if (!impl->params.pull_back)
      return;
    AssertThrow(F.size() == impl->tria.n_active_cells(),
                dealii::ExcMessage("Monodomain::set_deformation_gradients: "
                                   "give one entry per active cell."));
    impl->assemble_stiffness(&F);
  }


  const dealii::Quadrature<3> &
  Monodomain::diffusion_quadrature() const
  {
    return impl->space.quadrature;
  }


  void
  Monodomain::save()
  {
    Impl &m                        = *impl;
    m.saved.state                  = m.state;
    m.saved.t                      = m.t;
    m.saved.first                  = m.tracker.first();
    m.saved.latest                 = m.tracker.latest();
    m.saved.v_sample               = m.v_sample;
    m.saved.gate_half_step_pending = m.gate_half_step_pending;
  }


  void
  Monodomain::restore()
  {
    Impl &m                  = *impl;
    m.state                  = m.saved.state;
    m.t                      = m.saved.t;
    m.v_sample               = m.saved.v_sample;
    m.gate_half_step_pending = m.saved.gate_half_step_pending;
    m.tracker.set(m.saved.first, m.saved.latest);
    m.integrator->reset(m.t);
    m.update_output_vectors();
  }


  void
  Monodomain::attach_output(dealii::DataOut<3, 3> &data_out) const
  {
    data_out.add_data_vector(impl->space.dof_handler,
                             impl->outputs.potential_mV,
                             "transmembrane_potential");
    data_out.add_data_vector(impl->space.dof_handler,
                             impl->outputs.activation_field,
                             "activation_time");
    if (impl->model.has_calcium())
      data_out.add_data_vector(impl->space.dof_handler,
                               impl->outputs.calcium_uM,
                               "calcium");
  }


  dealii::types::global_dof_index
  Monodomain::n_dofs() const
  {
    return impl->space.dof_handler.n_dofs();
  }


  Statistics
  Monodomain::statistics() const
  {
    return impl->stats;
  }


  const IonicModel &
  Monodomain::ionic_model() const
  {
    return impl->model;
  }


  const PurkinjeNetwork &
  Monodomain::purkinje() const
  {
    return impl->purkinje;
  }
} // namespace systole::Electrophysiology
