#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/tria.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace systole::Geometry
{
  /// "(x, y, z)" with @p significant_digits significant digits
  /// (format_number()), for messages and logs.
  std::string
  format_point(const dealii::Point<3> &p, const int significant_digits = 6);

  /// A point found in a locally owned cell.
  struct CellPoint
  {
    /// The cell (invalid if the point lies in no owned cell).
    dealii::Triangulation<3, 3>::active_cell_iterator cell;
    /// Its reference coordinates, moved into the reference cell.
    dealii::Point<3> reference;
    /// How far outside the reference cell the point was, in reference
    /// coordinates (0 inside; infinite if not found).
    double outside = 0;
  };

  /// For each of @p points, a locally owned cell of @p tria that holds it
  /// within @p tolerance (in reference coordinates: the most negative
  /// barycentric coordinate on tetrahedra, the distance to the unit cube on
  /// hexahedra), the one it lies least outside of. Correct on tetrahedra,
  /// where deal.II 9.4's GridTools searches (and RemotePointEvaluation) test
  /// the unit cube and may return a wrong cell or none. Not collective.
  std::vector<CellPoint>
  locate_in_owned_cells(const dealii::Triangulation<3, 3>   &tria,
                        const dealii::Mapping<3, 3>         &mapping,
                        const std::vector<dealii::Point<3>> &points,
                        const double                         tolerance);

  /// The rank that evaluates each of the points that every rank of @p comm
  /// located in its owned cells (@p located, the same points on every rank):
  /// the one holding it least outside of a cell, the lowest among equals;
  /// the number of ranks where none holds it. Collective.
  std::vector<unsigned int>
  evaluating_ranks(const std::vector<CellPoint> &located, const MPI_Comm comm);

  /// The points of every rank, each evaluated on the rank that owns a cell
  /// holding it (the one it lies least outside of, the lowest rank among
  /// equals): the simplex-safe counterpart of
  /// Utilities::MPI::RemotePointEvaluation with a unique mapping. The set-up
  /// gathers all points on every rank (fine for the 10^5 points of a
  /// ventricle; not for 10^8).
  class DistributedPoints
  {
  public:
    /// Fills @p values (n_points × n_components, row-major) for the
    /// @p reference points of @p cell; @p cell_index numbers the cells this
    /// rank evaluates (the same cell and points on every call: a key for
    /// what the function caches).
    using CellFunction = std::function<
      void(const unsigned int                                       cell_index,
           const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
           const std::vector<dealii::Point<3>>                     &reference,
           std::vector<double>                                     &values)>;

    /// Locate this rank's @p points. Collective.
    DistributedPoints(const dealii::Triangulation<3, 3>   &tria,
                      const dealii::Mapping<3, 3>         &mapping,
                      const std::vector<dealii::Point<3>> &points,
                      const double                         tolerance,
                      const MPI_Comm                       comm);

    /// Whether this rank's point @p i was found in the mesh.
    bool
    point_found(const unsigned int i) const
    {
      return found[i];
    }

    /// The values of @p f at this rank's points, n_components per point
    /// (NaN for a point not found). Collective.
    std::vector<double>
    evaluate(const unsigned int n_components, const CellFunction &f) const;

  private:
    MPI_Comm          comm;
    std::vector<bool> found;
    /// Points this rank evaluates, grouped by cell: the cells, where each
    /// cell's points start (numbered as evaluated), their reference
    /// coordinates.
    std::vector<dealii::Triangulation<3, 3>::active_cell_iterator> cells;
    std::vector<unsigned int>                                      cell_start;
    std::vector<std::vector<dealii::Point<3>>>                     reference;
    unsigned int n_evaluated = 0;
    /// For each requesting rank, the evaluated points it gets (in the order
    /// of its indices).
    std::map<unsigned int, std::vector<unsigned int>> sent_points;
    /// For each evaluating rank, this rank's indices it sends values for (in
    /// the order it sends them).
    std::map<unsigned int, std::vector<unsigned int>> received_indices;
  };
} // namespace systole::Geometry
