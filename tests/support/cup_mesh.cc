#include "support/cup_mesh.h"

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/linear_algebra.h"
#include "mechanics/cavity_volume.h"

#include <cmath>
#include <set>

namespace test_support
{
  namespace
  {
    /// The unrefined cup as a serial triangulation with its boundary ids.
    void
    make_coarse_cup(dealii::Triangulation<3, 3> &cup)
    {
      dealii::Triangulation<3, 3> box;
      dealii::GridGenerator::subdivided_hyper_rectangle(box,
                                                        {3u, 3u, 2u},
                                                        dealii::Point<3>(),
                                                        dealii::Point<3>(3,
                                                                         3,
                                                                         2));
      std::set<dealii::Triangulation<3, 3>::active_cell_iterator> hole;
      for (const auto &cell : box.active_cell_iterators())
        if (cell->center().distance(dealii::Point<3>(1.5, 1.5, 1.5)) < 0.1)
          hole.insert(cell);
      dealii::GridGenerator::create_triangulation_with_removed_cells(box,
                                                                     hole,
                                                                     cup);
      for (const auto &cell : cup.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const auto   x       = face->center();
              const double small   = 1e-9;
              const bool   in_hole = x[0] > 1 - small && x[0] < 2 + small &&
                                   x[1] > 1 - small && x[1] < 2 + small &&
                                   x[2] > 1 - small && x[2] < 2 - small;
              face->set_boundary_id(x[2] > 2 - small ? cup_base
                                    : in_hole        ? cup_cavity
                                                     : cup_wall);
            }
    }
  } // namespace

  void
  make_cup(dealii::Triangulation<3, 3> &tria, const unsigned int refinements)
  {
    dealii::Triangulation<3, 3> cup;
    make_coarse_cup(cup);
    tria.copy_triangulation(cup);
    tria.refine_global(refinements);
  }

  void
  make_tet_cup(dealii::Triangulation<3, 3> &tria,
               const unsigned int           refinements)
  {
    dealii::Triangulation<3, 3> cup;
    make_coarse_cup(cup);
    dealii::GridGenerator::convert_hypercube_to_simplex_mesh(cup, tria);
    tria.refine_global(refinements);
  }

  WarpingDisplacement::WarpingDisplacement(const double warp,
                                           const double phase)
    : dealii::Function<3>(3)
    , warp(warp)
    , phase(phase)
  {}

  double
  WarpingDisplacement::value(const dealii::Point<3> &p,
                             const unsigned int      c) const
  {
    const double s = p[2] / 2.0; // 0 at the bottom, 1 on the top
    switch (c)
      {
        case 0:
          return 0.1 * s * std::sin(0.9 * p[1] + phase);
        case 1:
          return 0.08 * s * std::cos(0.7 * p[0] - phase);
        default:
          return 0.25 * (p[0] - 1.5) * s + warp * s * s *
                                             std::sin(1.3 * p[0] + phase) *
                                             std::cos(1.1 * p[1] - 0.5 * phase);
      }
  }

  FanCavityStudy
  fan_cavity_study(const unsigned int refinements, const MPI_Comm comm)
  {
    dealii::parallel::distributed::Triangulation<3> tria(comm);
    make_cup(tria, refinements);
    const dealii::FESystem<3> fe(dealii::FE_Q<3>(2), 3);
    dealii::DoFHandler<3>     dof_handler(tria);
    dof_handler.distribute_dofs(fe);
    const dealii::MappingQ<3> mapping(2);
    dealii::IndexSet          relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    const auto              &owned = dof_handler.locally_owned_dofs();
    systole::LA::MPI::Vector u_owned(owned, comm), d(owned, comm),
      dV_du(owned, comm);
    dealii::VectorTools::interpolate(mapping,
                                     dof_handler,
                                     WarpingDisplacement(0.15, 0.3),
                                     u_owned);
    dealii::VectorTools::interpolate(mapping,
                                     dof_handler,
                                     WarpingDisplacement(0.3, 1.1),
                                     d);
    systole::LA::MPI::Vector u(owned, relevant, comm);
    u = u_owned;
    const systole::Mechanics::CavityVolume cavity(tria, cup_cavity, cup_base);
    cavity.derivative(mapping, dof_handler, u, 4, dV_du);
    return {cavity.n_rim_vertices(),
            cavity.volume(mapping, dof_handler, u, 4),
            dV_du * d};
  }
} // namespace test_support
