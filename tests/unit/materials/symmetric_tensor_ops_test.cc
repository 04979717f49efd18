// The raw-storage operations of the laws' tangents (symmetric_tensor_ops.h)
// against deal.II's generic ones, on tensors with distinct entries: the
// storage layout they assume (6 pairs 00, 11, 22, 01, 02, 12; the rank-4
// tensor row-major over pairs) and the double weight of off-diagonal pairs
// in a contraction.

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/physics/elasticity/standard_tensors.h>

#include "materials/symmetric_tensor_ops.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

namespace
{
  using namespace systole::Materials::SymmetricOps;

  Rank2
  rank2(const double shift)
  {
    Rank2 a;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        a[i][j] = shift + 1.0 + i + 0.37 * j + 0.11 * i * j;
    return a;
  }

  /// A tensor with minor symmetries only (no major symmetry), distinct
  /// entries.
  Rank4
  rank4()
  {
    Rank4 t;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = k; l < 3; ++l)
            t[i][j][k][l] = 0.3 + i + 1.7 * j + 0.29 * k * k + 0.53 * l;
    return t;
  }

  /// The largest entry of a - b.
  double
  difference(const Rank4 &a, const Rank4 &b)
  {
    double d = 0.0;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = 0; l < 3; ++l)
            d = std::max(d, std::abs(a[i][j][k][l] - b[i][j][k][l]));
    return d;
  }
} // namespace

TEST_CASE("The raw outer products of symmetric tensors are deal.II's",
          "[materials][tensor]")
{
  const Rank2 a = rank2(0.0), b = rank2(2.5);
  const Rank4 base = rank4();

  Rank4 t = base;
  add_outer(t, 0.7, a, b);
  CHECK(difference(t, base + 0.7 * dealii::outer_product(a, b)) < 1e-13);

  t = base;
  add_symmetric_outer(t, -1.3, a, b);
  CHECK(difference(t,
                   base - 1.3 * (dealii::outer_product(a, b) +
                                 dealii::outer_product(b, a))) < 1e-12);
}

TEST_CASE("The raw contractions weigh off-diagonal pairs twice",
          "[materials][tensor]")
{
  const Rank4 A     = rank4();
  const Rank2 b     = rank2(0.4);
  const Rank2 right = contract(A, b), left = contract(b, A);
  const Rank2 right_ref = A * b, left_ref = b * A;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      {
        CHECK(right[i][j] == Approx(right_ref[i][j]).epsilon(1e-14));
        CHECK(left[i][j] == Approx(left_ref[i][j]).epsilon(1e-14));
      }
  // Without major symmetry the two differ (the test tensor tells them
  // apart).
  CHECK((right - left).norm() > 1.0);
}

TEST_CASE("The raw symmetric product C^-1 (.) C^-1 is -dC^-1/dC",
          "[materials][tensor]")
{
  dealii::Tensor<2, 3> F;
  F[0][0] = 1.1, F[0][1] = 0.2, F[0][2] = -0.1;
  F[1][0] = 0.05, F[1][1] = 0.9, F[1][2] = 0.3;
  F[2][0] = -0.2, F[2][1] = 0.1, F[2][2] = 1.2;
  const Rank2 C_inv =
    dealii::invert(dealii::symmetrize(dealii::transpose(F) * F));
  Rank4 t;
  add_symmetric_product(t, 2.0, C_inv);
  const Rank4 reference =
    -2.0 * dealii::Physics::Elasticity::StandardTensors<3>::dC_inv_dC(F);
  CHECK(difference(t, reference) < 1e-13);
}
