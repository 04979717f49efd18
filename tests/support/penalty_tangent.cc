#include "support/penalty_tangent.h"

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <array>
#include <cmath>
#include <vector>

namespace test_support
{
  using dealii::Point;
  using dealii::Tensor;

  void
  distorted_box(dealii::parallel::distributed::Triangulation<3> &tria,
                const unsigned int                               n)
  {
    dealii::GridGenerator::subdivided_hyper_rectangle(tria,
                                                      {n, n, n},
                                                      Point<3>(0, 0, 0),
                                                      Point<3>(2.0, 1.5, 1.0),
                                                      true);
    // Face x = 0 keeps id 0 (colorized), the others become 1.
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && face->boundary_id() != 0)
          face->set_boundary_id(1);
    dealii::GridTools::transform(
      [](const Point<3> &p) {
        return Point<3>(p[0] + 0.08 * std::sin(2.0 * p[1] + p[2]),
                        p[1] + 0.06 * std::sin(1.5 * p[0]) * p[2],
                        p[2] + 0.05 * p[0] * p[1] * p[1]);
      },
      tria);
  }


  BoxMechanics::BoxMechanics(const MPI_Comm     comm,
                             const unsigned int n,
                             const unsigned int n_refinements)
    : tria(comm,
           dealii::Triangulation<3>::limit_level_difference_at_vertices,
           dealii::parallel::distributed::Triangulation<
             3>::construct_multigrid_hierarchy)
    , fe(std::make_unique<dealii::FESystem<3>>(dealii::FE_Q<3>(2), 3))
    , mapping(std::make_unique<dealii::MappingQ<3>>(2))
  {
    distorted_box(tria, n);
    tria.refine_global(n_refinements);
    dof_handler.reinit(tria);
    dof_handler.distribute_dofs(*fe);
    dof_handler.distribute_mg_dofs();
    owned = dof_handler.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    constraints.reinit(relevant);
    dealii::DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    dealii::VectorTools::interpolate_boundary_values(
      *mapping,
      dof_handler,
      0,
      dealii::Functions::ZeroFunction<3>(3),
      constraints);
    constraints.close();
  }


  DistributedVector
  BoxMechanics::ghosted_vector() const
  {
    return DistributedVector(owned, relevant, tria.get_communicator());
  }


  DistributedVector
  BoxMechanics::interpolate(const dealii::Function<3> &f) const
  {
    DistributedVector v = ghosted_vector();
    dealii::VectorTools::interpolate(*mapping, dof_handler, f, v);
    v.update_ghost_values();
    return v;
  }


  Bulge::Bulge()
    : dealii::Function<3>(3)
  {}


  double
  Bulge::value(const Point<3> &p, const unsigned int c) const
  {
    switch (c)
      {
        case 0:
          return 0.12 * p[0] * p[0] + 0.05 * std::sin(3.0 * p[1]) * p[2];
        case 1:
          return -0.04 * p[0] * p[1] + 0.06 * std::cos(2.0 * p[2]) * p[0];
        default:
          return 0.08 * std::sin(p[0] * p[1]) - 0.03 * p[2] * p[2];
      }
  }


  namespace
  {
    /// A_iJkL = F_iI C_IJKL F_kK + delta_ik S_JL (times JxW), the tangent of
    /// P = F S with respect to F, from S and C = dS/dE.
    void
    first_elasticity(const Tensor<2, 3>                  &F,
                     const dealii::SymmetricTensor<2, 3> &S,
                     const dealii::SymmetricTensor<4, 3> &C,
                     const double                         JxW,
                     double (&A)[3][3][3][3])
    {
      double T[3][3][3][3]; // F_iI C_IJKL
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int J = 0; J < 3; ++J)
          for (unsigned int K = 0; K < 3; ++K)
            for (unsigned int L = 0; L < 3; ++L)
              T[i][J][K][L] = F[i][0] * C[0][J][K][L] +
                              F[i][1] * C[1][J][K][L] + F[i][2] * C[2][J][K][L];
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int J = 0; J < 3; ++J)
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int L = 0; L < 3; ++L)
              A[i][J][k][L] =
                (T[i][J][0][L] * F[k][0] + T[i][J][1][L] * F[k][1] +
                 T[i][J][2][L] * F[k][2] + (i == k ? S[J][L] : 0.0)) *
                JxW;
    }
  } // namespace


  void
  setup_sparse_tangent(const dealii::DoFHandler<3>              &dof_handler,
                       const dealii::AffineConstraints<double>  &constraints,
                       dealii::PETScWrappers::MPI::SparseMatrix &K)
  {
    const MPI_Comm         comm  = dof_handler.get_communicator();
    const dealii::IndexSet owned = dof_handler.locally_owned_dofs();
    dealii::IndexSet       relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    dealii::DynamicSparsityPattern dsp(relevant);
    dealii::DoFTools::make_sparsity_pattern(dof_handler,
                                            dsp,
                                            constraints,
                                            false);
    dealii::SparsityTools::distribute_sparsity_pattern(dsp,
                                                       owned,
                                                       comm,
                                                       relevant);
    K.reinit(owned, owned, dsp, comm);
  }


  void
  assemble_penalty_tangent(const dealii::Mapping<3>                &mapping,
                           const dealii::DoFHandler<3>             &dof_handler,
                           const dealii::AffineConstraints<double> &constraints,
                           const DistributedVector                 &u,
                           const systole::Materials::PassiveLaw    &passive,
                           const systole::Materials::VolumetricLaw &volumetric,
                           dealii::PETScWrappers::MPI::SparseMatrix &K)
  {
    K                      = 0;
    const auto         &fe = dof_handler.get_fe();
    const unsigned int  n  = fe.n_dofs_per_cell();
    dealii::QGauss<3>   quadrature(3);
    dealii::FEValues<3> values(mapping,
                               fe,
                               quadrature,
                               dealii::update_gradients |
                                 dealii::update_JxW_values);
    // node_dofs[A][c]: the DoF of node A, component c.
    std::vector<std::array<unsigned int, 3>> node_dofs(n / 3);
    for (unsigned int a = 0; a < n; ++a)
      {
        const auto [c, node] = fe.system_to_component_index(a);
        node_dofs[node][c]   = a;
      }
    const unsigned int n_nodes = node_dofs.size();

    dealii::FullMatrix<double>                   cell_matrix(n, n);
    std::vector<dealii::types::global_dof_index> dofs(n);
    std::vector<std::vector<Tensor<1, 3>>>       grad_u(quadrature.size(),
                                                  std::vector<Tensor<1, 3>>(3));
    std::vector<Tensor<1, 3>>                    g(n_nodes);
    systole::Materials::PassiveInput             in;
    systole::Materials::PassiveOutput            out;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          values.reinit(cell);
          values.get_function_gradients(u, grad_u);
          cell_matrix = 0;
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              Tensor<2, 3> F;
              for (unsigned int i = 0; i < 3; ++i)
                F[i] = grad_u[q][i];
              for (unsigned int d = 0; d < 3; ++d)
                F[d][d] += 1.0;
              in.F = F;
              passive.evaluate(in, out);
              volumetric.add_to(F, out.S, out.dS_dE);
              double A[3][3][3][3];
              first_elasticity(F, out.S, out.dS_dE, values.JxW(q), A);
              for (unsigned int N = 0; N < n_nodes; ++N)
                g[N] = values.shape_grad(node_dofs[N][0], q);
              for (unsigned int M = 0; M < n_nodes; ++M)
                {
                  // h_ikL = g_M,J A_iJkL
                  double h[3][3][3];
                  for (unsigned int i = 0; i < 3; ++i)
                    for (unsigned int k = 0; k < 3; ++k)
                      for (unsigned int L = 0; L < 3; ++L)
                        h[i][k][L] = g[M][0] * A[i][0][k][L] +
                                     g[M][1] * A[i][1][k][L] +
                                     g[M][2] * A[i][2][k][L];
                  for (unsigned int N = 0; N < n_nodes; ++N)
                    for (unsigned int i = 0; i < 3; ++i)
                      for (unsigned int k = 0; k < 3; ++k)
                        cell_matrix(node_dofs[M][i], node_dofs[N][k]) +=
                          h[i][k][0] * g[N][0] + h[i][k][1] * g[N][1] +
                          h[i][k][2] * g[N][2];
                }
            }
          cell->get_dof_indices(dofs);
          constraints.distribute_local_to_global(cell_matrix, dofs, K);
        }
    K.compress(dealii::VectorOperation::add);
  }


  void
  sparse_vmult(const dealii::PETScWrappers::MPI::SparseMatrix &K,
               const DistributedVector                        &src,
               dealii::PETScWrappers::MPI::Vector             &x,
               dealii::PETScWrappers::MPI::Vector             &y,
               DistributedVector                              &dst)
  {
    const dealii::IndexSet &owned = src.locally_owned_elements();
    std::vector<dealii::types::global_dof_index> indices(owned.begin(),
                                                         owned.end());
    std::vector<double>                          buffer(indices.size());
    for (unsigned int i = 0; i < indices.size(); ++i)
      buffer[i] = src.local_element(i);
    x.set(indices, buffer);
    x.compress(dealii::VectorOperation::insert);
    K.vmult(y, x);
    y.extract_subvector_to(indices, buffer);
    for (unsigned int i = 0; i < indices.size(); ++i)
      dst.local_element(i) = buffer[i];
  }
} // namespace test_support
