// Matrices and node data of Monodomain: lumped mass, stiffness with the
// fibre (and optionally deformation) dependent diffusivity, stimulus regions.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/numerics/rtree.h>

#include "electrophysiology/monodomain_impl.h"
#include "geometry/mesh.h"

#include <map>

namespace systole::Electrophysiology
{
  namespace
  {
    /// Adds the cell terms of every locally owned cell of @p dofs to
    /// @p global (a vector or matrix; compressed at the end): per cell,
    /// @p fe_values is reinitialized, @p local zeroed and written by
    /// @p fill(cell), and added at the cell's DoFs.
    template <class Local, class Global, class Fill>
    void
    add_cell_terms(const dealii::DoFHandler<3> &dofs,
                   dealii::FEValues<3>         &fe_values,
                   Local                       &local,
                   Global                      &global,
                   const Fill                  &fill)
    {
      std::vector<dealii::types::global_dof_index> indices(
        fe_values.dofs_per_cell);
      for (const auto &cell : dofs.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            local = 0;
            fill(cell);
            cell->get_dof_indices(indices);
            global.add(indices, local);
          }
      global.compress(dealii::VectorOperation::add);
    }
  } // namespace


  void
  Monodomain::Impl::assemble_lumped_mass()
  {
    // A rule on the nodes (Gauss-Lobatto points for FE_Q of degree 1 and 2,
    // the vertices for P1): the mass matrix integrated with it is diagonal
    // and positive.
    const dealii::Quadrature<3> nodal =
      space.kind.nodal_quadrature(space.fe->degree);
    dealii::FEValues<3>    fe_values(mapping,
                                  *space.fe,
                                  nodal,
                                  dealii::update_values |
                                    dealii::update_JxW_values);
    const unsigned int     n = space.fe->n_dofs_per_cell();
    dealii::Vector<double> local(n);
    matrices.lumped_mass_vector.reinit(space.owned, comm);
    const auto cell_terms = [&](const auto &) {
      for (unsigned int q = 0; q < nodal.size(); ++q)
        for (unsigned int i = 0; i < n; ++i)
          local[i] += fe_values.shape_value(i, q) * fe_values.JxW(q);
    };
    add_cell_terms(space.dof_handler,
                   fe_values,
                   local,
                   matrices.lumped_mass_vector,
                   cell_terms);

    matrices.lumped_mass.resize(space.n_owned);
    {
      const LocalRead m(matrices.lumped_mass_vector);
      std::copy(m.data(),
                m.data() + space.n_owned,
                matrices.lumped_mass.begin());
    }
    for (const double m : matrices.lumped_mass)
      AssertThrow(m > 0,
                  dealii::ExcMessage("Electrophysiology: a lumped mass is not "
                                     "positive (inverted cell?)."));

    std::map<dealii::types::global_dof_index, dealii::Point<3>> support;
    dealii::DoFTools::map_dofs_to_support_points(mapping,
                                                 space.dof_handler,
                                                 support);
    space.node_positions.resize(space.n_owned);
    for (unsigned int i = 0; i < space.n_owned; ++i)
      space.node_positions[i] = support.at(space.owned.nth_index_in_set(i));
  }


  void
  Monodomain::Impl::assemble_consistent_mass()
  {
    const dealii::Quadrature<3> gauss =
      space.kind.cell_quadrature(space.fe->degree + 1);
    dealii::FEValues<3>        fe_values(mapping,
                                  *space.fe,
                                  gauss,
                                  dealii::update_values |
                                    dealii::update_JxW_values);
    const unsigned int         n = space.fe->n_dofs_per_cell();
    dealii::FullMatrix<double> local(n, n);
    matrices.mass         = 0;
    const auto cell_terms = [&](const auto &) {
      for (unsigned int q = 0; q < gauss.size(); ++q)
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            local(i, j) += fe_values.shape_value(i, q) *
                           fe_values.shape_value(j, q) * fe_values.JxW(q);
    };
    add_cell_terms(space.dof_handler,
                   fe_values,
                   local,
                   matrices.mass,
                   cell_terms);
    matrices.mass_jacobi =
      std::make_unique<dealii::PETScWrappers::PreconditionJacobi>();
    matrices.mass_jacobi->initialize(matrices.mass);
    matrices.MinvKv_work.reinit(space.owned, comm);
  }


  void
  Monodomain::Impl::evaluate_fibres(const Fibres::FibreField &fibres)
  {
    dealii::FEValues<3>             fe_values(mapping,
                                  *space.fe,
                                  space.quadrature,
                                  dealii::update_quadrature_points);
    std::vector<Fibres::FibreBasis> bases;
    space.fibre_directions.assign(tria.n_active_cells(), {});
    for (const auto &cell : space.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          fibres(cell, fe_values.get_quadrature_points(), bases);
          AssertThrow(bases.size() == space.quadrature.size(),
                      dealii::ExcInternalError());
          auto &f = space.fibre_directions[cell->active_cell_index()];
          f.resize(bases.size());
          for (unsigned int q = 0; q < bases.size(); ++q)
            f[q] = bases[q].f;
        }
  }


