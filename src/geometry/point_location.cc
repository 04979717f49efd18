#include "geometry/point_location.h"

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/numerics/rtree.h>

#include "base/format.h"
#include "geometry/cell_kind.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace systole::Geometry
{
  std::string
  format_point(const dealii::Point<3> &p, const int significant_digits)
  {
    return "(" + format_number(p[0], significant_digits) + ", " +
           format_number(p[1], significant_digits) + ", " +
           format_number(p[2], significant_digits) + ")";
  }

  namespace
  {
    using CellIterator = dealii::Triangulation<3, 3>::active_cell_iterator;
    constexpr double infinity = std::numeric_limits<double>::infinity();

    /// How far @p reference lies outside the reference cell.
    double
    outside(const bool simplex, const dealii::Point<3> &reference)
    {
      if (!simplex)
        return dealii::GeometryInfo<3>::distance_to_unit_cell(reference);
      const double lowest =
        std::min({1.0 - reference[0] - reference[1] - reference[2],
                  reference[0],
                  reference[1],
                  reference[2]});
      return std::max(0.0, -lowest);
    }

    /// Try @p cell for @p point; keep it in @p best if it holds the point
    /// better.
    void
    try_cell(const dealii::Mapping<3, 3> &mapping,
             const CellIterator          &cell,
             const dealii::Point<3>      &point,
             CellPoint                   &best)
    {
      dealii::Point<3> reference;
      try
        {
          reference = mapping.transform_real_to_unit_cell(cell, point);
        }
      catch (const dealii::Mapping<3, 3>::ExcTransformationFailed &)
        {
          return;
        }
      const bool   simplex  = cell->reference_cell().is_simplex();
      const double distance = outside(simplex, reference);
      if (distance < best.outside)
        best = {cell, project_to_reference_cell(simplex, reference), distance};
    }
  } // namespace


  std::vector<CellPoint>
  locate_in_owned_cells(const dealii::Triangulation<3, 3>   &tria,
                        const dealii::Mapping<3, 3>         &mapping,
                        const std::vector<dealii::Point<3>> &points,
                        const double                         tolerance)
  {
    std::vector<CellIterator>                                owned;
    std::vector<std::pair<dealii::BoundingBox<3>, unsigned>> boxes;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          boxes.emplace_back(mapping.get_bounding_box(cell), owned.size());
          owned.push_back(cell);
        }
    const auto tree = dealii::pack_rtree(boxes);

    namespace bgi = boost::geometry::index;
    std::vector<CellPoint> located(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        CellPoint best;
        best.outside = infinity;
        std::vector<std::pair<dealii::BoundingBox<3>, unsigned>> near;
        tree.query(bgi::intersects(points[i]), std::back_inserter(near));
        for (const auto &box : near)
          try_cell(mapping, owned[box.second], points[i], best);
        // A point just outside the mesh (within the tolerance) lies in no
        // box: the nearest cells.
        if (best.outside > 0)
          {
            near.clear();
            tree.query(bgi::nearest(points[i], 8), std::back_inserter(near));
            for (const auto &box : near)
              try_cell(mapping, owned[box.second], points[i], best);
          }
        if (best.outside <= tolerance)
          located[i] = best;
        else
          located[i].outside = infinity;
      }
    return located;
  }


  std::vector<unsigned int>
  evaluating_ranks(const std::vector<CellPoint> &located, const MPI_Comm comm)
  {
    const unsigned int  rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int  ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    const unsigned int  n     = located.size();
    std::vector<double> distance(n), least(n);
    for (unsigned int i = 0; i < n; ++i)
      distance[i] = located[i].outside;
    dealii::Utilities::MPI::min(dealii::ArrayView<const double>(distance),
                                comm,
                                dealii::ArrayView<double>(least));
    std::vector<unsigned int> candidate(n), owner(n);
    for (unsigned int i = 0; i < n; ++i)
      candidate[i] =
        distance[i] < infinity && distance[i] == least[i] ? rank : ranks;
    dealii::Utilities::MPI::min(dealii::ArrayView<const unsigned int>(
                                  candidate),
                                comm,
                                dealii::ArrayView<unsigned int>(owner));
    return owner;
  }


  DistributedPoints::DistributedPoints(
    const dealii::Triangulation<3, 3>   &tria,
    const dealii::Mapping<3, 3>         &mapping,
    const std::vector<dealii::Point<3>> &points,
    const double                         tolerance,
    const MPI_Comm                       comm)
    : comm(comm)
  {
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    const auto         all   = dealii::Utilities::MPI::all_gather(comm, points);
    std::vector<unsigned int>     offset(ranks + 1, 0);
    std::vector<dealii::Point<3>> flat;
    for (unsigned int r = 0; r < ranks; ++r)
      {
        flat.insert(flat.end(), all[r].begin(), all[r].end());
        offset[r + 1] = flat.size();
      }
    const auto located = locate_in_owned_cells(tria, mapping, flat, tolerance);

    const std::vector<unsigned int> owner = evaluating_ranks(located, comm);

    found.assign(points.size(), false);
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        const unsigned int o = owner[offset[rank] + i];
        found[i]             = o < ranks;
        if (found[i])
          received_indices[o].push_back(i);
      }

    // The points this rank evaluates, by requester and index (the order in
    // which the requester expects them), then grouped by cell.
    std::vector<unsigned int> mine;
    for (unsigned int r = 0; r < ranks; ++r)
      for (unsigned int i = offset[r]; i < offset[r + 1]; ++i)
        if (owner[i] == rank)
          mine.push_back(i);
    std::vector<unsigned int> order(mine.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](unsigned a, unsigned b) {
      return located[mine[a]].cell < located[mine[b]].cell;
    });
    std::vector<unsigned int> slot(mine.size());
    for (const unsigned int k : order)
      {
        const auto &at = located[mine[k]];
        if (cells.empty() || cells.back() != at.cell)
          {
            cells.push_back(at.cell);
            cell_start.push_back(n_evaluated);
            reference.emplace_back();
          }
        reference.back().push_back(at.reference);
        slot[k] = n_evaluated++;
      }
    cell_start.push_back(n_evaluated);
    // mine is in the order of (requester, index there).
    for (unsigned int k = 0; k < mine.size(); ++k)
      {
        const unsigned int r =
          std::upper_bound(offset.begin(), offset.end(), mine[k]) -
          offset.begin() - 1;
        sent_points[r].push_back(slot[k]);
      }
  }


  std::vector<double>
  DistributedPoints::evaluate(const unsigned int  n_components,
                              const CellFunction &f) const
  {
    // Evaluate cell by cell, then send each requester its values in the
    // order of its indices.
    std::vector<double> here(n_evaluated * n_components);
    std::vector<double> values;
    for (unsigned int c = 0; c < cells.size(); ++c)
      {
        f(c, cells[c], reference[c], values);
        AssertThrow(values.size() == reference[c].size() * n_components,
                    dealii::ExcInternalError());
        std::copy(values.begin(),
                  values.end(),
                  here.begin() + cell_start[c] * n_components);
      }
    std::map<unsigned int, std::vector<double>> send;
    for (const auto &[r, slots] : sent_points)
      {
        auto &out = send[r];
        out.reserve(slots.size() * n_components);
        for (const unsigned int k : slots)
          out.insert(out.end(),
                     here.begin() + k * n_components,
                     here.begin() + (k + 1) * n_components);
      }
    const auto received = dealii::Utilities::MPI::some_to_some(comm, send);

    std::vector<double> result(found.size() * n_components,
                               std::numeric_limits<double>::quiet_NaN());
    for (const auto &[r, data] : received)
      {
        const auto &indices = received_indices.at(r);
        AssertThrow(data.size() == indices.size() * n_components,
                    dealii::ExcInternalError());
        for (unsigned int j = 0; j < indices.size(); ++j)
          std::copy(data.begin() + j * n_components,
                    data.begin() + (j + 1) * n_components,
                    result.begin() + indices[j] * n_components);
      }
    return result;
  }
} // namespace systole::Geometry
