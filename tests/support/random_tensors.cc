#include "support/random_tensors.h"

#include <cmath>

namespace test_support
{
  dealii::Tensor<2, 3>
  random_rotation(std::mt19937 &rng)
  {
    std::normal_distribution<double> normal(0.0, 1.0);
    double                           q[4];
    double                           norm = 0.0;
    do
      {
        norm = 0.0;
        for (double &qi : q)
          {
            qi = normal(rng);
            norm += qi * qi;
          }
    } while (norm < 1e-8);
    norm           = std::sqrt(norm);
    const double w = q[0] / norm, x = q[1] / norm, y = q[2] / norm,
                 z = q[3] / norm;

    dealii::Tensor<2, 3> R;
    R[0][0] = 1 - 2 * (y * y + z * z);
    R[0][1] = 2 * (x * y - w * z);
    R[0][2] = 2 * (x * z + w * y);
    R[1][0] = 2 * (x * y + w * z);
    R[1][1] = 1 - 2 * (x * x + z * z);
    R[1][2] = 2 * (y * z - w * x);
    R[2][0] = 2 * (x * z - w * y);
    R[2][1] = 2 * (y * z + w * x);
    R[2][2] = 1 - 2 * (x * x + y * y);
    return R;
  }


  dealii::Tensor<2, 3>
  random_rotation(const unsigned int seed)
  {
    std::mt19937 rng(seed);
    return random_rotation(rng);
  }


  dealii::Tensor<2, 3>
  random_deformation_gradient(const unsigned int seed, const double strain)
  {
    std::mt19937                           rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    const dealii::Tensor<2, 3>             Q = random_rotation(rng);
    while (true)
      {
        dealii::Tensor<2, 3> U;
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            U[i][j] = (i == j ? 1.0 : 0.0) + strain * uniform(rng);
        if (dealii::determinant(U) > 0.2)
          return Q * U;
      }
  }


  systole::Fibres::FibreBasis
  random_fibre_basis(const unsigned int seed)
  {
    const dealii::Tensor<2, 3>  R = random_rotation(seed);
    systole::Fibres::FibreBasis basis;
    for (unsigned int i = 0; i < 3; ++i)
      {
        basis.f[i] = R[i][0];
        basis.s[i] = R[i][1];
      }
    basis.n = dealii::cross_product_3d(basis.f, basis.s);
    return basis;
  }


  systole::Materials::PassiveInput
  random_passive_input(const unsigned int seed, const double strain)
  {
    systole::Materials::PassiveInput in;
    in.F     = random_deformation_gradient(seed, strain);
    in.basis = random_fibre_basis(seed + 1000);
    return in;
  }


  systole::Materials::PassiveInput
  identity_input(const unsigned int seed)
  {
    systole::Materials::PassiveInput in;
    in.F     = dealii::unit_symmetric_tensor<3>();
    in.basis = random_fibre_basis(seed);
    return in;
  }


  dealii::Tensor<2, 3>
  uniaxial_stretch(const dealii::Tensor<1, 3> &axis, const double stretch)
  {
    return dealii::Tensor<2, 3>(dealii::unit_symmetric_tensor<3>()) +
           (stretch - 1.0) * dealii::outer_product(axis, axis);
  }
} // namespace test_support
