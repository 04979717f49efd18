#include "electrophysiology/eikonal.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/rtree.h>

#include "geometry/mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <set>

namespace systole::Electrophysiology
{
  namespace
  {
    constexpr double infinity = std::numeric_limits<double>::infinity();

    double
    norm_A(const dealii::SymmetricTensor<2, 3> &A,
           const dealii::Tensor<1, 3>          &r)
    {
      return std::sqrt(std::max(0.0, r * (A * r)));
    }

    /// The minimum over the open segment y1 + λ (y0 - y1), λ in (0, 1).
    double
    edge_update(const dealii::SymmetricTensor<2, 3> &A,
                const dealii::Point<3>              &x,
                const dealii::Point<3>              &y0,
                const dealii::Point<3>              &y1,
                const double                         T0,
                const double                         T1)
    {
      const dealii::Tensor<1, 3> e = y0 - y1, d = x - y1;
      const dealii::Tensor<1, 3> Ae = A * e;
      const double               Q  = e * Ae;
      if (!(Q > 0))
        return infinity;
      const double g = T0 - T1;
      const double r = 1 - g * g / Q;
      if (!(r > 0))
        return infinity; // the interpolant outruns the front: a vertex
      const double b      = Ae * d;
      const double c      = d * (A * d);
      const double s      = std::sqrt(std::max(0.0, (c - b * b / Q) / r));
      const double lambda = (b - g * s) / Q;
      if (!(lambda > 0 && lambda < 1))
        return infinity;
      return T1 + lambda * g + norm_A(A, d - lambda * e);
    }

    /// The minimum over the open triangle y2 + λ0 (y0 - y2) + λ1 (y1 - y2).
    double
    triangle_update(const dealii::SymmetricTensor<2, 3> &A,
                    const dealii::Point<3>              &x,
                    const dealii::Point<3>              &y0,
                    const dealii::Point<3>              &y1,
                    const dealii::Point<3>              &y2,
                    const double                         T0,
                    const double                         T1,
                    const double                         T2)
    {
      const dealii::Tensor<1, 3> e0 = y0 - y2, e1 = y1 - y2, d = x - y2;
      const dealii::Tensor<1, 3> Ae0 = A * e0, Ae1 = A * e1;
      const double               Q00 = e0 * Ae0, Q01 = e0 * Ae1, Q11 = e1 * Ae1;
      const double               det = Q00 * Q11 - Q01 * Q01;
      if (!(det > 1e-12 * Q00 * Q11))
        return infinity; // degenerate triangle
      const double g0 = T0 - T2, g1 = T1 - T2;
      const double b0 = Ae0 * d, b1 = Ae1 * d;
      const double c = d * (A * d);
      // Q^-1 g and Q^-1 b.
      const double w0 = (Q11 * g0 - Q01 * g1) / det;
      const double w1 = (Q00 * g1 - Q01 * g0) / det;
      const double l0 = (Q11 * b0 - Q01 * b1) / det;
      const double l1 = (Q00 * b1 - Q01 * b0) / det;
      const double gw = g0 * w0 + g1 * w1;
      if (!(gw < 1))
        return infinity;
      // Stationary point: g = (b - Q λ)/s with s = |d - E λ|_A, so
      // λ = Q^-1 b - s Q^-1 g and s² (1 - g·Q^-1 g) = c - b·Q^-1 b.
      const double s =
        std::sqrt(std::max(0.0, (c - (b0 * l0 + b1 * l1)) / (1 - gw)));
      const double lambda0 = l0 - s * w0, lambda1 = l1 - s * w1;
      if (!(lambda0 > 0 && lambda1 > 0 && lambda0 + lambda1 < 1))
        return infinity;
      return T2 + lambda0 * g0 + lambda1 * g1 +
             norm_A(A, d - lambda0 * e0 - lambda1 * e1);
    }

