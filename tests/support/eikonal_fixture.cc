#include "support/eikonal_fixture.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>

#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace test_support
{
  using namespace systole;

  Fibres::FibreBasis
  eikonal_block_frame()
  {
    // f, s, n: the axes rotated by 30 degrees about z, then 20 about x.
    const double         a = M_PI / 6, b = M_PI / 9;
    dealii::Tensor<1, 3> f, s;
    f[0] = std::cos(a), f[1] = std::sin(a);
    s[0] = -std::sin(a), s[1] = std::cos(a);
    const auto rotate_x = [b](const dealii::Tensor<1, 3> &v) {
      dealii::Tensor<1, 3> w;
      w[0] = v[0];
      w[1] = std::cos(b) * v[1] - std::sin(b) * v[2];
      w[2] = std::sin(b) * v[1] + std::cos(b) * v[2];
      return w;
    };
    Fibres::FibreBasis basis;
    basis.f = rotate_x(f);
    basis.s = rotate_x(s);
    basis.n = dealii::cross_product_3d(basis.f, basis.s);
    return basis;
  }

  EikonalBlockResult
  run_eikonal_block(const EikonalBlock &block, const MPI_Comm comm)
  {
    Geometry::Parameters geometry;
    geometry.type       = Geometry::Parameters::Type::box;
    geometry.box_upper  = block.upper;
    geometry.box_cells  = block.cells;
    geometry.tetrahedra = block.tetrahedra;
    const auto mesh     = Geometry::create_distributed_mesh(geometry, comm);
    const Geometry::CellKind kind(*mesh.tria);
    const auto               fe = kind.lagrange(1);
    dealii::DoFHandler<3>    dofs(*mesh.tria);
    dofs.distribute_dofs(*fe);

    const Fibres::FibreBasis frame = eikonal_block_frame();
    const Fibres::FibreField fibres =
      [frame](const auto &, const auto &points, auto &bases) {
        bases.assign(points.size(), frame);
      };
    Electrophysiology::EikonalSettings settings;
    settings.velocity_fibre        = block.v_f;
    settings.velocity_sheet        = block.v_s;
    settings.velocity_normal       = block.v_n;
    settings.endocardial_part      = block.layer_part;
    settings.endocardial_thickness = block.layer_thickness;
    settings.endocardial_velocity  = block.layer_velocity;
    Electrophysiology::EikonalSolver solver(dofs, fibres, mesh.names, settings);

    // The exact arrival time sqrt((x - x0) V^-1 (x - x0)).
    const bool plane = block.plane_normal.norm() > 0;
    const auto V_of  = [&](const dealii::Tensor<1, 3> &v) {
      const double vf = v * frame.f, vs = v * frame.s, vn = v * frame.n;
      return vf * vf * block.v_f * block.v_f + vs * vs * block.v_s * block.v_s +
             vn * vn * block.v_n * block.v_n;
    };
    // The plane front's gradient p = nu / sqrt(nu V nu): p V p = 1.
    const dealii::Tensor<1, 3> slowness =
      plane ? block.plane_normal / std::sqrt(V_of(block.plane_normal))
            : dealii::Tensor<1, 3>();
    const auto exact = [&](const dealii::Point<3> &x) {
      const dealii::Tensor<1, 3> r = x - block.source;
      if (plane)
        return block.start + slowness * r;
      const double rf = r * frame.f, rs = r * frame.s, rn = r * frame.n;
      return block.start + std::sqrt(rf * rf / (block.v_f * block.v_f) +
                                     rs * rs / (block.v_s * block.v_s) +
                                     rn * rn / (block.v_n * block.v_n));
    };
    double h = 0;
    for (unsigned int d = 0; d < 3; ++d)
      h = std::max(h, block.upper[d] / block.cells[d]);
    const double radius =
      block.exact_radius > 0 ? block.exact_radius : h * (1 + 1e-9);
    const auto         &x = solver.owned_positions();
    std::vector<double> initial(x.size(),
                                std::numeric_limits<double>::infinity());
    for (unsigned int i = 0; i < x.size(); ++i)
      {
        double distance = 0;
        for (unsigned int d = 0; d < 3; ++d)
          distance = std::max(distance, std::abs(x[i][d] - block.source[d]));
        bool boundary = false;
        for (unsigned int d = 0; d < 3; ++d)
          boundary = boundary || std::abs(x[i][d]) < 1e-9 ||
                     std::abs(x[i][d] - block.upper[d]) < 1e-9;
        if (plane ? boundary : distance <= radius)
          initial[i] = exact(x[i]);
      }
    solver.solve(initial);

    EikonalBlockResult result;
    result.n_nodes = dofs.n_dofs();
    result.rounds  = solver.statistics().rounds;
    // Every node's (x, y, z, T, exact) on every rank, in the order of the
    // positions (the DoF numbers depend on the partition).
    std::vector<std::array<double, 5>> local;
    for (unsigned int i = 0; i < x.size(); ++i)
      local.push_back(
        {{x[i][0], x[i][1], x[i][2], solver.owned_times()[i], exact(x[i])}});
    std::vector<std::array<double, 5>> all;
    for (const auto &from_rank :
         dealii::Utilities::MPI::all_gather(comm, local))
      all.insert(all.end(), from_rank.begin(), from_rank.end());
    std::sort(all.begin(), all.end());
    for (const auto &node : all)
      {
        result.times.push_back(node[3]);
        result.exact.push_back(node[4]);
        const double e   = std::abs(node[3] - node[4]);
        result.max_error = std::max(result.max_error, e);
        result.mean_error += e / all.size();
      }
    return result;
  }
} // namespace test_support
