#include "geometry/cell_kind.h"

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/fe/fe_dgp.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/fe/mapping_q_cache.h>
#include <deal.II/grid/tria.h>

#include "geometry/mid_edge_nodes.h"

#include <algorithm>
#include <array>

namespace systole::Geometry
{
  CellKind::CellKind(const dealii::Triangulation<3, 3> &tria)
  {
    bool hex = tria.all_reference_cells_are_hyper_cube();
    bool tet = tria.all_reference_cells_are_simplex();
    // A rank without cells answers true to both: ask the others.
    if (const auto *parallel =
          dynamic_cast<const dealii::parallel::TriangulationBase<3, 3> *>(
            &tria))
      {
        const MPI_Comm comm = parallel->get_communicator();
        hex = dealii::Utilities::MPI::min(hex ? 1 : 0, comm) == 1;
        tet = dealii::Utilities::MPI::min(tet ? 1 : 0, comm) == 1;
      }
    AssertThrow(hex || tet,
                dealii::ExcMessage(
                  "The mesh mixes cell shapes (hexahedra, tetrahedra, "
                  "prisms or pyramids): Systole needs a mesh of one shape, "
                  "all hexahedra or all tetrahedra."));
    is_simplex = tet && !hex;
    // Every rank reads the mesh file, so each attaches the same nodes.
    curved = is_simplex && mid_edge_nodes(tria) != nullptr;
  }

  std::string
  CellKind::name() const
  {
    return is_simplex ? "tetrahedra" : "hexahedra";
  }

  std::unique_ptr<dealii::FiniteElement<3, 3>>
  CellKind::lagrange(const unsigned int degree) const
  {
    if (is_simplex)
      return std::make_unique<dealii::FE_SimplexP<3>>(degree);
    return std::make_unique<dealii::FE_Q<3>>(degree);
  }

  std::unique_ptr<dealii::FiniteElement<3, 3>>
  CellKind::discontinuous(const unsigned int degree) const
  {
    if (is_simplex)
      return std::make_unique<dealii::FE_SimplexDGP<3>>(degree);
    return std::make_unique<dealii::FE_DGP<3>>(degree);
  }

  namespace
  {
    /// The Gauss rule of @p n_points_1d points per direction on the
    /// simplex (@p simplex, a @p simplex_name) or the hypercube of @p dim.
    template <int dim>
    dealii::Quadrature<dim>
    gauss_rule(const bool         simplex,
               const char        *simplex_name,
               const unsigned int n_points_1d)
    {
      // deal.II 9.4's QGaussSimplex knows 1 to 4 points per direction and is
      // silently empty beyond.
      AssertThrow(!simplex || (n_points_1d >= 1 && n_points_1d <= 4),
                  dealii::ExcMessage(std::string("A Gauss rule on ") +
                                     simplex_name +
                                     " has 1 to 4 points per direction "
                                     "(asked for " +
                                     std::to_string(n_points_1d) + ")."));
      if (simplex)
        return dealii::QGaussSimplex<dim>(n_points_1d);
      return dealii::QGauss<dim>(n_points_1d);
    }
  } // namespace

  dealii::Quadrature<3>
  CellKind::cell_quadrature(const unsigned int n_points_1d) const
  {
    return gauss_rule<3>(is_simplex, "tetrahedra", n_points_1d);
  }

  dealii::Quadrature<2>
  CellKind::face_quadrature(const unsigned int n_points_1d) const
  {
    return gauss_rule<2>(is_simplex, "triangles", n_points_1d);
  }

  dealii::Quadrature<3>
  CellKind::nodal_quadrature(const unsigned int degree) const
  {
    if (!is_simplex)
      return dealii::QGaussLobatto<3>(degree + 1);
    AssertThrow(degree == 1,
                dealii::ExcMessage(
                  "A lumped (nodal) mass on tetrahedra needs degree 1 (P" +
                  std::to_string(degree) +
                  " gives its vertices zero weight)."));
    const std::vector<dealii::Point<3>> vertices = {dealii::Point<3>(0, 0, 0),
                                                    dealii::Point<3>(1, 0, 0),
                                                    dealii::Point<3>(0, 1, 0),
                                                    dealii::Point<3>(0, 0, 1)};
    return dealii::Quadrature<3>(vertices, std::vector<double>(4, 1.0 / 24));
  }

  dealii::Quadrature<2>
  CellKind::face_sample_points() const
  {
    if (!is_simplex)
      return dealii::QGaussLobatto<2>(3);
    const std::vector<dealii::Point<2>> points = {dealii::Point<2>(0, 0),
                                                  dealii::Point<2>(1, 0),
                                                  dealii::Point<2>(0, 1),
                                                  dealii::Point<2>(0.5, 0),
                                                  dealii::Point<2>(0.5, 0.5),
                                                  dealii::Point<2>(0, 0.5),
                                                  dealii::Point<2>(1. / 3,
                                                                   1. / 3)};
    return dealii::Quadrature<2>(points, std::vector<double>(7, 1.0 / 14));
  }

  dealii::Point<3>
  CellKind::project_to_reference_cell(const dealii::Point<3> &point) const
  {
    return Geometry::project_to_reference_cell(is_simplex, point);
  }

  dealii::Point<3>
  project_to_reference_cell(const bool simplex, const dealii::Point<3> &point)
  {
    if (!simplex)
      return dealii::GeometryInfo<3>::project_to_unit_cell(point);
    // Barycentric coordinates (1 - x - y - z, x, y, z). Clamped, they sum
    // to at least 1 (what one exceeds 1 by, the others fall below 0 by).
    std::array<double, 4> lambda = {
      {1.0 - point[0] - point[1] - point[2], point[0], point[1], point[2]}};
    bool   inside = true;
    double sum    = 0;
    for (double &l : lambda)
      {
        inside = inside && l >= 0.0 && l <= 1.0;
        l      = std::clamp(l, 0.0, 1.0);
        sum += l;
      }
    if (inside)
      return point;
    return dealii::Point<3>(lambda[1] / sum, lambda[2] / sum, lambda[3] / sum);
  }

  std::unique_ptr<dealii::Mapping<3, 3>>
  CellKind::mapping(const dealii::Triangulation<3, 3> &tria,
                    const unsigned int                 degree) const
  {
    if (is_simplex)
      return std::make_unique<dealii::MappingFE<3>>(
        dealii::FE_SimplexP<3>(mapping_degree(degree)));
    auto cache = std::make_unique<dealii::MappingQCache<3>>(degree);
    cache->initialize(dealii::MappingQ<3>(degree), tria);
    return cache;
  }
} // namespace systole::Geometry
