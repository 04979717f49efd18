#include "simulation/reference_unloader.h"

#include <deal.II/base/utilities.h>
#include <deal.II/distributed/tria.h>

#include "base/errors.h"
#include "base/logger.h"
#include "geometry/point_less.h"
#include "mechanics/problem.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"

#include <algorithm>
#include <cmath>

namespace systole
{
  /// The vertices of the whole mesh, the same table on every rank, sorted by
  /// their first reference position (so that sums over it do not depend on
  /// the partition), and where each vertex of this rank's mesh sits in it.
  class ReferenceUnloader::VertexTable
  {
  public:
    /// From the vertices of @p problem (its mesh's current positions).
    VertexTable(const Mechanics::Problem &problem,
                dealii::Triangulation<3> &tria)
    {
      const auto gathered = gather(problem, tria.get_communicator());
      for (std::size_t i = 0; i < gathered.size(); i += 6)
        X.emplace_back(gathered[i], gathered[i + 1], gathered[i + 2]);
      std::sort(X.begin(), X.end(), Geometry::PointLess());
      const auto lookup = index();
      record.assign(tria.n_vertices(), dealii::numbers::invalid_unsigned_int);
      for (const auto &cell : tria.active_cell_iterators())
        if (!cell->is_artificial())
          for (const unsigned int v : cell->vertex_indices())
            {
              const auto it = lookup.find(cell->vertex(v));
              AssertThrow(it != lookup.end(),
                          dealii::ExcMessage(
                            "Unloading: a vertex of this rank's cells is "
                            "not in the gathered vertex table (the ranks "
                            "disagree on its coordinates)."));
              record[cell->vertex_index(v)] = it->second;
            }
    }

    /// The displacement u of @p problem at every vertex of the table
    /// (collective): X holds its mesh's positions.
    std::vector<dealii::Tensor<1, 3>>
    displacements(const Mechanics::Problem &problem, const MPI_Comm comm) const
    {
      const auto                        gathered = gather(problem, comm);
      const auto                        lookup   = index();
      std::vector<dealii::Tensor<1, 3>> u(X.size());
      std::size_t                       found = 0;
      for (std::size_t i = 0; i < gathered.size(); i += 6)
        {
          const dealii::Point<3> reference(gathered[i],
                                           gathered[i + 1],
                                           gathered[i + 2]);
          const auto             it = lookup.find(reference);
          AssertThrow(it != lookup.end(),
                      dealii::ExcMessage("Unloading: a vertex of the "
                                         "mechanics is not in the table."));
          for (unsigned int d = 0; d < 3; ++d)
            u[it->second][d] = gathered[i + 3 + d] - reference[d];
          ++found;
        }
      AssertThrow(found == X.size(),
                  dealii::ExcMessage("Unloading: the mechanics returned " +
                                     std::to_string(found) + " of " +
                                     std::to_string(X.size()) + " vertices."));
      return u;
    }

    /// Move every vertex of @p tria that the table knows to its position
    /// in X (all levels: the vertices are shared).
    void
    move(dealii::Triangulation<3> &tria) const
    {
      for (const auto &cell : tria.cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          {
            const unsigned int r = record[cell->vertex_index(v)];
            if (r != dealii::numbers::invalid_unsigned_int)
              cell->vertex(v) = X[r];
          }
    }

    /// Current positions, one per vertex of the mesh [mm].
    std::vector<dealii::Point<3>> X;

  private:
    /// [X, x] of the vertices whose DoFs this rank owns, all ranks in order.
    static std::vector<double>
    gather(const Mechanics::Problem &problem, const MPI_Comm comm)
    {
      std::vector<double> mine;
      for (const auto &s : problem.vertex_states())
        for (const auto &p : {s.reference, s.deformed})
          for (unsigned int d = 0; d < 3; ++d)
            mine.push_back(p[d]);
      std::vector<double> all;
      for (const auto &part : dealii::Utilities::MPI::all_gather(comm, mine))
        all.insert(all.end(), part.begin(), part.end());
      return all;
    }

    std::map<dealii::Point<3>, unsigned int, Geometry::PointLess>
    index() const
    {
      std::map<dealii::Point<3>, unsigned int, Geometry::PointLess> lookup;
      for (unsigned int i = 0; i < X.size(); ++i)
        lookup.emplace(X[i], i);
      AssertThrow(lookup.size() == X.size(),
                  dealii::ExcMessage(
                    "Unloading: two vertices of the reference coincide "
                    "(the reference is degenerate)."));
      return lookup;
    }

    /// Per vertex index of this rank's mesh: its row in X (or invalid).
    std::vector<unsigned int> record;
  };