  void
  Monodomain::Impl::assemble_stiffness(
    const std::vector<std::vector<dealii::Tensor<2, 3>>> *deformation)
  {
    const double D_l = params.diffusivity_l(), D_t = params.diffusivity_t();
    dealii::FEValues<3>               fe_values(mapping,
                                  *space.fe,
                                  space.quadrature,
                                  dealii::update_gradients |
                                    dealii::update_JxW_values);
    const unsigned int                n = space.fe->n_dofs_per_cell();
    dealii::FullMatrix<double>        local(n, n);
    std::vector<dealii::Tensor<1, 3>> D_grad(n);
    const dealii::Tensor<2, 3> identity = dealii::unit_symmetric_tensor<3>();

    matrices.stiffness = 0;
    add_cell_terms(
      space.dof_handler,
      fe_values,
      local,
      matrices.stiffness,
      [&](const auto &cell) {
        const auto &fibres_q =
          space.fibre_directions[cell->active_cell_index()];
        const std::vector<dealii::Tensor<2, 3>> *F_cell = nullptr;
        if (deformation != nullptr &&
            !(*deformation)[cell->active_cell_index()].empty())
          {
            F_cell = &(*deformation)[cell->active_cell_index()];
            AssertThrow(F_cell->size() == 1 ||
                          F_cell->size() == space.quadrature.size(),
                        dealii::ExcMessage(
                          "Monodomain::set_deformation_gradients: give one "
                          "F per cell or one per point of "
                          "diffusion_quadrature()."));
          }
        for (unsigned int q = 0; q < space.quadrature.size(); ++q)
          {
            dealii::Tensor<2, 3> D;
            if (F_cell == nullptr)
              D = D_t * identity +
                  (D_l - D_t) * dealii::outer_product(fibres_q[q], fibres_q[q]);
            else
              {
                // Spatial diffusivity along the deformed fibre, pulled back
                // to the reference configuration: J F^-1 D(f) F^-T.
                const auto  &F = (*F_cell)[F_cell->size() == 1 ? 0 : q];
                const double J = dealii::determinant(F);
                AssertThrow(J > 0,
                            dealii::ExcMessage(
                              "Monodomain: a deformation gradient with "
                              "det F <= 0."));
                dealii::Tensor<1, 3> f = F * fibres_q[q];
                f /= f.norm();
                const dealii::Tensor<2, 3> D_spatial =
                  D_t * identity + (D_l - D_t) * dealii::outer_product(f, f);
                const dealii::Tensor<2, 3> F_inv = dealii::invert(F);
                D = J * F_inv * D_spatial * dealii::transpose(F_inv);
              }
            for (unsigned int i = 0; i < n; ++i)
              D_grad[i] = D * fe_values.shape_grad(i, q);
            const double JxW = fe_values.JxW(q);
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j < n; ++j)
                local(i, j) += fe_values.shape_grad(i, q) * D_grad[j] * JxW;
          }
      });
    matrices.gamma_stage = -1;
    matrices.gamma_amg   = -1;
  }


  void
  Monodomain::Impl::locate_stimuli(const Geometry::BoundaryNames &names)
  {
    stimulation.nodes.assign(params.stimuli.size(), {});
    for (unsigned int s = 0; s < params.stimuli.size(); ++s)
      {
        const Stimulus     &stimulus = params.stimuli[s];
        std::vector<double> distance(space.n_owned, 0.0);
        if (stimulus.region.shape == StimulusRegion::Shape::surface)
          {
            // Distance to the boundary part: to the nearest of its face
            // sample points (vertices, edge midpoints and centres of every
            // face, gathered from all ranks), within a quarter of a face's
            // size of the exact distance.
            const auto &part = stimulus.region.boundary_part;
            const auto  id   = names.id(part);
            Geometry::require_boundary(tria, names, part);
            const dealii::Quadrature<2> face_points =
              space.kind.face_sample_points();
            dealii::FEFaceValues<3>       fe_face(mapping,
                                            *space.fe,
                                            face_points,
                                            dealii::update_quadrature_points);
            std::vector<dealii::Point<3>> local_points;
            for (const auto &cell : space.dof_handler.active_cell_iterators())
              if (cell->is_locally_owned())
                for (const auto f : cell->face_indices())
                  if (cell->face(f)->at_boundary() &&
                      cell->face(f)->boundary_id() == id)
                    {
                      fe_face.reinit(cell, f);
                      for (const auto &p : fe_face.get_quadrature_points())
                        local_points.push_back(p);
                    }
            std::vector<dealii::Point<3>> points;
            for (const auto &from_rank :
                 dealii::Utilities::MPI::all_gather(comm, local_points))
              points.insert(points.end(), from_rank.begin(), from_rank.end());
            const auto tree = dealii::pack_rtree(points);
            for (unsigned int i = 0; i < space.n_owned; ++i)
              {
                std::vector<dealii::Point<3>> nearest;
                tree.query(
                  boost::geometry::index::nearest(space.node_positions[i], 1),
                  std::back_inserter(nearest));
                distance[i] = space.node_positions[i].distance(nearest.front());
              }
          }
        for (unsigned int i = 0; i < space.n_owned; ++i)
          if (stimulus.region.contains(space.node_positions[i], distance[i]))
            stimulation.nodes[s].push_back(i);
        const auto n_nodes =
          dealii::Utilities::MPI::sum(static_cast<unsigned long>(
                                        stimulation.nodes[s].size()),
                                      comm);
        AssertThrow(n_nodes > 0,
                    dealii::ExcMessage(
                      "Electrophysiology / Stimuli: the region of '" +
                      stimulus.name +
                      "' contains no node of the mesh; enlarge it or refine "
                      "the mesh."));
      }
  }
} // namespace systole::Electrophysiology
