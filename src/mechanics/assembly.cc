// Residual and consistent tangent of the quasi-static mechanics.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "base/errors.h"
#include "materials/active_stress.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem_impl.h"
#include "mechanics/surface_terms.h"

namespace systole::Mechanics
{
  double
  Problem::Impl::assemble(const double pressure,
                          const double active_tension,
                          const bool   with_matrix,
                          const bool   with_volume_derivative)
  {
    using dealii::SymmetricTensor;
    using dealii::Tensor;

    // The passive (and active) stress is integrated with the full Gauss rule;
    // the volumetric penalty with one point less per direction (selective
    // reduced integration), which relieves the volumetric locking of the
    // displacement formulation ("Volumetric integration = reduced").
    const dealii::QGauss<3> quadrature(n_q_1d);
    const dealii::QGauss<3> volumetric_quadrature(
      reduced_volumetric ? n_q_1d - 1 : n_q_1d);
    const dealii::QGauss<2> face_quadrature(n_q_face_1d);
    const auto cell_flags = dealii::update_values | dealii::update_gradients |
                            dealii::update_JxW_values;
    dealii::FEValues<3>     fe_values(mapping, fe, quadrature, cell_flags);
    dealii::FEValues<3>     fe_volumetric(mapping,
                                      fe,
                                      volumetric_quadrature,
                                      cell_flags);
    dealii::FEFaceValues<3> fe_face(mapping,
                                    fe,
                                    face_quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_normal_vectors |
                                      dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector displacement(0);

    const unsigned int         n = fe.n_dofs_per_cell();
    dealii::FullMatrix<double> cell_matrix(n, n);
    dealii::Vector<double>     cell_residual(n);
    dealii::Vector<double>     cell_volume_derivative(n);
    AssertThrow(!with_volume_derivative || cavity.has_value(),
                dealii::ExcMessage("This problem has no cavity."));
    std::vector<dealii::types::global_dof_index> dofs(n);
    std::vector<Tensor<2, 3>>                    grad_u(quadrature.size()),
      face_grad_u(face_quadrature.size());
    std::vector<Tensor<1, 3>> face_u(face_quadrature.size());

    // Per shape function at one point: component, gradient of its only
    // nonzero component, dE = sym(F^T grad phi) and C : dE.
    std::vector<unsigned int>          component(n);
    std::vector<Tensor<1, 3>>          grad_phi(n);
    std::vector<SymmetricTensor<2, 3>> dE(n), C_dE(n);
    for (unsigned int a = 0; a < n; ++a)
      component[a] = fe.system_to_component_index(a).first;

    // Adds the point q of @p values with stress S and tangent dS/dE:
    // R_a += P : grad phi_a, K_ab += dE_a : dS/dE : dE_b + S : (grad phi_a^T
    // grad phi_b) (material and geometric stiffness).
    const auto add_point = [&](const dealii::FEValues<3>   &values,
                               const unsigned int           q,
                               const Tensor<2, 3>          &F,
                               const SymmetricTensor<2, 3> &S,
                               const SymmetricTensor<4, 3> &dS_dE) {
      const Tensor<2, 3> P   = F * Tensor<2, 3>(S);
      const double       JxW = values.JxW(q);
      for (unsigned int a = 0; a < n; ++a)
        {
          grad_phi[a] = values.shape_grad(a, q);
          // dE_a = sym(F^T (e_c x grad phi)) = sym(F_c. x grad phi)
          Tensor<1, 3> Fc;
          for (unsigned int d = 0; d < 3; ++d)
            Fc[d] = F[component[a]][d];
          dE[a] = dealii::symmetrize(dealii::outer_product(Fc, grad_phi[a]));
          cell_residual(a) += (P[component[a]] * grad_phi[a]) * JxW;
        }
      if (!with_matrix)
        return;
      const Tensor<2, 3> S_full(S);
      for (unsigned int b = 0; b < n; ++b)
        C_dE[b] = dS_dE * dE[b];
      for (unsigned int a = 0; a < n; ++a)
        {
          const Tensor<1, 3> S_grad_a = S_full * grad_phi[a];
          for (unsigned int b = a; b < n; ++b)
            {
              double value = dE[a] * C_dE[b];
              if (component[a] == component[b])
                value += S_grad_a * grad_phi[b];
              cell_matrix(a, b) += value * JxW;
            }
        }
    };

    if (with_matrix)
      {
        tangent            = 0;
        have_factorization = false; // PETSc would refactorize on next solve
      }
    residual = 0;
    if (with_volume_derivative)
      volume_derivative = 0;

    unsigned int inverted = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned() || inverted)
          continue;
        fe_values.reinit(cell);
        fe_values[displacement].get_function_gradients(u, grad_u);
        cell_matrix       = 0;
        cell_residual     = 0;
        const auto &bases = fibre_bases[cell->active_cell_index()];
        const std::vector<double> *tension_field =
          active_tension_field.empty()
            ? nullptr
            : &active_tension_field[cell->active_cell_index()];

        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            Materials::PassiveInput in;
            in.F     = dealii::unit_symmetric_tensor<3>() + grad_u[q];
            in.basis = bases[q];
            if (!(dealii::determinant(in.F) > 0.0))
              {
                inverted = 1;
                break;
              }
            Materials::PassiveOutput out;
            passive_law.evaluate(in, out);
            if (!reduced_volumetric)
              volumetric_law.add_to(in.F, out.S, out.dS_dE);
            const double tension =
              active_tension + (tension_field ? (*tension_field)[q] : 0.0);
            if (tension != 0.0)
              Materials::add_active_stress(tension,
                                           params.active_transverse_fraction,
                                           in.basis,
                                           out.S);
            add_point(fe_values, q, in.F, out.S, out.dS_dE);
          }

