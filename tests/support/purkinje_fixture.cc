#include "support/purkinje_fixture.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>

#include "electrophysiology/eikonal.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace test_support
{
  using namespace systole;

  Electrophysiology::PurkinjeParameters
  small_purkinje_parameters()
  {
    Electrophysiology::PurkinjeParameters p;
    p.enabled           = true;
    p.his_point         = dealii::Point<3>(7, 0, 1);
    p.initial_direction = dealii::Tensor<1, 3>({0, 0, -1});
    p.his_length        = 3;
    p.fascicle_angles   = {-60, 60};
    p.fascicle_lengths  = {4, 4};
    p.segment_length    = 0.5;
    p.branch_length     = 2.5;
    p.branch_angle      = 25;
    p.variation         = 0.3;
    p.generations       = 5;
    p.minimum_distance  = 0.45;
    p.velocity          = 3;
    p.junction_delay    = 2;
    p.seed              = 7;
    return p;
  }


  PurkinjeRun
  run_purkinje_lv(const Electrophysiology::PurkinjeParameters &params,
                  const unsigned int                           refinements,
                  const bool                                   eikonal,
                  const MPI_Comm                               comm)
  {
    Geometry::Parameters geometry; // defaults: the Land 2015 ventricle
    geometry.global_refinements = refinements;
    const auto mesh = Geometry::create_distributed_mesh(geometry, comm);
    const auto endo = mesh.names.id(params.surface);
    const auto surface =
      Electrophysiology::TriangleSurface::gather(*mesh.tria, endo, comm);
    PurkinjeRun run;
    run.network = Electrophysiology::build_purkinje_network(surface, params, 0);
    if (!params.right.surface.empty())
      {
        const auto right =
          Electrophysiology::TriangleSurface::gather(*mesh.tria,
                                                     mesh.names.id(
                                                       params.right.surface),
                                                     comm);
        run.n_left  = run.network.nodes.size();
        run.network = Electrophysiology::merge(
          run.network,
          Electrophysiology::build_purkinje_network(right,
                                                    params.right_bundle(),
                                                    0));
      }
    // The triangles again, for the independent distance check.
    for (const auto &cell : mesh.tria->active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == endo)
            {
              const auto face = cell->face(f);
              run.triangles.push_back(
                {{face->vertex(0), face->vertex(1), face->vertex(3)}});
              run.triangles.push_back(
                {{face->vertex(0), face->vertex(3), face->vertex(2)}});
            }
    run.triangles = [&]() {
      std::vector<std::array<dealii::Point<3>, 3>> all;
      for (const auto &part :
           dealii::Utilities::MPI::all_gather(comm, run.triangles))
        all.insert(all.end(), part.begin(), part.end());
      return all;
    }();
    if (!eikonal)
      return run;

    const Geometry::CellKind kind(*mesh.tria);
    const auto               fe = kind.lagrange(1);
    dealii::DoFHandler<3>    dofs(*mesh.tria);
    dofs.distribute_dofs(*fe);
    for (const auto &cell : mesh.tria->active_cell_iterators())
      if (cell->is_locally_owned())
        for (unsigned int l = 0; l < cell->n_lines(); ++l)
          run.h = std::max(run.h, cell->line(l)->diameter());
    run.h = dealii::Utilities::MPI::max(run.h, comm);
    const Fibres::FibreField fibres =
      [](const auto &, const auto &points, auto &bases) {
        Fibres::FibreBasis frame;
        frame.f = dealii::Tensor<1, 3>({1, 0, 0});
        frame.s = dealii::Tensor<1, 3>({0, 1, 0});
        frame.n = dealii::Tensor<1, 3>({0, 0, 1});
        bases.assign(points.size(), frame);
      };
    Electrophysiology::EikonalSettings settings;
    settings.velocity_fibre  = run.velocity;
    settings.velocity_sheet  = run.velocity;
    settings.velocity_normal = run.velocity;
    Electrophysiology::EikonalSolver solver(dofs, fibres, mesh.names, settings);
    const auto                      &x = solver.owned_positions();
    std::vector<double>              initial(x.size(),
                                std::numeric_limits<double>::infinity());
    Electrophysiology::add_junction_sources(run.network, x, initial, comm);
    solver.solve(initial);
    for (const double t : solver.owned_times())
      run.n_unreached += std::isfinite(t) ? 0 : 1;
    run.n_unreached = dealii::Utilities::MPI::sum(run.n_unreached, comm);

    // The node nearest to each junction (over all ranks) and its time.
    const auto         &net = run.network;
    const double        inf = std::numeric_limits<double>::infinity();
    std::vector<double> distance(net.junctions.size(), inf);
    std::vector<std::array<double, 4>> local(net.junctions.size());
    for (unsigned int j = 0; j < net.junctions.size(); ++j)
      for (unsigned int i = 0; i < x.size(); ++i)
        {
          const double d = x[i].distance(net.nodes[net.junctions[j]]);
          if (d < distance[j])
            {
              distance[j] = d;
              local[j] = {{x[i][0], x[i][1], x[i][2], solver.owned_times()[i]}};
            }
        }
    std::vector<double> global(distance.size());
    MPI_Allreduce(distance.data(),
                  global.data(),
                  distance.size(),
                  MPI_DOUBLE,
                  MPI_MIN,
                  comm);
    const auto all   = dealii::Utilities::MPI::all_gather(comm, local);
    const auto all_d = dealii::Utilities::MPI::all_gather(comm, distance);
    run.junction_node.resize(net.junctions.size());
    run.junction_node_time.resize(net.junctions.size(), inf);
    for (unsigned int r = 0; r < all.size(); ++r)
      for (unsigned int j = 0; j < net.junctions.size(); ++j)
        if (all_d[r][j] == global[j])
          {
            run.junction_node[j] =
              dealii::Point<3>(all[r][j][0], all[r][j][1], all[r][j][2]);
            run.junction_node_time[j] = all[r][j][3];
          }
    return run;
  }


  double
  distance_to_triangle(const dealii::Point<3>                &p,
                       const std::array<dealii::Point<3>, 3> &t)
  {
    const auto segment = [&](const dealii::Point<3> &a,
                             const dealii::Point<3> &b) {
      const auto   ab = b - a;
      const double s  = std::clamp(((p - a) * ab) / ab.norm_square(), 0., 1.);
      return p.distance(a + s * ab);
    };
    // Barycentric coordinates of the foot by Cramer's rule on the normal
    // equations of p - t0 = u e1 + v e2 + w n.
    const auto   e1 = t[1] - t[0], e2 = t[2] - t[0];
    const auto   r   = p - t[0];
    const double a11 = e1 * e1, a12 = e1 * e2, a22 = e2 * e2;
    const double b1 = r * e1, b2 = r * e2;
    const double det = a11 * a22 - a12 * a12;
    const double u   = (b1 * a22 - b2 * a12) / det;
    const double v   = (a11 * b2 - a12 * b1) / det;
    if (u >= 0 && v >= 0 && u + v <= 1)
      return p.distance(t[0] + u * e1 + v * e2);
    return std::min(
      {segment(t[0], t[1]), segment(t[1], t[2]), segment(t[2], t[0])});
  }
} // namespace test_support
