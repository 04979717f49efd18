#include "simulation/electrical_activation.h"

#include <deal.II/base/mpi_remote_point_evaluation.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/numerics/data_out.h>

#include "base/logger.h"
#include "electrophysiology/activation.h"
#include "electrophysiology/parameters.h"
#include "fibres/fibre_field.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "geometry/point_location.h"
#include "mechanics/problem.h"
#include "simulation/ecg_columns.h"
#include "simulation/parameters.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <sstream>

namespace systole
{
  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();

    /// A mechanics point is in an EP cell if it lies within this distance of
    /// it in reference coordinates: the two meshes approximate the curved
    /// surfaces differently (the mechanics coarser), so points on or near
    /// the boundary may lie a little outside the EP mesh.
    constexpr double point_tolerance = 0.05;

    /// Mechanics points read from the EP mesh: located by
    /// RemotePointEvaluation (unique mapping) on hexahedra, by
    /// Geometry::DistributedPoints on tetrahedra (deal.II 9.4's search tests
    /// the unit cube, and misses or misplaces points in tetrahedra).
    struct PointSet
    {
      std::unique_ptr<dealii::Utilities::MPI::RemotePointEvaluation<3>> rpe;
      std::unique_ptr<Geometry::DistributedPoints>                      simplex;
      unsigned int n_points = 0;
      /// On tetrahedra: the EP shape values at the points of each cell
      /// evaluated here (computed on the first evaluation).
      mutable std::vector<std::vector<double>> shape_values;

      /// Locate @p points (collective).
      void
      reinit(const std::vector<dealii::Point<3>>                     &points,
             const dealii::parallel::DistributedTriangulationBase<3> &tria,
             const dealii::Mapping<3>                                &mapping,
             const bool tetrahedra)
      {
        n_points = points.size();
        if (tetrahedra)
          simplex = std::make_unique<Geometry::DistributedPoints>(
            tria,
            mapping,
            points,
            point_tolerance,
            tria.get_communicator());
        else
          {
            rpe = std::make_unique<
              dealii::Utilities::MPI::RemotePointEvaluation<3>>(
              point_tolerance,
              /*enforce_unique_mapping=*/true);
            rpe->reinit(points, tria, mapping);
          }
      }

      bool
      point_found(const unsigned int i) const
      {
        return simplex ? simplex->point_found(i) : rpe->point_found(i);
      }
    };

    /// Throw unless every point of @p set was found (collective).
    void
    require_all_found(const PointSet    &set,
                      const std::string &what,
                      const MPI_Comm     comm)
    {
      unsigned int missing = 0;
      for (unsigned int i = 0; i < set.n_points; ++i)
        if (!set.point_found(i))
          ++missing;
      missing = dealii::Utilities::MPI::sum(missing, comm);
      AssertThrow(missing == 0,
                  dealii::ExcMessage(
                    std::to_string(missing) + " " + what +
                    " of the mechanics lie outside the electrophysiology "
                    "mesh (the mechanics mesh refined Electrophysiology / "
                    "Mesh refinement times): the two geometries differ "
                    "more than the cells allow; check Discretization / "
                    "Mapping degree."));
    }

    Electrophysiology::Parameters
    coupled_parameters(const dealii::ParameterHandler &prm, const double period)
    {
      auto params = Electrophysiology::Parameters::parse(prm);
      AssertThrow(
        !params.pull_back,
        dealii::ExcMessage(
          "Electrophysiology / Pull back conductivity = true is not supported "
          "by the heartbeat: its coupling is one way (the potential does not "
          "see the deformation). Set it to false."));
      if (params.stimulus_period == 0)
        params.stimulus_period = period;
      AssertThrow(std::abs(params.stimulus_period - period) <= 1e-9 * period,
                  dealii::ExcMessage(
                    "Electrophysiology / Stimulus period (" +
                    dealii::Utilities::to_string(params.stimulus_period) +
                    " ms) differs from Circulation / Period (" +
                    dealii::Utilities::to_string(period) +
                    " ms): the stimulus starts every beat. Set it to 0 (the "
                    "beat period) or to the period."));
      AssertThrow(!params.stimuli.empty(),
                  dealii::ExcMessage(
                    "Electrophysiology / Stimuli is empty: nothing would "
                    "trigger the beat."));
      return params;
    }

