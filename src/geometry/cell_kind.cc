#include "geometry/cell_kind.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/fe/fe_dgp.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/fe/mapping_q_cache.h>
#include <deal.II/grid/tria.h>

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

  dealii::Quadrature<3>
  CellKind::cell_quadrature(const unsigned int n_points_1d) const
  {
    // deal.II 9.4's QGaussSimplex knows 1 to 4 points per direction and is
    // silently empty beyond.
    AssertThrow(!is_simplex || (n_points_1d >= 1 && n_points_1d <= 4),
                dealii::ExcMessage("A Gauss rule on tetrahedra has 1 to 4 "
                                   "points per direction (asked for " +
                                   std::to_string(n_points_1d) + ")."));
    if (is_simplex)
      return dealii::QGaussSimplex<3>(n_points_1d);
    return dealii::QGauss<3>(n_points_1d);
  }

  dealii::Quadrature<2>
  CellKind::face_quadrature(const unsigned int n_points_1d) const
  {
    AssertThrow(!is_simplex || (n_points_1d >= 1 && n_points_1d <= 4),
                dealii::ExcMessage("A Gauss rule on triangles has 1 to 4 "
                                   "points per direction (asked for " +
                                   std::to_string(n_points_1d) + ")."));
    if (is_simplex)
      return dealii::QGaussSimplex<2>(n_points_1d);
    return dealii::QGauss<2>(n_points_1d);
  }

  std::unique_ptr<dealii::Mapping<3, 3>>
  CellKind::mapping(const dealii::Triangulation<3, 3> &tria,
                    const unsigned int                 degree) const
  {
    if (is_simplex)
      return std::make_unique<dealii::MappingFE<3>>(dealii::FE_SimplexP<3>(1));
    auto cache = std::make_unique<dealii::MappingQCache<3>>(degree);
    cache->initialize(dealii::MappingQ<3>(degree), tria);
    return cache;
  }
} // namespace systole::Geometry
