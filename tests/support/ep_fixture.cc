#include "support/ep_fixture.h"

#include <deal.II/distributed/tria.h>
#include <deal.II/fe/mapping_q.h>

#include "base/logger.h"
#include "geometry/mesh.h"

#include <cmath>
#include <sstream>

namespace test_support
{
  using namespace systole;

  dealii::Tensor<1, 3>
  unit_vector(const unsigned int direction)
  {
    dealii::Tensor<1, 3> e;
    e[direction] = 1.0;
    return e;
  }

  EPResult
  run_ep_box(const Electrophysiology::Parameters &params,
             const EPBox                         &box,
             const double                         end_time,
             const double                         interval,
             const std::vector<dealii::Point<3>> &probes,
             const MPI_Comm                       comm)
  {
    Geometry::Parameters geometry;
    geometry.type      = Geometry::Parameters::Type::box;
    geometry.box_lower = box.lower;
    geometry.box_upper = box.upper;
    geometry.box_cells = box.cells;
    dealii::parallel::distributed::Triangulation<3> tria(comm);
    const auto                 names = Geometry::create_mesh(geometry, tria);
    const dealii::MappingQ<3>  mapping(1);
    const dealii::Tensor<1, 3> f = box.fibre;
    const Fibres::FibreField   fibres =
      [f](const auto &, const auto &points, auto &bases) {
        // Any right-handed frame with this fibre direction.
        dealii::Tensor<1, 3> other;
        other[std::abs(f[0]) < 0.9 ? 0 : 1] = 1.0;
        Fibres::FibreBasis b;
        b.f = f;
        b.s = other - (other * f) * f;
        b.s /= b.s.norm();
        b.n = dealii::cross_product_3d(b.f, b.s);
        bases.assign(points.size(), b);
      };
    std::ostringstream            sink;
    Logger                        logger(comm, sink);
    Electrophysiology::Monodomain ep(params,
                                     tria,
                                     mapping,
                                     fibres,
                                     names,
                                     logger);
    const unsigned int            n =
      static_cast<unsigned int>(std::ceil(end_time / interval - 1e-9));
    for (unsigned int k = 1; k <= n; ++k)
      ep.advance(std::min(k * interval, end_time));
    EPResult result;
    result.probes     = ep.values_at_points(probes);
    result.summary    = ep.activation_summary(0.9);
    result.statistics = ep.statistics();
    return result;
  }
} // namespace test_support