    /// The EP mesh: the mechanics mesh (from @p geometry) refined
    /// Electrophysiology / Mesh refinement more times; loaded from
    /// @p checkpoint if not empty.
    Geometry::DistributedMesh
    ep_mesh(const Geometry::Parameters          &geometry,
            const Electrophysiology::Parameters &params,
            const MPI_Comm                       comm,
            const std::string                   &checkpoint)
    {
      Geometry::Parameters refined = geometry;
      refined.global_refinements += params.mesh_refinement;
      return Geometry::create_distributed_mesh(refined,
                                               comm,
                                               checkpoint.empty()
                                                 ? ""
                                                 : checkpoint + "/ep.mesh");
    }

    /// The mapping of the EP mesh: CellKind's on tetrahedra (affine); on
    /// hexahedra a plain MappingQ, whose point searches give the
    /// RemotePointEvaluation the same cells as before (a MappingQCache
    /// moves the activation of points on cell faces by 1e-10).
    std::unique_ptr<dealii::Mapping<3, 3>>
    ep_mapping(const Geometry::CellKind          &kind,
               const dealii::Triangulation<3, 3> &tria,
               const unsigned int                 degree)
    {
      if (kind.simplex())
        return kind.mapping(tria, degree);
      return std::make_unique<dealii::MappingQ<3>>(degree);
    }
  } // namespace

  struct ElectricalActivation::Impl
  {
    explicit Impl(const Inputs &in);

    /// Values (potential, first, latest activation) at the points of @p rpe,
    /// NaN where a point was not found. Collective.
    std::vector<dealii::Tensor<1, 4>>
    evaluate(const PointSet &set) const;

    /// Sample the potential at the mechanics points (at the current EP time)
    /// and record their upstrokes since the last sample. Collective.
    void
    sample();

    Electrophysiology::Parameters params;
    /// The EP mesh and the names of its boundary parts.
    Geometry::DistributedMesh                      mesh;
    Geometry::CellKind                             kind;
    std::unique_ptr<dealii::Mapping<3, 3>>         mapping;
    std::unique_ptr<Electrophysiology::Monodomain> monodomain;
    MPI_Comm                                       comm;

    /// Mechanics quadrature points: where each cell's points start in the
    /// flat list, and the upstroke times of each point (ascending).
    std::vector<unsigned int> cell_start;
    unsigned int              n_points = 0;
    PointSet                  at_quadrature;
    /// Upstrokes of the potential interpolated at each point (crossings of
    /// the activation threshold, located linearly in time between samples).
    Electrophysiology::ActivationTracker tracker;
    std::vector<double>                  sampled_potential;
    double                               sampled_time = 0;
    std::vector<std::vector<double>>     upstrokes;
    double                               transfer_seconds = 0;
    /// The calcium [µM] at the mechanics points at the sample times since
    /// the last forget_calcium_before() (keep_calcium()).
    bool                            keep_calcium = false;
    std::deque<double>              calcium_times;
    std::deque<std::vector<double>> calcium_samples;
    /// The 12 leads of the pseudo-ECG at every sample since the last
    /// forget_ecg_before() (Electrophysiology / ECG).
    EcgBeat                                                  ecg;
    const dealii::parallel::DistributedTriangulationBase<3> &mech_tria;
    const Mechanics::Problem                                &problem;

    /// Output on the mechanics mesh (set up on first use).
    struct MechanicsOutput
    {
      explicit MechanicsOutput(const unsigned int degree)
        : degree(degree)
      {}

      unsigned int                                       degree;
      std::unique_ptr<dealii::FiniteElement<3, 3>>       fe;
      std::unique_ptr<dealii::DoFHandler<3>>             dofs;
      std::unique_ptr<PointSet>                          at_nodes;
      std::vector<dealii::types::global_dof_index>       node_dofs;
      dealii::LinearAlgebra::distributed::Vector<double> potential, first,
        latest;
    } mech_output;
  };


  std::unique_ptr<Electrophysiology::Monodomain>
  create_monodomain(const MonodomainInputs &in)
  {
    return std::make_unique<Electrophysiology::Monodomain>(
      in.params,
      *in.mesh.tria,
      in.mapping,
      Fibres::create_fibre_field(
        Fibres::Parameters::parse(in.prm, in.run.parameter_directory),
        in.geometry.lv_shape,
        *in.mesh.tria,
        in.mesh.names,
        &in.logger),
      in.mesh.names,
      in.logger,
      in.start_time);
  }


  ElectricalActivation::Impl::Impl(const Inputs &in)
    : params(coupled_parameters(in.prm, in.period))
    , mesh(ep_mesh(in.geometry, params, in.comm, in.checkpoint))
    , kind(*mesh.tria)
    , mapping(ep_mapping(kind, *mesh.tria, in.run.mapping_degree))
    , comm(in.comm)
    , tracker(0, params.activation_threshold_mV)
    , mech_tria(in.mechanics_tria)
    , problem(in.problem)
    , mech_output(in.run.polynomial_degree)
  {
    AssertThrow(!kind.simplex() || (in.run.checkpoint_interval == 0 &&
                                    in.run.checkpoint_minutes == 0),
                dealii::ExcMessage(
                  "The electrophysiology on a tetrahedral mesh cannot be "
                  "checkpointed yet: set Output / Checkpoint interval = 0 and "
                  "Output / Checkpoint wall time interval = 0."));
    // The fibre generator runs again on the EP mesh (the rule-based one
    // solves its Laplace problems there); the monodomain model evaluates it
    // once, at its own quadrature points.
    monodomain = create_monodomain(
      {in.prm, in.run, params, in.geometry, mesh, *mapping, in.logger, 0.0});

    std::vector<std::vector<dealii::Point<3>>> points;
    problem.quadrature_points(points);
    std::vector<dealii::Point<3>> flat;
    for (const auto &cell : points)
      {
        cell_start.push_back(flat.size());
        flat.insert(flat.end(), cell.begin(), cell.end());
      }
    cell_start.push_back(flat.size());
    n_points = flat.size();
    at_quadrature.reinit(flat, *mesh.tria, *mapping, kind.simplex());
    require_all_found(at_quadrature, "quadrature points", comm);
    upstrokes.assign(n_points, {});
    tracker =
      Electrophysiology::ActivationTracker(n_points,
                                           params.activation_threshold_mV);
    sample();
  }


  std::vector<dealii::Tensor<1, 4>>
  ElectricalActivation::Impl::evaluate(const PointSet &set) const
  {
    using Value                      = dealii::Tensor<1, 4>;
    const unsigned int             n = set.n_points;
    Electrophysiology::PointValues values;
    if (set.simplex)
      {
        // (Points are handed over moved into their cell.)
        const auto flat = set.simplex->evaluate(
          4,
          [&](const unsigned int                                    c,
              const dealii::Triangulation<3>::active_cell_iterator &cell,
              const std::vector<dealii::Point<3>>                  &reference,
              std::vector<double>                                  &result) {
            if (c >= set.shape_values.size())
              set.shape_values.resize(c + 1);
            if (set.shape_values[c].empty())
              set.shape_values[c] = monodomain->shape_values(reference);
            monodomain->evaluate(cell, set.shape_values[c], values);
            result.resize(4 * reference.size());
            for (unsigned int q = 0; q < reference.size(); ++q)
              {
                result[4 * q]     = values.potential[q];
                result[4 * q + 1] = values.activation_time[q];
                result[4 * q + 2] = values.latest_activation_time[q];
                result[4 * q + 3] = values.calcium_uM[q];
              }
          });
        std::vector<Value> per_point(n);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int c = 0; c < 4; ++c)
            per_point[i][c] = flat[4 * i + c];
        return per_point;
      }

    std::vector<Value> output, buffer;
    set.rpe->evaluate_and_process<Value>(
      output,
      buffer,
      [&](const dealii::ArrayView<Value> &result,
          const dealii::Utilities::MPI::RemotePointEvaluation<3>::CellData
            &data) {
        for (unsigned int c = 0; c < data.cells.size(); ++c)
          {
            const dealii::Triangulation<3>::active_cell_iterator
              cell(mesh.tria.get(), data.cells[c].first, data.cells[c].second);
            const unsigned int begin = data.reference_point_ptrs[c];
            const unsigned int end   = data.reference_point_ptrs[c + 1];
            // Points found within the tolerance outside the cell are
            // evaluated on its boundary.
            std::vector<dealii::Point<3>> reference(
              data.reference_point_values.begin() + begin,
              data.reference_point_values.begin() + end);
            for (auto &point : reference)
              point = kind.project_to_reference_cell(point);
            const dealii::Quadrature<3> points(reference);
            monodomain->evaluate(cell, points, values);
            for (unsigned int q = 0; q < end - begin; ++q)
              {
                result[begin + q][0] = values.potential[q];
                result[begin + q][1] = values.activation_time[q];
                result[begin + q][2] = values.latest_activation_time[q];
                result[begin + q][3] = values.calcium_uM[q];
              }
          }
      });
    // One entry per point and cell around it (unique mapping: at most one).
    std::vector<Value> per_point(n, Value({nan, nan, nan, nan}));
    const auto        &ptr = set.rpe->get_point_ptrs();
    for (unsigned int i = 0; i < n; ++i)
      if (ptr[i + 1] > ptr[i])
        per_point[i] = output[ptr[i]];
    return per_point;
  }


  void
  ElectricalActivation::Impl::sample()
  {
    const auto          start  = std::chrono::steady_clock::now();
    const auto          values = evaluate(at_quadrature);
    const double        time   = monodomain->time();
    std::vector<double> potential(n_points);
    for (unsigned int i = 0; i < n_points; ++i)
      potential[i] = values[i][0];
    if (params.model == Electrophysiology::Parameters::Model::eikonal &&
        time > sampled_time)
      {
        // The eikonal model alone: its activation times are the upstrokes
        // (interpolated from the nodes; NaN while the beat's front crosses
        // the cell), not sampled from a potential.
        std::vector<double> first(n_points), latest(n_points);
        for (unsigned int i = 0; i < n_points; ++i)
          {
            first[i]  = values[i][1];
            latest[i] = values[i][2];
            if (!std::isnan(latest[i]) &&
                (upstrokes[i].empty() || latest[i] > upstrokes[i].back()))
              upstrokes[i].push_back(latest[i]);
          }
        tracker.set(first, latest);
      }
    else if (!sampled_potential.empty() && time > sampled_time)
      {
        tracker.update(sampled_time,
                       sampled_potential.data(),
                       time,
                       potential.data());
        for (unsigned int i = 0; i < n_points; ++i)
          {
            const double latest = tracker.latest()[i];
            if (!std::isnan(latest) &&
                (upstrokes[i].empty() || latest > upstrokes[i].back()))
              upstrokes[i].push_back(latest);
          }
      }
    if (keep_calcium && (calcium_times.empty() || time > calcium_times.back()))
      {
        std::vector<double> calcium(n_points);
        for (unsigned int i = 0; i < n_points; ++i)
          calcium[i] = values[i][3];
        calcium_times.push_back(time);
        calcium_samples.push_back(std::move(calcium));
      }
    sampled_potential = std::move(potential);
    sampled_time      = time;
    if (monodomain->has_ecg())
      ecg.add(time, monodomain->ecg_leads());
    transfer_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
  }


  ElectricalActivation::ElectricalActivation(const Inputs &in)
    : impl(std::make_unique<Impl>(in))
  {}


  namespace
  {
    using MechanicsCell = dealii::Triangulation<3, 3>::cell_iterator;
    using CellStatus    = dealii::Triangulation<3, 3>::CellStatus;
    using Range = boost::iterator_range<std::vector<char>::const_iterator>;
  } // namespace


  bool
  ElectricalActivation::checkpointable() const
  {
    return !impl->kind.simplex();
  }


  void
  ElectricalActivation::save_checkpoint(boost::archive::text_oarchive &archive,
                                        const std::string             &folder)
  {
    Impl &m = *impl;
    m.monodomain->prepare_checkpoint(archive);
    m.mesh.tria->save(folder + "/ep.mesh");
    m.monodomain->finish_checkpoint();
    archive            &m.sampled_time;
    std::vector<double> calcium_times(m.calcium_times.begin(),
                                      m.calcium_times.end());
    archive &m.keep_calcium &calcium_times;
    // The ECG samples kept (the same on every rank), flattened.
    std::vector<double> ecg_leads;
    for (const auto &leads : m.ecg.leads)
      ecg_leads.insert(ecg_leads.end(), leads.begin(), leads.end());
    archive &m.ecg.times &ecg_leads;
    // Per mechanics point: first and latest upstroke of the tracker, the
    // last sample, the upstrokes, the calcium samples (keep_calcium()). (The
    // registration only lasts until the mechanics mesh is saved; it does not
    // change the mesh, hence the cast.)
    auto &mechanics_tria =
      const_cast<dealii::parallel::DistributedTriangulationBase<3, 3> &>(
        m.mech_tria);
    mechanics_tria.register_data_attach(
      [&m](const MechanicsCell &cell, const CellStatus) {
        std::vector<double> data;
        const unsigned int  c = cell->active_cell_index();
        for (unsigned int i = m.cell_start[c]; i < m.cell_start[c + 1]; ++i)
          {
            data.push_back(m.tracker.first()[i]);
            data.push_back(m.tracker.latest()[i]);
            data.push_back(m.sampled_potential[i]);
            data.push_back(m.upstrokes[i].size());
            data.insert(data.end(),
                        m.upstrokes[i].begin(),
                        m.upstrokes[i].end());
            for (const auto &sample : m.calcium_samples)
              data.push_back(sample[i]);
          }
        return dealii::Utilities::pack(data, false);
      },
      /*returns_variable_size_data=*/true);
  }


  void
  ElectricalActivation::load_checkpoint(boost::archive::text_iarchive &archive)
  {
    Impl &m = *impl;
    m.monodomain->load_checkpoint(archive);
    archive            &m.sampled_time;
    std::vector<double> calcium_times;
    archive &m.keep_calcium &calcium_times;
    std::vector<double>      ecg_leads;
    archive &m.ecg.times &ecg_leads;
    AssertThrow(ecg_leads.size() == 12 * m.ecg.times.size(),
                dealii::ExcMessage("The checkpoint's ECG samples are "
                                   "incomplete."));
    m.ecg.leads.resize(m.ecg.times.size());
    for (unsigned int k = 0; k < m.ecg.times.size(); ++k)
      std::copy(ecg_leads.begin() + 12 * k,
                ecg_leads.begin() + 12 * (k + 1),
                m.ecg.leads[k].begin());
    m.calcium_times.assign(calcium_times.begin(), calcium_times.end());
    m.calcium_samples.assign(calcium_times.size(),
                             std::vector<double>(m.n_points));
    auto &mechanics_tria =
      const_cast<dealii::parallel::DistributedTriangulationBase<3, 3> &>(
        m.mech_tria);
    const unsigned int handle = mechanics_tria.register_data_attach(
      [](const MechanicsCell &, const CellStatus) {
        return std::vector<char>();
      },
      true);
    std::vector<double> first(m.n_points), latest(m.n_points);
    mechanics_tria.notify_ready_to_unpack(
      handle,
      [&](const MechanicsCell &cell, const CellStatus, const Range &range) {
        const auto data =
          dealii::Utilities::unpack<std::vector<double>>(range.begin(),
                                                         range.end(),
                                                         false);
        const unsigned int c   = cell->active_cell_index();
        std::size_t        pos = 0;
        for (unsigned int i = m.cell_start[c]; i < m.cell_start[c + 1]; ++i)
          {
            AssertThrow(pos + 4 <= data.size(),
                        dealii::ExcMessage(
                          "The checkpoint's activation data do not fit the "
                          "quadrature of the mechanics."));
            first[i]                = data[pos++];
            latest[i]               = data[pos++];
            m.sampled_potential[i]  = data[pos++];
            const std::size_t count = static_cast<std::size_t>(data[pos++]);
            m.upstrokes[i].assign(data.begin() + pos,
                                  data.begin() + pos + count);
            pos += count;
            AssertThrow(pos + m.calcium_samples.size() <= data.size(),
                        dealii::ExcMessage(
                          "The checkpoint's calcium samples do not fit the "
                          "quadrature of the mechanics."));
            for (auto &sample : m.calcium_samples)
              sample[i] = data[pos++];
          }
      });
    m.tracker.set(first, latest);
  }


  ElectricalActivation::~ElectricalActivation() = default;


  void
  ElectricalActivation::advance_to(const double t)
  {
    Impl        &m  = *impl;
    const double dt = m.params.time_step;
    // Step by step on the grid of multiples of dt up to the first one at or
    // after t (EP's steps do not depend on the mechanics' steps), sampling
    // the mechanics points after each.
    while (m.monodomain->time() < t - 1e-9 * dt)
      {
        const double next =
          (std::floor(m.monodomain->time() / dt + 1e-9) + 1.0) * dt;
        m.monodomain->advance(next);
        m.sample();
      }
  }


  void
  ElectricalActivation::activation_times(
    const double                      t,
    std::vector<std::vector<double>> &times) const
  {
    const Impl &m = *impl;
    Assert(t <= m.monodomain->time() + 1e-9 * m.params.time_step,
           dealii::ExcMessage("ElectricalActivation: advance_to(t) first."));
    times.resize(m.cell_start.size() - 1);
    for (unsigned int c = 0; c + 1 < m.cell_start.size(); ++c)
      {
        times[c].resize(m.cell_start[c + 1] - m.cell_start[c]);
        for (unsigned int q = 0; q < times[c].size(); ++q)
          {
            const auto &list = m.upstrokes[m.cell_start[c] + q];
            double      time = nan;
            for (auto it = list.rbegin(); it != list.rend(); ++it)
              if (*it <= t)
                {
                  time = *it;
                  break;
                }
            times[c][q] = time;
          }
      }
  }


  double
  ElectricalActivation::time() const
  {
    return impl->monodomain->time();
  }


  void
  ElectricalActivation::keep_calcium()
  {
    Impl &m = *impl;
    AssertThrow(m.monodomain->ionic_model().has_calcium(),
                dealii::ExcMessage(
                  "A calcium-driven tension model (Active tension / Model) "
                  "needs an ionic model with intracellular calcium: set "
                  "Electrophysiology / Ionic model = ten Tusscher-Panfilov."));
    if (m.keep_calcium)
      return;
    m.keep_calcium             = true;
    const auto          values = m.evaluate(m.at_quadrature);
    std::vector<double> calcium(m.n_points);
    for (unsigned int i = 0; i < m.n_points; ++i)
      calcium[i] = values[i][3];
    m.calcium_times.assign(1, m.monodomain->time());
    m.calcium_samples.assign(1, std::move(calcium));
  }


  void
  ElectricalActivation::calcium(const double                      t,
                                std::vector<std::vector<double>> &calcium) const
  {
    const Impl &m = *impl;
    AssertThrow(m.keep_calcium && !m.calcium_times.empty(),
                dealii::ExcMessage("ElectricalActivation: keep_calcium() "
                                   "first."));
    const double slack = 1e-9 * std::max(1.0, std::abs(t));
    AssertThrow(t >= m.calcium_times.front() - slack &&
                  t <= m.calcium_times.back() + slack,
                dealii::ExcMessage(
                  "ElectricalActivation: the calcium at t = " +
                  dealii::Utilities::to_string(t) +
                  " ms lies outside the kept samples (" +
                  dealii::Utilities::to_string(m.calcium_times.front()) +
                  " to " +
                  dealii::Utilities::to_string(m.calcium_times.back()) +
                  " ms): advance_to(t) first, forget only accepted times."));
    // The samples around t, linear in between.
    std::size_t k = 0;
    while (k + 2 < m.calcium_times.size() && m.calcium_times[k + 1] < t)
      ++k;
    const auto &a = m.calcium_samples[k];
    const auto &b =
      m.calcium_samples[std::min(k + 1, m.calcium_times.size() - 1)];
    const double t0 = m.calcium_times[k];
    const double t1 =
      m.calcium_times[std::min(k + 1, m.calcium_times.size() - 1)];
    const double w = t1 > t0 ? std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 0.0;
    calcium.resize(m.cell_start.size() - 1);
    for (unsigned int c = 0; c + 1 < m.cell_start.size(); ++c)
      {
        calcium[c].resize(m.cell_start[c + 1] - m.cell_start[c]);
        for (unsigned int q = 0; q < calcium[c].size(); ++q)
          {
            const unsigned int i = m.cell_start[c] + q;
            calcium[c][q]        = (1.0 - w) * a[i] + w * b[i];
          }
      }
  }


  void
  ElectricalActivation::forget_calcium_before(const double t)
  {
    Impl &m = *impl;
    while (m.calcium_times.size() >= 2 && m.calcium_times[1] <= t)
      {
        m.calcium_times.pop_front();
        m.calcium_samples.pop_front();
      }
  }


  double
  ElectricalActivation::earliest_stimulus() const
  {
    double earliest = std::numeric_limits<double>::max();
    for (const auto &stimulus : impl->params.stimuli)
      earliest = std::min(earliest, stimulus.start);
    return earliest;
  }


  void
  ElectricalActivation::attach_output(dealii::DataOut<3, 3> &data_out)
  {
    Impl &m = *impl;
    if (!m.mech_output.dofs)
      {
        // A scalar Q(degree) (P(degree) on tetrahedra) field on the
        // mechanics mesh: EP is read at the support points of the locally
        // owned nodes.
        m.mech_output.fe =
          Geometry::CellKind(m.mech_tria).lagrange(m.mech_output.degree);
        m.mech_output.dofs =
          std::make_unique<dealii::DoFHandler<3>>(m.mech_tria);
        m.mech_output.dofs->distribute_dofs(*m.mech_output.fe);
        const auto       owned = m.mech_output.dofs->locally_owned_dofs();
        dealii::IndexSet relevant;
        dealii::DoFTools::extract_locally_relevant_dofs(*m.mech_output.dofs,
                                                        relevant);
        for (auto *v : {&m.mech_output.potential,
                        &m.mech_output.first,
                        &m.mech_output.latest})
          v->reinit(owned, relevant, m.comm);
        std::map<dealii::types::global_dof_index, dealii::Point<3>> support;
        dealii::DoFTools::map_dofs_to_support_points(m.problem.mapping(),
                                                     *m.mech_output.dofs,
                                                     support);
        std::vector<dealii::Point<3>> points;
        for (const auto &[dof, point] : support)
          if (owned.is_element(dof))
            {
              m.mech_output.node_dofs.push_back(dof);
              points.push_back(point);
            }
        m.mech_output.at_nodes = std::make_unique<PointSet>();
        m.mech_output.at_nodes->reinit(points,
                                       *m.mesh.tria,
                                       *m.mapping,
                                       m.kind.simplex());
        require_all_found(*m.mech_output.at_nodes, "output nodes", m.comm);
      }
    const auto values = m.evaluate(*m.mech_output.at_nodes);
    for (unsigned int i = 0; i < m.mech_output.node_dofs.size(); ++i)
      {
        m.mech_output.potential[m.mech_output.node_dofs[i]] = values[i][0];
        // (A finite "not activated": NaN would spread through DataOut.)
        m.mech_output.first[m.mech_output.node_dofs[i]] =
          std::isnan(values[i][1]) ? Electrophysiology::not_activated_time
                                   : values[i][1];
        m.mech_output.latest[m.mech_output.node_dofs[i]] =
          std::isnan(values[i][2]) ? Electrophysiology::not_activated_time
                                   : values[i][2];
      }
    for (auto *v : {&m.mech_output.potential,
                    &m.mech_output.first,
                    &m.mech_output.latest})
      v->update_ghost_values();
    data_out.add_data_vector(*m.mech_output.dofs,
                             m.mech_output.potential,
                             "transmembrane_potential");
    data_out.add_data_vector(*m.mech_output.dofs,
                             m.mech_output.first,
                             "activation_time");
    data_out.add_data_vector(*m.mech_output.dofs,
                             m.mech_output.latest,
                             "latest_activation_time");
  }


  double
  ElectricalActivation::activated_fraction() const
  {
    return impl->monodomain->activated_fraction();
  }


  const Electrophysiology::PurkinjeNetwork &
  ElectricalActivation::purkinje() const
  {
    return impl->monodomain->purkinje();
  }


  bool
  ElectricalActivation::has_ecg() const
  {
    return impl->monodomain->has_ecg();
  }


  std::array<double, 12>
  ElectricalActivation::ecg_leads(const double t) const
  {
    const Impl &m = *impl;
    AssertThrow(m.monodomain->has_ecg(),
                dealii::ExcMessage("ElectricalActivation: no ECG."));
    Assert(t <= m.monodomain->time() + 1e-9 * m.params.time_step,
           dealii::ExcMessage("ElectricalActivation: advance_to(t) first."));
    return m.ecg.at(t);
  }


  void
  ElectricalActivation::append_ecg_biomarkers(const double             start,
                                              const double             end,
                                              std::vector<IO::Column> &row)
  {
    Impl &m = *impl;
    m.ecg.append_biomarkers(start, end, m.params.ecg.threshold, row);
    // The next beat starts at end: its samples (EP may have run ahead) stay.
    m.ecg.forget_before(end);
  }


  Electrophysiology::ActivationSummary
  ElectricalActivation::beat_summary() const
  {
    return impl->monodomain->activation_summary(0.9, true);
  }


  Electrophysiology::Statistics
  ElectricalActivation::statistics() const
  {
    return impl->monodomain->statistics();
  }


  double
  ElectricalActivation::transfer_seconds() const
  {
    return impl->transfer_seconds;
  }


  std::string
  ElectricalActivation::description() const
  {
    const Impl        &m = *impl;
    std::ostringstream o;
    o << "Electrophysiology mesh: the mechanics mesh refined "
      << m.params.mesh_refinement << " time(s), "
      << m.mesh.tria->n_global_active_cells() << " " << m.kind.name() << ", "
      << (m.kind.simplex() ? "P" : "Q") << m.params.degree << ", "
      << m.monodomain->n_dofs() << " nodes;\n  stimulus every "
      << m.params.stimulus_period << " ms, read at "
      << dealii::Utilities::MPI::sum(m.n_points, m.comm)
      << " mechanics quadrature points";
    return o.str();
  }
  unsigned long long
  ElectricalActivation::n_nodes() const
  {
    return impl->monodomain->n_dofs();
  }
} // namespace systole
