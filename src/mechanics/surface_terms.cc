#include "mechanics/surface_terms.h"

#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>

#include "mechanics/hyperelastic_kernel.h"

#include <vector>

namespace systole::Mechanics
{
  std::vector<unsigned int>
  shape_components(const dealii::FiniteElement<3, 3> &fe)
  {
    std::vector<unsigned int> component(fe.n_dofs_per_cell());
    for (unsigned int a = 0; a < component.size(); ++a)
      component[a] = fe.system_to_component_index(a).first;
    return component;
  }

  void
  area_derivative(const dealii::Tensor<2, 3> &F,
                  const dealii::Tensor<1, 3> &N,
                  double (&A)[3][3][3])
  {
    const auto &perm = levi_civita;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int K = 0; K < 3; ++K)
          A[i][j][K] = 0.0;
    for (const auto &p : perm)
      for (const auto &r : perm)
        A[p[0]][p[1]][r[1]] += p[3] * r[3] * F[p[2]][r[2]] * N[r[0]];
  }

  void
  add_volume_flux(const dealii::FEFaceValues<3, 3>        &fe_face,
                  const std::vector<dealii::Tensor<2, 3>> &grad_u,
                  const double                             scale,
                  dealii::Vector<double>                  &vector,
                  dealii::FullMatrix<double>              *matrix)
  {
    const auto                       &fe        = fe_face.get_fe();
    const unsigned int                n         = fe.n_dofs_per_cell();
    const std::vector<unsigned int>   component = shape_components(fe);
    std::vector<dealii::Tensor<1, 3>> grad(n);
    for (const unsigned int q : fe_face.quadrature_point_indices())
      {
        const dealii::Tensor<2, 3> F =
          dealii::unit_symmetric_tensor<3>() + grad_u[q];
        const dealii::Tensor<1, 3> &N    = fe_face.normal_vector(q);
        const double                JxW  = scale * fe_face.JxW(q);
        const dealii::Tensor<1, 3>  area = dealii::cofactor(F) * N;

        // (dcof(F)[G] N)_i = A[i][j][K] G_jK.
        double A[3][3][3] = {};
        if (matrix != nullptr)
          area_derivative(F, N, A);

        // Only the displacement components (0-2) take part; a pressure field
        // of the mixed formulations (component 3) does not.
        if (matrix != nullptr)
          for (unsigned int b = 0; b < n; ++b)
            if (component[b] < 3)
              grad[b] = fe_face.shape_grad_component(b, q, component[b]);
        for (unsigned int a = 0; a < n; ++a)
          {
            const unsigned int ca = component[a];
            if (ca >= 3)
              continue;
            const double phi = fe_face.shape_value(a, q);
            if (phi == 0.0)
              continue;
            vector(a) += phi * area[ca] * JxW;
            if (matrix == nullptr)
              continue;
            for (unsigned int b = 0; b < n; ++b)
              {
                if (component[b] >= 3)
                  continue;
                const double *row  = A[ca][component[b]];
                const double value = row[0] * grad[b][0] + row[1] * grad[b][1] +
                                     row[2] * grad[b][2];
                (*matrix)(a, b) += phi * value * JxW;
              }
          }
      }
  }
} // namespace systole::Mechanics
