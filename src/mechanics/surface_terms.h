#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace systole::Mechanics
{
  /// The volume flux of a boundary face and its derivatives: one implementation
  /// of the follower pressure load and of the cavity-volume derivative.
  ///
  /// For shape functions @f$\varphi_a@f$ (FESystem of 3 scalar elements) and
  /// the deformed area vector @f$a = \mathrm{cof}(F) N\,dA@f$ (Nanson; N the
  /// outward normal of the body), adds
  /// @f[ v_a \mathrel{+}= s \int \varphi_a\cdot \mathrm{cof}(F)N\,dA, \qquad
  ///     M_{ab} \mathrel{+}= s \int \varphi_a\cdot
  ///       \big(\partial_F \mathrm{cof}(F)[\nabla\varphi_b]\big) N\,dA @f]
  /// with @f$\partial_F\mathrm{cof}(F)[G]_{iJ} = \epsilon_{ijk}\epsilon_{JKL}
  /// G_{jK}F_{kL}@f$ (cof F is quadratic in F). With s = -1 on the
  /// endocardium, v is dV/du of the cavity volume (whose outward normal is -N)
  /// and M its derivative d2V/du2; a pressure p on the cavity then loads the
  /// wall with p v and stiffens it with -p M. The identity v = dV/du is exact
  /// for the discrete volume of CavityVolume when the basal ring stays in the
  /// lid plane (tested by finite differences).
  ///
  /// @param[in] fe_face values at the face (update_values, gradients,
  ///            normal_vectors, JxW_values)
  /// @param[in] grad_u displacement gradient at each face quadrature point
  /// @param[in] scale s
  /// @param[in,out] vector local vector v (size dofs_per_cell)
  /// @param[in,out] matrix local matrix M, or nullptr to skip it
  /// The vector component (0, 1, 2; 3: a pressure field of the mixed
  /// formulations) of each shape function of @p fe.
  std::vector<unsigned int>
  shape_components(const dealii::FiniteElement<3, 3> &fe);

  /// The derivative of the area vector cof(F) N: A[i][j][K] = eps_ijk
  /// eps_JKL F_kL N_J, so that (dcof(F)[e_j (x) g] N)_i = sum_K A[i][j][K]
  /// g_K (cof F is quadratic in F).
  void
  area_derivative(const dealii::Tensor<2, 3> &F,
                  const dealii::Tensor<1, 3> &N,
                  double (&A)[3][3][3]);

  void
  add_volume_flux(const dealii::FEFaceValues<3, 3>        &fe_face,
                  const std::vector<dealii::Tensor<2, 3>> &grad_u,
                  const double                             scale,
                  dealii::Vector<double>                  &vector,
                  dealii::FullMatrix<double>              *matrix);
} // namespace systole::Mechanics
