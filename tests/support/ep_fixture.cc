#include "support/ep_fixture.h"

#include <deal.II/fe/mapping.h>

#include "base/logger.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
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
             const MPI_Comm                       comm,
             const std::function<void(const Electrophysiology::Monodomain &)>
               &after_interval)
  {
    Geometry::Parameters geometry;
    geometry.type       = Geometry::Parameters::Type::box;
    geometry.box_lower  = box.lower;
    geometry.box_upper  = box.upper;
    geometry.box_cells  = box.cells;
    geometry.tetrahedra = box.tetrahedra;
    const auto  mesh    = Geometry::create_distributed_mesh(geometry, comm);
    const auto &tria    = *mesh.tria;
    const auto &names   = mesh.names;
    const auto  mapping = Geometry::CellKind(tria).mapping(tria, 1);
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
                                     *mapping,
                                     fibres,
                                     names,
                                     logger);
    const unsigned int            n =
      static_cast<unsigned int>(std::ceil(end_time / interval - 1e-9));
    if (after_interval)
      after_interval(ep);
    for (unsigned int k = 1; k <= n; ++k)
      {
        ep.advance(std::min(k * interval, end_time));
        if (after_interval)
          after_interval(ep);
      }
    EPResult result;
    result.probes     = ep.values_at_points(probes);
    result.summary    = ep.activation_summary(0.9);
    result.statistics = ep.statistics();
    result.n_dofs     = ep.n_dofs();
    return result;
  }
} // namespace test_support
