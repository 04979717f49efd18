#include "mechanics/cavity_volume.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/petsc_vector.h>

#include "geometry/cell_kind.h"
#include "mechanics/surface_terms.h"

namespace systole::Mechanics
{
  CavityVolume::CavityVolume(const dealii::types::boundary_id endocardium,
                             const Geometry::Plane           &lid)
    : endocardium(endocardium)
    , lid(lid)
  {}

  double
  CavityVolume::volume(const dealii::Mapping<3, 3>    &mapping,
                       const dealii::DoFHandler<3, 3> &dof_handler,
                       const LA::MPI::Vector          &u,
                       const unsigned int              n_points) const
  {
    const dealii::Quadrature<2> quadrature =
      Geometry::CellKind(dof_handler.get_triangulation())
        .face_quadrature(n_points);
    dealii::FEFaceValues<3>                  fe_face(mapping,
                                    dof_handler.get_fe(),
                                    quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_quadrature_points |
                                      dealii::update_normal_vectors |
                                      dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector displacement(0);
    std::vector<dealii::Tensor<1, 3>>        u_values(quadrature.size());
    std::vector<dealii::Tensor<2, 3>>        u_gradients(quadrature.size());

    const dealii::Tensor<1, 3> &e            = lid.normal;
    double                      local_volume = 0.0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->at_boundary())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == endocardium)
            {
              fe_face.reinit(cell, face);
              fe_face[displacement].get_function_values(u, u_values);
              fe_face[displacement].get_function_gradients(u, u_gradients);
              for (unsigned int q = 0; q < quadrature.size(); ++q)
                {
                  const dealii::Tensor<2, 3> F =
                    dealii::unit_symmetric_tensor<3>() + u_gradients[q];
                  // cof(F) N dA = J F^{-T} N dA: the deformed vector area
                  // element.
                  const dealii::Tensor<1, 3> deformed_area =
                    dealii::cofactor(F) * fe_face.normal_vector(q);
                  const dealii::Tensor<1, 3> x =
                    fe_face.quadrature_point(q) + u_values[q];
                  local_volume -= ((x - lid.point) * e) * (e * deformed_area) *
                                  fe_face.JxW(q);
                }
            }
    return dealii::Utilities::MPI::sum(local_volume,
                                       dof_handler.get_communicator());
  }

  void
  CavityVolume::derivative(const dealii::Mapping<3, 3>    &mapping,
                           const dealii::DoFHandler<3, 3> &dof_handler,
                           const LA::MPI::Vector          &u,
                           const unsigned int              n_points,
                           LA::MPI::Vector                &dV_du) const
  {
    const dealii::Quadrature<2> quadrature =
      Geometry::CellKind(dof_handler.get_triangulation())
        .face_quadrature(n_points);
    dealii::FEFaceValues<3>                  fe_face(mapping,
                                    dof_handler.get_fe(),
                                    quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_normal_vectors |
                                      dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector displacement(0);
    std::vector<dealii::Tensor<2, 3>>        u_gradients(quadrature.size());
    const unsigned int     n = dof_handler.get_fe().n_dofs_per_cell();
    dealii::Vector<double> local(n);
    std::vector<dealii::types::global_dof_index> dofs(n);

    dV_du = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->at_boundary())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == endocardium)
            {
              fe_face.reinit(cell, face);
              fe_face[displacement].get_function_gradients(u, u_gradients);
              local = 0;
              add_volume_flux(fe_face, u_gradients, -1.0, local, nullptr);
              cell->get_dof_indices(dofs);
              for (unsigned int i = 0; i < n; ++i)
                dV_du(dofs[i]) += local(i);
            }
    dV_du.compress(dealii::VectorOperation::add);
  }
} // namespace systole::Mechanics
