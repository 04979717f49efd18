// Checkpoints of Mechanics::Problem: the saved states and the held
// factorization travel with the cells of the mesh (SolutionTransfer and
// attached cell data of the distributed mesh's save/load), so a run on
// hexahedra (p4est) can resume on another number of ranks; one on tetrahedra
// (fully distributed) resumes on the same number.

#include <deal.II/base/utilities.h>

#include "mechanics/problem_impl.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/serialization/vector.hpp>

#include <cstdint>
#include <cstring>

namespace systole::Mechanics
{
  namespace
  {
    using CellIterator = dealii::Triangulation<3, 3>::cell_iterator;
    using CellStatus   = dealii::Triangulation<3, 3>::CellStatus;
    using Range = boost::iterator_range<std::vector<char>::const_iterator>;

    /// Whether the cell data of a checkpoint must have one size on every
    /// cell: deal.II 9.4's fully distributed mesh saves fixed-size data only
    /// (p4est saves either).
    bool
    fixed_size_cell_data(
      const dealii::parallel::DistributedTriangulationBase<3, 3> &tria)
    {
      return dynamic_cast<
               const dealii::parallel::distributed::Triangulation<3, 3> *>(
               &tria) == nullptr;
    }

    /// @p bytes behind their length (8 bytes), padded with zeros to
    /// 8 + @p size bytes.
    std::vector<char>
    with_length(const std::vector<char> &bytes, const std::uint64_t size)
    {
      std::vector<char>   out(sizeof(std::uint64_t) + size, 0);
      const std::uint64_t n = bytes.size();
      std::memcpy(out.data(), &n, sizeof(n));
      std::copy(bytes.begin(), bytes.end(), out.begin() + sizeof(n));
      return out;
    }

    /// The bytes with_length() wrapped.
    Range
    without_length(const Range &range)
    {
      std::uint64_t n = 0;
      std::memcpy(&n, &*range.begin(), sizeof(n));
      const auto begin = range.begin() + sizeof(n);
      AssertThrow(n <= static_cast<std::uint64_t>(range.end() - begin),
                  dealii::ExcMessage("The checkpoint's mechanics cell data "
                                     "are truncated."));
      return Range(begin, begin + n);
    }
  } // namespace


  std::vector<std::vector<double>>
  Problem::Impl::checkpoint_data_of(const CellIterator &cell) const
  {
    const auto                       c = cell->active_cell_index();
    std::vector<std::vector<double>> data(3);
    if (c < factorized.tension.size())
      data[0] = factorized.tension[c];
    if (c < factorized.model_inputs.size())
      data[2] = factorized.model_inputs[c];
    if (points.tension_model != nullptr)
      for (const auto &point : points.point_data.get_data(cell))
        {
          data[1].insert(data[1].end(),
                         point->tension_state.begin(),
                         point->tension_state.end());
          data[1].push_back(point->stretch_n);
          data[1].push_back(point->model_tension);
        }
    return data;
  }