  namespace
  {
    double
    max_distance(const std::vector<dealii::Tensor<1, 3>> &d)
    {
      double m = 0;
      for (const auto &v : d)
        m = std::max(m, v.norm());
      return m;
    }
  } // namespace

  ReferenceUnloader::ReferenceUnloader(MechanicsModel           &model,
                                       const RunParameters      &run,
                                       const Fibres::Parameters &fibres,
                                       Logger                   &logger,
                                       const MPI_Comm            comm)
    : model(model)
    , run(run)
    , fibres(fibres)
    , logger(logger)
    , comm(comm)
  {
    AssertThrow(
      fibres.generator == "rule-based" || fibres.generator == "cartesian",
      dealii::ExcMessage(
        "Problem = " + run.problem +
        " computes the fibres on every trial reference: Fibres / Generator "
        "must be rule-based (or cartesian), not " +
        fibres.generator +
        " (the analytic rule needs the generated ellipsoid, a DTI image "
        "lives in the loaded geometry)."));
    AssertThrow(model.problem->n_cavities() == 1,
                dealii::ExcMessage(
                  "Problem = " + run.problem +
                  " unloads one cavity: Mechanics / Pressure boundary names "
                  "one boundary part (the endocardium) and the mesh has a "
                  "part 'base'."));
    // The reference is its vertices: a moved vertex must not snap back to a
    // curved manifold of the generator, and the mapping (MappingQ of the
    // flat manifold: trilinear cells) follows the moved vertices. The
    // written gmsh mesh stores the same trilinear cells.
    model.tria.set_all_manifold_ids(dealii::numbers::flat_manifold_id);
    model.tria.reset_all_manifolds();
    rebuild();
    table = std::make_unique<VertexTable>(*model.problem, model.tria);
  }

  ReferenceUnloader::~ReferenceUnloader() = default;

  void
  ReferenceUnloader::rebuild()
  {
    for (const auto &[section, seconds] : model.problem->timings())
      earlier_timings[section] += seconds;
    model.problem.reset();
    model.problem =
      std::make_unique<Mechanics::Problem>(Mechanics::Problem::Inputs{
        model.params,
        model.tria,
        model.names,
        run.polynomial_degree,
        run.mapping_degree,
        *model.passive,
        model.volumetric,
        Fibres::create_fibre_field(fibres,
                                   model.geometry.lv_shape,
                                   model.tria,
                                   model.names,
                                   &logger),
        logger});
  }

  const std::vector<dealii::Point<3>> &
  ReferenceUnloader::vertices() const
  {
    return table->X;
  }

  void
  ReferenceUnloader::set_vertices(const std::vector<dealii::Point<3>> &X)
  {
    AssertThrow(X.size() == table->X.size(), dealii::ExcInternalError());
    table->X = X;
    table->move(model.tria);
    rebuild();
  }

  std::vector<dealii::Tensor<1, 3>>
  ReferenceUnloader::displacements() const
  {
    return table->displacements(*model.problem, comm);
  }