        if (reduced_volumetric && !inverted)
          {
            fe_volumetric.reinit(cell);
            fe_volumetric[displacement].get_function_gradients(u, grad_u);
            for (const unsigned int q :
                 fe_volumetric.quadrature_point_indices())
              {
                const Tensor<2, 3> F =
                  dealii::unit_symmetric_tensor<3>() + grad_u[q];
                if (!(dealii::determinant(F) > 0.0))
                  {
                    inverted = 1;
                    break;
                  }
                SymmetricTensor<2, 3> S;
                SymmetricTensor<4, 3> dS_dE;
                volumetric_law.add_to(F, S, dS_dE);
                add_point(fe_volumetric, q, F, S, dS_dE);
              }
          }
        if (inverted)
          continue;
        if (with_matrix)
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < a; ++b)
              cell_matrix(a, b) = cell_matrix(b, a);

        // Boundary terms.
        cell_volume_derivative = 0;
        if (cell->at_boundary())
          for (const auto &face : cell->face_iterators())
            {
              if (!face->at_boundary())
                continue;
              const auto id = face->boundary_id();
              if (pressure_id && id == *pressure_id &&
                  (pressure != 0.0 || with_volume_derivative))
                {
                  fe_face.reinit(cell, face);
                  fe_face[displacement].get_function_gradients(u, face_grad_u);
                  if (with_volume_derivative)
                    add_volume_flux(fe_face,
                                    face_grad_u,
                                    -1.0,
                                    cell_volume_derivative,
                                    nullptr);
                  // R -= p dV/du, K -= p d2V/du2 with the wall normal: the
                  // pressure pushes the wall along -N (into the body).
                  if (pressure != 0.0)
                    add_volume_flux(fe_face,
                                    face_grad_u,
                                    pressure,
                                    cell_residual,
                                    with_matrix ? &cell_matrix : nullptr);
                }
              if (robin_ids.count(id) > 0)
                {
                  fe_face.reinit(cell, face);
                  fe_face[displacement].get_function_values(u, face_u);
                  const double k = params.robin_stiffness;
                  for (const unsigned int q :
                       fe_face.quadrature_point_indices())
                    {
                      const Tensor<1, 3> &N        = fe_face.normal_vector(q);
                      const double        JxW      = k * fe_face.JxW(q);
                      const Tensor<1, 3>  traction = params.robin_normal_only
                                                       ? (face_u[q] * N) * N
                                                       : face_u[q];
                      for (unsigned int a = 0; a < n; ++a)
                        {
                          const double phi_a = fe_face.shape_value(a, q);
                          if (phi_a == 0.0)
                            continue;
                          cell_residual(a) +=
                            phi_a * traction[component[a]] * JxW;
                          if (!with_matrix)
                            continue;
                          for (unsigned int b = 0; b < n; ++b)
                            {
                              const double phi_b = fe_face.shape_value(b, q);
                              const double coupling =
                                params.robin_normal_only
                                  ? N[component[a]] * N[component[b]]
                                  : (component[a] == component[b] ? 1.0 : 0.0);
                              cell_matrix(a, b) +=
                                phi_a * phi_b * coupling * JxW;
                            }
                        }
                    }
                }
            }

        cell->get_dof_indices(dofs);
        if (with_matrix)
          constraints.distribute_local_to_global(cell_matrix,
                                                 cell_residual,
                                                 dofs,
                                                 tangent,
                                                 residual);
        else
          constraints.distribute_local_to_global(cell_residual, dofs, residual);
        if (with_volume_derivative && cell->at_boundary())
          constraints.distribute_local_to_global(cell_volume_derivative,
                                                 dofs,
                                                 volume_derivative);
      }

    if (with_matrix)
      tangent.compress(dealii::VectorOperation::add);
    residual.compress(dealii::VectorOperation::add);
    if (with_volume_derivative)
      volume_derivative.compress(dealii::VectorOperation::add);

    // An inverted element on any rank fails the step on every rank.
    inverted = dealii::Utilities::MPI::max(inverted, comm);
    AssertThrow(inverted == 0, ExcInvertedElement());
    return residual.l2_norm();
  }
} // namespace systole::Mechanics
