#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/types.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>

#include "geometry/point_less.h"

#include <map>
#include <memory>
#include <utility>

namespace systole::Geometry
{
  /// The mid-edge nodes of a second-order tetrahedral mesh (gmsh's 10-node
  /// tetrahedra): the node of each edge, keyed by the positions of its two
  /// corners (the smaller first, in PointLess order). Positions, not vertex
  /// numbers, because they travel unchanged with the cells to every rank of
  /// a fully distributed triangulation.
  using MidEdgeTable =
    std::map<std::pair<dealii::Point<3>, dealii::Point<3>>,
             dealii::Point<3>,
             bool (*)(const std::pair<dealii::Point<3>, dealii::Point<3>> &,
                      const std::pair<dealii::Point<3>, dealii::Point<3>> &)>;

  /// An empty table with its order.
  MidEdgeTable
  make_mid_edge_table();

  /// The key of the edge between corners @p a and @p b (either order).
  std::pair<dealii::Point<3>, dealii::Point<3>>
  mid_edge_key(const dealii::Point<3> &a, const dealii::Point<3> &b);

  /// The manifold id that marks the cells of a mesh with mid-edge nodes.
  constexpr dealii::types::manifold_id mid_edge_manifold_id = 1010;

  /// A flat manifold that knows the mid-edge nodes of the coarse mesh: the
  /// new point halfway between the two corners of an edge of the table (the
  /// weights 1/2, 1/2 on two points, 0 on the others) is the file's node;
  /// every other new point is the weighted average, as on a FlatManifold.
  ///
  /// It carries the curved geometry into deal.II in the two places that ask
  /// a manifold for points: MappingFE(FE_SimplexP(2)) takes its support
  /// points from it (the corners and the mid-edge nodes: the isoparametric
  /// P2 geometry of the file), and global refinement puts the new vertices
  /// of the coarse edges on the file's nodes. Edges made by refinement are
  /// not in the table and stay straight.
  class MidEdgeManifold : public dealii::FlatManifold<3, 3>
  {
  public:
    explicit MidEdgeManifold(std::shared_ptr<const MidEdgeTable> table);

    std::unique_ptr<dealii::Manifold<3, 3>>
    clone() const override;

    dealii::Point<3>
    get_new_point(
      const dealii::ArrayView<const dealii::Point<3>> &points,
      const dealii::ArrayView<const double>           &weights) const override;

    void
    get_new_points(
      const dealii::ArrayView<const dealii::Point<3>> &points,
      const dealii::Table<2, double>                  &weights,
      dealii::ArrayView<dealii::Point<3>> new_points) const override;

    /// Number of mid-edge nodes known.
    std::size_t
    n_nodes() const
    {
      return table->size();
    }

  private:
    std::shared_ptr<const MidEdgeTable> table;
  };

  /// Marks every cell, face and edge of @p tria with mid_edge_manifold_id
  /// and attaches a MidEdgeManifold over @p table. Call it on the coarse
  /// mesh before any refinement.
  void
  attach_mid_edge_nodes(dealii::Triangulation<3, 3>        &tria,
                        std::shared_ptr<const MidEdgeTable> table);

  /// The MidEdgeManifold attached to @p tria, or nullptr (a linear mesh).
  const MidEdgeManifold *
  mid_edge_nodes(const dealii::Triangulation<3, 3> &tria);

  /// Attaches the MidEdgeManifold of @p from (if any) to @p to, a
  /// triangulation built from it whose cells keep their manifold ids (a
  /// fully distributed one).
  void
  copy_mid_edge_nodes(const dealii::Triangulation<3, 3> &from,
                      dealii::Triangulation<3, 3>       &to);
} // namespace systole::Geometry