    /// Per local vertex of a cell, the triangles (local vertex triples) of
    /// the part of the cell's boundary that faces away from it.
    std::vector<std::vector<std::array<unsigned int, 3>>>
    far_triangles(const bool simplex)
    {
      std::vector<std::vector<std::array<unsigned int, 3>>> triangles;
      if (simplex)
        {
          for (unsigned int a = 0; a < 4; ++a)
            {
              std::array<unsigned int, 3> face{};
              unsigned int                k = 0;
              for (unsigned int b = 0; b < 4; ++b)
                if (b != a)
                  face[k++] = b;
              triangles.push_back({face});
            }
          return triangles;
        }
      // Hexahedron: vertex v = x + 2 y + 4 z in {0, 1}^3; the far faces of
      // a are those at coordinate d = 1 - a_d.
      for (unsigned int a = 0; a < 8; ++a)
        {
          std::vector<std::array<unsigned int, 3>> list;
          for (unsigned int d = 0; d < 3; ++d)
            {
              std::vector<unsigned int> face;
              for (unsigned int v = 0; v < 8; ++v)
                if (((v >> d) & 1u) != ((a >> d) & 1u))
                  face.push_back(v);
              for (unsigned int skip = 0; skip < 4; ++skip)
                {
                  std::array<unsigned int, 3> t{};
                  unsigned int                k = 0;
                  for (unsigned int j = 0; j < 4; ++j)
                    if (j != skip)
                      t[k++] = face[j];
                  list.push_back(t);
                }
            }
          triangles.push_back(list);
        }
      return triangles;
    }
  } // namespace


  double
  eikonal_simplex_update(const dealii::SymmetricTensor<2, 3> &A,
                         const dealii::Point<3>              &x,
                         const dealii::Point<3>              *y[],
                         const double                        *T,
                         const unsigned int                   n)
  {
    // A convex function on the closed simplex: its minimum is the
    // stationary point of the interior if that lies inside, otherwise on
    // the boundary; every candidate is its value at a point of the simplex,
    // so the least candidate is the minimum.
    double best = infinity;
    for (unsigned int k = 0; k < n; ++k)
      best = std::min(best, T[k] + norm_A(A, x - *y[k]));
    if (n >= 2)
      for (unsigned int k = 0; k < n; ++k)
        for (unsigned int l = k + 1; l < n; ++l)
          best = std::min(best, edge_update(A, x, *y[k], *y[l], T[k], T[l]));
    if (n == 3)
      best =
        std::min(best,
                 triangle_update(A, x, *y[0], *y[1], *y[2], T[0], T[1], T[2]));
    return best;
  }


  namespace
  {
    struct CellTables
    {
      bool                                                  simplex;
      std::vector<std::vector<std::array<unsigned int, 3>>> triangles;
    };

    const CellTables &
    tables(const bool simplex)
    {
      static const CellTables hex{false, far_triangles(false)};
      static const CellTables tet{true, far_triangles(true)};
      return simplex ? tet : hex;
    }
  } // namespace


  namespace
  {
    /// The points of the fast endocardial layer's boundary parts (a
    /// comma-separated list; their faces' vertices and centres, gathered from
    /// every rank), in a tree.
    dealii::RTree<dealii::Point<3>>
    layer_points(const dealii::DoFHandler<3>   &dofs,
                 const Geometry::BoundaryNames &names,
                 const EikonalSettings         &settings)
    {
      AssertThrow(settings.endocardial_velocity > 0,
                  dealii::ExcMessage(
                    "Electrophysiology / Fast endocardial layer velocity "
                    "must be > 0."));
      const auto                          &tria = dofs.get_triangulation();
      std::set<dealii::types::boundary_id> ids;
      for (const auto &part :
           dealii::Utilities::split_string_list(settings.endocardial_part))
        {
          Geometry::require_boundary(tria, names, part);
          ids.insert(names.id(part));
        }
      std::vector<dealii::Point<3>> local_points;
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const auto f : cell->face_indices())
            if (cell->face(f)->at_boundary() &&
                ids.count(cell->face(f)->boundary_id()) > 0)
              {
                local_points.push_back(cell->face(f)->center());
                for (const auto v : cell->face(f)->vertex_indices())
                  local_points.push_back(cell->face(f)->vertex(v));
              }
      std::vector<dealii::Point<3>> points;
      for (const auto &from_rank :
           dealii::Utilities::MPI::all_gather(dofs.get_communicator(),
                                              local_points))
        points.insert(points.end(), from_rank.begin(), from_rank.end());
      return dealii::pack_rtree(points);
    }