  SolveCounts
  ReferenceUnloader::inflate(const double pressure)
  {
    LoadRamp ramp;
    ramp.pressure = pressure;
    ramp.failure =
      [&](const SolveCounts &, const double target, const std::exception &e) {
        return "Unloading: a forward solve did not converge at load fraction " +
               dealii::Utilities::to_string(target) + " after " +
               std::to_string(model.params.max_step_cuts) + " step cuts (" +
               one_line_message(e) +
               "). The reference may have become too distorted: try Unloading "
               "/ Acceleration = none or more Mechanics / Load steps.";
      };
    return model.ramp_load(ramp, logger);
  }

  UnloadingResult
  ReferenceUnloader::unload(
    const std::vector<dealii::Point<3>>                   &image,
    const UnloadingParameters                             &up,
    const std::vector<dealii::Point<3>>                   *truth,
    const std::function<void(const UnloadingIteration &)> &on_iteration)
  {
    AssertThrow(image.size() == table->X.size(), dealii::ExcInternalError());
    // X_{k+1} = X_k + omega_k R_k, R_k = x_img - X_k - u(X_k): the residual
    // of Sellier's map G(X) = x_img - u(X). Aitken: omega_k = -omega_{k-1}
    // R_{k-1}.(R_k - R_{k-1}) / |R_k - R_{k-1}|^2, the secant step of the
    // whole field along its last direction; sums over the vertex table, in
    // the same order on every rank and for every partition.
    UnloadingResult                   result;
    std::vector<dealii::Tensor<1, 3>> residual, last_residual;
    double                            omega = 1.0;
    for (unsigned int k = 0;; ++k)
      {
        UnloadingIteration it;
        it.iteration        = k;
        it.reference_volume = model.problem->cavity_volume();
        it.forward          = inflate(up.image_pressure);
        ++result.forward_solves;
        result.totals += it.forward;
        it.reloaded_volume = model.problem->cavity_volume();
        const auto u       = displacements();
        residual.assign(u.size(), dealii::Tensor<1, 3>());
        std::vector<dealii::Tensor<1, 3>> to_truth(u.size());
        for (unsigned int i = 0; i < u.size(); ++i)
          {
            residual[i] = image[i] - table->X[i] - u[i];
            if (truth)
              to_truth[i] = table->X[i] - (*truth)[i];
          }
        it.reload_error    = max_distance(residual);
        it.reference_error = truth ? max_distance(to_truth) : 0.0;

        if (k > 0 &&
            up.acceleration == UnloadingParameters::Acceleration::aitken)
          {
            double num = 0, den = 0;
            for (unsigned int i = 0; i < residual.size(); ++i)
              {
                const auto dR = residual[i] - last_residual[i];
                num += last_residual[i] * dR;
                den += dR * dR;
              }
            if (den > 0)
              omega = -omega * num / den;
          }
        const bool done   = it.reload_error <= up.tolerance;
        it.relaxation     = done ? 0.0 : omega;
        result.last       = it;
        result.iterations = k;
        on_iteration(it);
        if (done)
          return result;
        AssertThrow(k < up.max_iterations,
                    dealii::ExcMessage(
                      "Unloading did not converge in Unloading / Maximum "
                      "iterations = " +
                      std::to_string(up.max_iterations) +
                      " iterations (reload error " +
                      dealii::Utilities::to_string(it.reload_error) +
                      " mm > Unloading / Tolerance = " +
                      dealii::Utilities::to_string(up.tolerance) + " mm)."));
        std::vector<dealii::Point<3>> next = table->X;
        for (unsigned int i = 0; i < residual.size(); ++i)
          next[i] += omega * residual[i];
        last_residual = residual;
        set_vertices(next);
      }
  }

  void
  ReferenceUnloader::add_earlier_timings(
    std::vector<IO::Column> &statistics) const
  {
    for (auto &column : statistics)
      for (const auto &[section, seconds] : earlier_timings)
        if (column.name ==
            "timer: " +
              dealii::Utilities::replace_in_string(section, " / ", ": "))
          column.value += seconds;
  }
} // namespace systole
