#include "geometry/mid_edge_nodes.h"

#include <deal.II/base/array_view.h>
#include <deal.II/base/table.h>
#include <deal.II/grid/tria.h>

#include <cmath>

namespace systole::Geometry
{
  namespace
  {
    bool
    key_less(const std::pair<dealii::Point<3>, dealii::Point<3>> &a,
             const std::pair<dealii::Point<3>, dealii::Point<3>> &b)
    {
      const PointLess less;
      if (less(a.first, b.first))
        return true;
      if (less(b.first, a.first))
        return false;
      return less(a.second, b.second);
    }

    /// The two points of weight 1/2 if all others weigh 0.
    bool
    edge_midpoint(const dealii::ArrayView<const double> &weights,
                  unsigned int                          &first,
                  unsigned int                          &second)
    {
      unsigned int n_half = 0;
      for (unsigned int i = 0; i < weights.size(); ++i)
        if (std::abs(weights[i] - 0.5) < 1e-12)
          {
            if (n_half == 0)
              first = i;
            else
              second = i;
            ++n_half;
          }
        else if (std::abs(weights[i]) > 1e-12)
          return false;
      return n_half == 2;
    }
  } // namespace

  MidEdgeTable
  make_mid_edge_table()
  {
    return MidEdgeTable(&key_less);
  }

  std::pair<dealii::Point<3>, dealii::Point<3>>
  mid_edge_key(const dealii::Point<3> &a, const dealii::Point<3> &b)
  {
    return PointLess()(b, a) ? std::make_pair(b, a) : std::make_pair(a, b);
  }

  MidEdgeManifold::MidEdgeManifold(std::shared_ptr<const MidEdgeTable> table)
    : table(std::move(table))
  {}

  std::unique_ptr<dealii::Manifold<3, 3>>
  MidEdgeManifold::clone() const
  {
    return std::make_unique<MidEdgeManifold>(table);
  }

  dealii::Point<3>
  MidEdgeManifold::get_new_point(
    const dealii::ArrayView<const dealii::Point<3>> &points,
    const dealii::ArrayView<const double>           &weights) const
  {
    unsigned int a = 0, b = 0;
    if (edge_midpoint(weights, a, b))
      {
        const auto found = table->find(mid_edge_key(points[a], points[b]));
        if (found != table->end())
          return found->second;
      }
    return dealii::FlatManifold<3, 3>::get_new_point(points, weights);
  }

  void
  MidEdgeManifold::get_new_points(
    const dealii::ArrayView<const dealii::Point<3>> &points,
    const dealii::Table<2, double>                  &weights,
    dealii::ArrayView<dealii::Point<3>>              new_points) const
  {
    for (unsigned int row = 0; row < weights.size(0); ++row)
      new_points[row] =
        get_new_point(points, dealii::make_array_view(weights, row));
  }

  void
  attach_mid_edge_nodes(dealii::Triangulation<3, 3>        &tria,
                        std::shared_ptr<const MidEdgeTable> table)
  {
    tria.set_all_manifold_ids(mid_edge_manifold_id);
    tria.set_manifold(mid_edge_manifold_id, MidEdgeManifold(std::move(table)));
  }

  const MidEdgeManifold *
  mid_edge_nodes(const dealii::Triangulation<3, 3> &tria)
  {
    return dynamic_cast<const MidEdgeManifold *>(
      &tria.get_manifold(mid_edge_manifold_id));
  }

  void
  copy_mid_edge_nodes(const dealii::Triangulation<3, 3> &from,
                      dealii::Triangulation<3, 3>       &to)
  {
    if (const MidEdgeManifold *manifold = mid_edge_nodes(from))
      to.set_manifold(mid_edge_manifold_id, *manifold);
  }
} // namespace systole::Geometry