    /// The metric V^-1 of every owned cell, then of the ghost cells, indexed
    /// by the active cell index: isotropic in the fast layer (the cells
    /// whose centre lies within its thickness of a point of @p layer; none
    /// when @p layer is null), from the fibres elsewhere.
    std::vector<dealii::SymmetricTensor<2, 3>>
    cell_metrics(const dealii::DoFHandler<3>           &dofs,
                 const Fibres::FibreField              &fibres,
                 const EikonalSettings                 &settings,
                 const dealii::RTree<dealii::Point<3>> *layer)
    {
      std::vector<dealii::SymmetricTensor<2, 3>> metric(
        dofs.get_triangulation().n_active_cells());
      std::vector<Fibres::FibreBasis> bases;
      for (const auto &cell : dofs.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const dealii::Point<3> centre = cell->center();
            bool                   fast   = false;
            if (layer != nullptr)
              {
                std::vector<dealii::Point<3>> nearest;
                layer->query(boost::geometry::index::nearest(centre, 1),
                             std::back_inserter(nearest));
                fast = centre.distance(nearest.front()) <=
                       settings.endocardial_thickness;
              }
            dealii::SymmetricTensor<2, 3> A;
            if (fast)
              A =
                dealii::unit_symmetric_tensor<3>() /
                (settings.endocardial_velocity * settings.endocardial_velocity);
            else
              {
                fibres(cell, {centre}, bases);
                const auto &b = bases.at(0);
                for (unsigned int i = 0; i < 3; ++i)
                  for (unsigned int j = i; j < 3; ++j)
                    A[i][j] =
                      b.f[i] * b.f[j] /
                        (settings.velocity_fibre * settings.velocity_fibre) +
                      b.s[i] * b.s[j] /
                        (settings.velocity_sheet * settings.velocity_sheet) +
                      b.n[i] * b.n[j] /
                        (settings.velocity_normal * settings.velocity_normal);
              }
            metric[cell->active_cell_index()] = A;
          }
      dealii::GridTools::exchange_cell_data_to_ghosts<
        dealii::SymmetricTensor<2, 3>,
        dealii::DoFHandler<3>>(
        dofs,
        [&](const dealii::DoFHandler<3>::active_cell_iterator &cell) {
          return metric[cell->active_cell_index()];
        },
        [&](const dealii::DoFHandler<3>::active_cell_iterator &cell,
            const dealii::SymmetricTensor<2, 3>               &A) {
          metric[cell->active_cell_index()] = A;
        });
      return metric;
    }
  } // namespace


  EikonalSolver::EikonalSolver(const dealii::DoFHandler<3>   &dofs,
                               const Fibres::FibreField      &fibres,
                               const Geometry::BoundaryNames &names,
                               const EikonalSettings         &settings)
    : dofs(dofs)
    , comm(dofs.get_communicator())
  {
    const auto &fe = dofs.get_fe();
    AssertThrow(fe.n_components() == 1 && fe.degree == 1 &&
                  fe.n_dofs_per_cell() == fe.reference_cell().n_vertices(),
                dealii::ExcMessage(
                  "The eikonal solver needs a first-order element (Q1 on "
                  "hexahedra, P1 on tetrahedra): set Electrophysiology / "
                  "Polynomial degree = 1."));
    for (const double v : {settings.velocity_fibre,
                           settings.velocity_sheet,
                           settings.velocity_normal})
      AssertThrow(v > 0,
                  dealii::ExcMessage("Electrophysiology: the conduction "
                                     "velocities must be > 0."));
    nodes_per_cell     = fe.n_dofs_per_cell();
    const bool simplex = nodes_per_cell == 4;

    locally_owned = dofs.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(dofs, locally_relevant);
    n_owned = locally_owned.n_elements();
    times.reinit(locally_owned, locally_relevant, comm);
    const auto        &partitioner = *times.get_partitioner();
    const unsigned int n_local =
      times.locally_owned_size() + partitioner.n_ghost_indices();

    // The fast endocardial layer: the distance of each owned cell's centre
    // to the boundary part.
    const bool layer =
      !settings.endocardial_part.empty() && settings.endocardial_thickness > 0;
    dealii::RTree<dealii::Point<3>> tree;
    if (layer)
      tree = layer_points(dofs, names, settings);
    const std::vector<dealii::SymmetricTensor<2, 3>> metric =
      cell_metrics(dofs, fibres, settings, layer ? &tree : nullptr);

    // The owned and ghost cells: nodes in local numbering, positions.
    position.resize(n_local);
    std::vector<dealii::types::global_dof_index> indices(nodes_per_cell);
    std::vector<unsigned int>                    count(n_local, 0);
    for (const auto &cell : dofs.active_cell_iterators())
      if (!cell->is_artificial())
        {
          cell->get_dof_indices(indices);
          for (unsigned int v = 0; v < nodes_per_cell; ++v)
            {
              // Q1 and P1: dof v sits at vertex v.
              const unsigned int i = partitioner.global_to_local(indices[v]);
              cell_nodes.push_back(i);
              position[i] = cell->vertex(v);
              ++count[i];
            }
          cell_metric.push_back(metric[cell->active_cell_index()]);
        }
    node_cells_start.assign(n_local + 1, 0);
    for (unsigned int i = 0; i < n_local; ++i)
      node_cells_start[i + 1] = node_cells_start[i] + count[i];
    node_cells.resize(node_cells_start.back());
    std::fill(count.begin(), count.end(), 0);
    for (unsigned int c = 0; c < cell_metric.size(); ++c)
      for (unsigned int v = 0; v < nodes_per_cell; ++v)
        {
          const unsigned int i = cell_nodes[c * nodes_per_cell + v];
          node_cells[node_cells_start[i] + count[i]++] = c;
        }
    owned_position.assign(position.begin(), position.begin() + n_owned);
    (void)simplex;
  }


  double
  EikonalSolver::update(const unsigned int c,
                        const unsigned int vertex,
                        const unsigned int changed) const
  {
    const auto             &triangles = tables(nodes_per_cell == 4).triangles;
    const unsigned int     *nodes     = &cell_nodes[c * nodes_per_cell];
    const auto             &A         = cell_metric[c];
    const auto             &x         = position[nodes[vertex]];
    double                  best      = infinity;
    const dealii::Point<3> *y[3];
    double                  T[3];
    for (const auto &triangle : triangles[vertex])
      {
        // Only the triangles of the node that changed give anything new.
        if (triangle[0] != changed && triangle[1] != changed &&
            triangle[2] != changed)
          continue;
        unsigned int n = 0;
        for (const unsigned int v : triangle)
          {
            const double t = times.local_element(nodes[v]);
            if (t < infinity)
              {
                y[n]   = &position[nodes[v]];
                T[n++] = t;
              }
          }
        if (n > 0)
          best = std::min(best, eikonal_simplex_update(A, x, y, T, n));
      }
    return best;
  }


  void
  EikonalSolver::solve(const std::vector<double> &initial)
  {
    const auto start = std::chrono::steady_clock::now();
    AssertThrow(initial.size() == n_owned, dealii::ExcInternalError());
    stats                      = EikonalStatistics();
    const unsigned int n_local = position.size();

    times.zero_out_ghost_values();
    for (unsigned int i = 0; i < n_owned; ++i)
      times.local_element(i) = initial[i];
    times.update_ghost_values();

    using Entry = std::pair<double, unsigned int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> active;
    for (unsigned int i = 0; i < n_local; ++i)
      if (times.local_element(i) < infinity)
        active.emplace(times.local_element(i), i);

    // A decrease counts if it exceeds round-off (a few ulp of times up to
    // seconds): updates that only shuffle the last bits do not re-open
    // the list, so the iteration ends.
    const auto decreases = [](const double candidate, const double current) {
      return current == infinity
               ? candidate < infinity
               : candidate < current - 1e-14 * (1 + std::abs(current));
    };
    std::vector<double> ghosts_before(n_local - n_owned);
    while (true)
      {
        while (!active.empty())
          {
            const auto [t, j] = active.top();
            active.pop();
            if (t != times.local_element(j))
              continue; // stale entry
            for (unsigned int k = node_cells_start[j];
                 k < node_cells_start[j + 1];
                 ++k)
              {
                const unsigned int c  = node_cells[k];
                unsigned int       jv = 0;
                while (cell_nodes[c * nodes_per_cell + jv] != j)
                  ++jv;
                for (unsigned int v = 0; v < nodes_per_cell; ++v)
                  {
                    const unsigned int i = cell_nodes[c * nodes_per_cell + v];
                    if (i == j || i >= n_owned)
                      continue;
                    ++stats.local_updates;
                    const double candidate = update(c, v, jv);
                    if (decreases(candidate, times.local_element(i)))
                      {
                        times.local_element(i) = candidate;
                        active.emplace(candidate, i);
                      }
                  }
              }
          }
        ++stats.rounds;
        // The owned values to the other ranks' ghosts; the ghosts that
        // decreased re-open the list there.
        for (unsigned int g = 0; g < ghosts_before.size(); ++g)
          ghosts_before[g] = times.local_element(n_owned + g);
        times.update_ghost_values();
        unsigned int changed = 0;
        for (unsigned int g = 0; g < ghosts_before.size(); ++g)
          {
            const double now = times.local_element(n_owned + g);
            if (now != ghosts_before[g])
              {
                ++changed;
                active.emplace(now, n_owned + g);
              }
          }
        if (dealii::Utilities::MPI::sum(changed, comm) == 0)
          break;
      }
    owned.assign(n_owned, 0);
    for (unsigned int i = 0; i < n_owned; ++i)
      owned[i] = times.local_element(i);
    stats.local_updates =
      dealii::Utilities::MPI::sum(stats.local_updates, comm);
    stats.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
  }
} // namespace systole::Electrophysiology
