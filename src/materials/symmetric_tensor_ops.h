#pragma once

// Internal to src/materials: the outer products and contractions of the
// laws' tangents on deal.II's storage of symmetric tensors, without its
// per-entry accessors (dealii::outer_product of two SymmetricTensor<2, 3>
// alone took 3.7 % of Land problem 2 at 511k DOFs, issue 40).
//
// deal.II stores a SymmetricTensor<2, 3> as its 6 independent entries, in
// the order 00, 11, 22, 01, 02, 12, and a SymmetricTensor<4, 3> as the 6 x 6
// matrix of those pairs, row-major: t[i][j][k][l] = raw[6 p(ij) + p(kl)]
// (symmetric_tensor_ops_test checks this against deal.II's accessors). A
// contraction over a pair counts the off-diagonal pairs (01, 02, 12) twice.

#include <deal.II/base/symmetric_tensor.h>

namespace systole::Materials::SymmetricOps
{
  using Rank2 = dealii::SymmetricTensor<2, 3>;
  using Rank4 = dealii::SymmetricTensor<4, 3>;

  /// Independent entries of a symmetric rank-2 tensor in 3D.
  constexpr unsigned int n = 6;

  /// The weight of a pair in a contraction: 1 on the diagonal, 2 off it.
  constexpr double
  weight(const unsigned int p)
  {
    return p < 3 ? 1.0 : 2.0;
  }

  /// t += factor (a x b).
  inline void
  add_outer(Rank4 &t, const double factor, const Rank2 &a, const Rank2 &b)
  {
    double       *T = t.begin_raw();
    const double *A = a.begin_raw();
    const double *B = b.begin_raw();
    for (unsigned int p = 0; p < n; ++p)
      {
        const double fa = factor * A[p];
        for (unsigned int q = 0; q < n; ++q)
          T[n * p + q] += fa * B[q];
      }
  }

  /// t += factor (a x b + b x a).
  inline void
  add_symmetric_outer(Rank4       &t,
                      const double factor,
                      const Rank2 &a,
                      const Rank2 &b)
  {
    double       *T = t.begin_raw();
    const double *A = a.begin_raw();
    const double *B = b.begin_raw();
    for (unsigned int p = 0; p < n; ++p)
      for (unsigned int q = 0; q < n; ++q)
        T[n * p + q] += factor * (A[p] * B[q] + B[p] * A[q]);
  }

  /// A : b, (A : b)_ij = A_ijkl b_kl.
  inline Rank2
  contract(const Rank4 &A, const Rank2 &b)
  {
    Rank2         c;
    double       *C  = c.begin_raw();
    const double *AA = A.begin_raw();
    const double *BB = b.begin_raw();
    for (unsigned int p = 0; p < n; ++p)
      {
        double sum = 0.0;
        for (unsigned int q = 0; q < n; ++q)
          sum += AA[n * p + q] * weight(q) * BB[q];
        C[p] = sum;
      }
    return c;
  }

  /// b : A, (b : A)_kl = b_ij A_ijkl.
  inline Rank2
  contract(const Rank2 &b, const Rank4 &A)
  {
    Rank2         c;
    double       *C  = c.begin_raw();
    const double *AA = A.begin_raw();
    const double *BB = b.begin_raw();
    for (unsigned int q = 0; q < n; ++q)
      {
        double sum = 0.0;
        for (unsigned int p = 0; p < n; ++p)
          sum += weight(p) * BB[p] * AA[n * p + q];
        C[q] = sum;
      }
    return c;
  }

  /// t += factor (a (.) a), (a (.) a)_ijkl = (a_ik a_jl + a_il a_jk) / 2.
  inline void
  add_symmetric_product(Rank4 &t, const double factor, const Rank2 &a)
  {
    constexpr unsigned int pair[n][2] =
      {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    double full[3][3];
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        full[i][j] = a[i][j];
    double *T = t.begin_raw();
    for (unsigned int p = 0; p < n; ++p)
      {
        const unsigned int i = pair[p][0], j = pair[p][1];
        for (unsigned int q = 0; q < n; ++q)
          {
            const unsigned int k = pair[q][0], l = pair[q][1];
            T[n * p + q] += 0.5 * factor *
                            (full[i][k] * full[j][l] + full[i][l] * full[j][k]);
          }
      }
  }
} // namespace systole::Materials::SymmetricOps