  void
  Problem::Impl::remember_factorized_tension()
  {
    factorized.tension.assign(tria.n_active_cells(), {});
    factorized.model_inputs.assign(points.tension_model != nullptr
                                     ? tria.n_active_cells()
                                     : 0,
                                   {});
    factorized.tension_time      = points.tension_time;
    factorized.tension_time_step = points.tension_time_step;
    if (dynamics.started)
      {
        dynamics.factorized_time_step = dynamics.time_step;
        dynamics.factorized_u_n       = dynamics.u_n;
        dynamics.factorized_v_n       = dynamics.v_n;
        dynamics.factorized_a_n       = dynamics.a_n;
      }
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &data : points.point_data.get_data(cell))
          {
            const auto c = cell->active_cell_index();
            factorized.tension[c].push_back(data->tension);
            if (points.tension_model != nullptr)
              {
                auto &inputs = factorized.model_inputs[c];
                inputs.insert(inputs.end(),
                              data->tension_state.begin(),
                              data->tension_state.end());
                inputs.push_back(data->stretch_n);
                inputs.push_back(data->calcium);
              }
          }
  }


  void
  Problem::prepare_checkpoint(boost::archive::text_oarchive &archive)
  {
    Impl &m = *impl;
    // The saved states and the factorized iterate; in a time integration also
    // the accepted dynamic state (u_n, v_n, a_n, R(u_n)) and that of the
    // factorized tangent.
    Dynamics                            &d       = m.dynamics;
    std::vector<const LA::MPI::Vector *> sources = {&m.history.u_saved,
                                                    &m.history.u_previous,
                                                    &m.history.u_before,
                                                    &m.factorized.u};
    if (d.started)
      sources.insert(sources.end(),
                     {&d.u_n,
                      &d.v_n,
                      &d.a_n,
                      &d.residual_n,
                      &d.factorized_u_n,
                      &d.factorized_v_n,
                      &d.factorized_a_n});
    if (m.boundaries.any_from_end_diastole())
      sources.insert(sources.end(),
                     {&m.boundaries.support_reference,
                      &m.boundaries.release.from,
                      &m.boundaries.release.to});
    m.pending_checkpoint.vectors.attach(m.discretization.dof_handler,
                                        m.discretization.relevant,
                                        sources);
    // The tension of the factorized iterate, and the tension model's
    // accepted state of every point (its states, the stretch, the tension),
    // packed per owned cell.
    m.pending_checkpoint.cell_data.assign(m.tria.n_active_cells(), {});
    std::uint64_t longest = 0;
    for (const auto &cell : m.tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const auto &bytes =
            m.pending_checkpoint.cell_data[cell->active_cell_index()] =
              dealii::Utilities::pack(m.checkpoint_data_of(cell), false);
          longest = std::max<std::uint64_t>(longest, bytes.size());
        }
    const bool fixed = fixed_size_cell_data(m.tria);
    if (fixed)
      {
        longest = dealii::Utilities::MPI::max(longest, m.comm);
        for (auto &bytes : m.pending_checkpoint.cell_data)
          bytes = with_length(bytes, longest);
      }
    m.tria.register_data_attach(
      [&m](const CellIterator &cell, const CellStatus) {
        return m.pending_checkpoint.cell_data[cell->active_cell_index()];
      },
      /*returns_variable_size_data=*/!fixed);
    archive &m.history.n_saves &m.factorized.held &m.factorized.pressures;
    archive                                       &m.factorized.active_tension;
    archive &m.factorized.tension_time &m.factorized.tension_time_step;
    // Whether the next solve may reuse the factorization (the last one
    // converged), and whether it is of a bordered system (B0, W0 stored).
    bool     bordered = !m.factorized.volume_derivatives.empty();
    archive &m.factorized.last_solve_converged &bordered;
    archive &d.started &d.time_step &d.factorized_time_step;
    archive                         &m.boundaries.release.start;
  }


  namespace
  {
    /// Reads the cell data prepare_checkpoint() attached: the tension of the
    /// factorized iterate and the inputs of the tension model into
    /// @p factorized, the tension model's accepted state into the points.
    void
    unpack_cell_data(dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
                     QuadraturePoints &points,
                     Factorization    &factorized)
    {
      const bool         fixed  = fixed_size_cell_data(tria);
      const unsigned int handle = tria.register_data_attach(
        [](const CellIterator &, const CellStatus) {
          return std::vector<char>();
        },
        !fixed);
      const Materials::TensionModel *model = points.tension_model;
      factorized.tension.assign(tria.n_active_cells(), {});
      factorized.model_inputs.assign(model != nullptr ? tria.n_active_cells()
                                                      : 0,
                                     {});
      tria.notify_ready_to_unpack(
        handle,
        [&points, &factorized, model, fixed](const CellIterator &cell,
                                             const CellStatus,
                                             const Range &packed) {
          const Range range = fixed ? without_length(packed) : packed;
          const auto  data =
            dealii::Utilities::unpack<std::vector<std::vector<double>>>(
              range.begin(),
              range.end(),
              false);
          AssertThrow(data.size() == 3,
                      dealii::ExcMessage("The checkpoint's mechanics cell "
                                         "data are not of this version."));
          factorized.tension[cell->active_cell_index()] = data[0];
          if (model != nullptr)
            factorized.model_inputs[cell->active_cell_index()] = data[2];
          const unsigned int n = model != nullptr ? model->n_states() : 0;
          const auto         at_points = points.point_data.get_data(cell);
          AssertThrow((model == nullptr && data[1].empty()) ||
                        data[1].size() == at_points.size() * (n + 2),
                      dealii::ExcMessage(
                        "The checkpoint's tension-model states do not fit "
                        "this run (another Active tension / Model, or "
                        "another quadrature)."));
          if (model != nullptr)
            for (unsigned int q = 0; q < at_points.size(); ++q)
              {
                const double *x = data[1].data() + q * (n + 2);
                at_points[q]->tension_state.assign(x, x + n);
                at_points[q]->stretch_n     = x[n];
                at_points[q]->model_tension = x[n + 1];
              }
        });
    }

    /// The per-point active tension of the factorized iterate into the
    /// points.
    void
    restore_factorized_tension(const dealii::Triangulation<3, 3> &tria,
                               QuadraturePoints                  &points,
                               const Factorization               &factorized)
    {
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const auto  data = points.point_data.get_data(cell);
            const auto &t    = factorized.tension[cell->active_cell_index()];
            AssertThrow(t.size() == data.size(),
                        dealii::ExcMessage(
                          "The checkpoint's active tension does not fit "
                          "the quadrature of the mechanics."));
            for (unsigned int q = 0; q < data.size(); ++q)
              data[q]->tension = t[q];
          }
    }

    /// Swaps the tension model's inputs of the factorized iterate with the
    /// accepted ones (and the step), so that its tangent can be assembled;
    /// a second call swaps them back.
    void
    swap_model_inputs(const dealii::Triangulation<3, 3> &tria,
                      QuadraturePoints                  &points,
                      Factorization                     &factorized)
    {
      if (points.tension_model == nullptr)
        return;
      const unsigned int n = points.tension_model->n_states();
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const auto data = points.point_data.get_data(cell);
            auto &inputs = factorized.model_inputs[cell->active_cell_index()];
            AssertThrow(inputs.size() == data.size() * (n + 2),
                        dealii::ExcMessage(
                          "The checkpoint's tension-model inputs do not "
                          "fit the quadrature of the mechanics."));
            for (unsigned int q = 0; q < data.size(); ++q)
              {
                double *x = inputs.data() + q * (n + 2);
                for (unsigned int i = 0; i < n; ++i)
                  std::swap(data[q]->tension_state[i], x[i]);
                std::swap(data[q]->stretch_n, x[n]);
                std::swap(data[q]->calcium, x[n + 1]);
              }
          }
      std::swap(points.tension_time, factorized.tension_time);
      std::swap(points.tension_time_step, factorized.tension_time_step);
    }

    /// Swaps the accepted dynamic state and the time step with those of the
    /// factorized iterate (its mass and rate terms); a second call swaps
    /// them back.
    void
    swap_dynamic_state(Dynamics &d)
    {
      if (!d.started)
        return;
      d.u_n.swap(d.factorized_u_n);
      d.v_n.swap(d.factorized_v_n);
      d.a_n.swap(d.factorized_a_n);
      std::swap(d.time_step, d.factorized_time_step);
    }
  } // namespace


  void
  Problem::Impl::rebuild_factorization(const bool bordered)
  {
    // The tangent of the factorized iterate, assembled and factorized as the
    // Newton iteration did (the same values on the same ranks), and W0 =
    // K^-1 B0.
    u_owned = factorized.u;
    u       = u_owned;
    restore_factorized_tension(tria, points, factorized);
    // The tension model's inputs and the dynamic state of that iterate in
    // place of the accepted ones while it is assembled (swapped in, then
    // back).
    swap_dynamic_state(dynamics);
    swap_model_inputs(tria, points, factorized);
    assemble(factorized.pressures,
             factorized.active_tension,
             true,
             /*with_volume_derivative=*/bordered);
    swap_model_inputs(tria, points, factorized);
    swap_dynamic_state(dynamics);
    system.linear_solver->setup(system.tangent,
                                system.pressure_matrix.get(),
                                system.augmentation.get());
    factorize_low_rank();
    factorized.volume_derivatives.clear();
    factorized.volume_rows.clear();
    factorized.w.clear();
    if (bordered)
      {
        std::vector<LA::MPI::Vector> w(loads.cavities.size());
        for (unsigned int j = 0; j < w.size(); ++j)
          {
            w[j].reinit(discretization.owned, comm);
            linear_solve(w[j], loads.volume_derivatives[j], 0, 0.0);
          }
        factorized.volume_derivatives = loads.volume_derivatives;
        factorized.volume_rows        = loads.volume_rows;
        factorized.w                  = w;
      }
    // (assemble() marks the factorization stale.)
    factorized.held = true;
  }


  void
  Problem::load_checkpoint(boost::archive::text_iarchive &archive)
  {
    Impl    &m = *impl;
    archive &m.history.n_saves &m.factorized.held &m.factorized.pressures;
    archive                                       &m.factorized.active_tension;
    archive &m.factorized.tension_time &m.factorized.tension_time_step;
    bool                                bordered = false;
    archive &m.factorized.last_solve_converged &bordered;
    Dynamics                                   &d       = m.dynamics;
    bool                                        dynamic = false;
    double                       time_step = 0, factorized_time_step = 0;
    archive &dynamic &time_step &factorized_time_step;
    archive                     &m.boundaries.release.start;
    if (dynamic)
      m.setup_dynamics();

    const bool referred = m.boundaries.any_from_end_diastole();
    const std::vector<LA::MPI::Vector> out =
      read_attached_vectors(m.discretization.dof_handler,
                            m.discretization.owned,
                            (dynamic ? 11 : 4) + (referred ? 3 : 0));
    m.history.u_saved    = out[0];
    m.history.u_previous = out[1];
    m.history.u_before   = out[2];
    m.factorized.u       = out[3];
    if (dynamic)
      {
        d.started              = true;
        d.time_step            = time_step;
        d.factorized_time_step = factorized_time_step;
        d.u_n                  = out[4];
        d.v_n                  = out[5];
        d.a_n                  = out[6];
        d.residual_n           = out[7];
        d.factorized_u_n       = out[8];
        d.factorized_v_n       = out[9];
        d.factorized_a_n       = out[10];
      }
    if (referred)
      {
        const auto n                   = out.size();
        m.boundaries.support_reference = out[n - 3];
        m.boundaries.release.from      = out[n - 2];
        m.boundaries.release.to        = out[n - 1];
        m.boundaries.release.applied   = -1;
      }
    unpack_cell_data(m.tria, m.points, m.factorized);
    if (m.factorized.held)
      m.rebuild_factorization(bordered);
    m.u_owned = m.history.u_saved;
    m.u       = m.u_owned;
  }


  void
  Problem::finish_checkpoint()
  {
    impl->pending_checkpoint.vectors.clear();
    impl->pending_checkpoint.cell_data.clear();
  }
} // namespace systole::Mechanics
