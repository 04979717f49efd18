#pragma once

// Internal to the matrix-free operators (matrix_free_tangent_impl.h): the
// pressure coupling of the mixed Q2-P1disc formulation at the quadrature
// points of the cell batches. Include it only in .cc files.

#include <deal.II/base/aligned_vector.h>
#include <deal.II/base/tensor.h>
#include <deal.II/lac/full_matrix.h>

#include <array>
#include <cstddef>
#include <vector>

namespace systole::Mechanics::internal
{
  /// The pressure rows B of a mixed formulation with a discontinuous
  /// pressure of four DoFs per cell (P1disc on hexahedra, a mapped element:
  /// its shape values at the points are the same on every cell), in the
  /// terms of a matrix-free operator on the unit-cell gradients g of a
  /// displacement (entry 3 i + alpha, point q at g[(3 i + alpha) n_q + q]):
  /// @f$(B u)_k = -\sum_q \psi_k(q)\, d_q : \hat g_q@f$ with
  /// @f$d_{q,i\alpha} = JxW \sum_J (J F^{-T})_{iJ} G_{J\alpha}@f$ (G the
  /// inverse Jacobian), the assembly's -int psi J F^-T : grad u.
  ///
  /// Per cell batch it also keeps three 4 x 4 matrices of the cell's
  /// pressure DoFs: Gamma = gamma W^-1 of the augmented Lagrangian (W = int
  /// (1/kappa + 1/mu) psi psi), C = -int psi psi / kappa, and the inverse of
  /// the Schur preconditioner's block -int w psi psi (the weights per point
  /// as the assembly's add_pressure_point()).
  template <typename VA, unsigned int n_q>
  struct PressureCoupling
  {
    static constexpr unsigned int n_p       = 4;
    static constexpr unsigned int per_batch = n_q * 9 + 3 * n_p * n_p;
    enum Matrix : unsigned int
    {
      gamma_inverse_weight = 0,
      pressure_block       = 1,
      inverse_schur        = 2
    };

    /// Whether there is a pressure (set()).
    bool
    active() const
    {
      return !storage.empty();
    }

    /// d of point @p q of batch @p batch (9 numbers).
    const VA *
    d(const unsigned int batch, const unsigned int q) const
    {
      return &storage[batch * per_batch + q * 9];
    }
    VA *
    d(const unsigned int batch, const unsigned int q)
    {
      return &storage[batch * per_batch + q * 9];
    }

    /// Matrix @p m of batch @p batch (row-major 4 x 4).
    const VA *
    matrix(const unsigned int batch, const Matrix m) const
    {
      return &storage[batch * per_batch + n_q * 9 + m * n_p * n_p];
    }
    VA *
    matrix(const unsigned int batch, const Matrix m)
    {
      return &storage[batch * per_batch + n_q * 9 + m * n_p * n_p];
    }

    /// B u of batch @p batch from the unit-cell gradients @p g.
    std::array<VA, n_p>
    rows(const unsigned int batch, const VA *g) const
    {
      std::array<VA, n_p> b;
      for (auto &x : b)
        x = 0.0;
      for (unsigned int q = 0; q < n_q; ++q)
        {
          const VA *dq  = d(batch, q);
          VA        dot = dq[0] * g[q];
          for (unsigned int a = 1; a < 9; ++a)
            dot += dq[a] * g[a * n_q + q];
          for (unsigned int k = 0; k < n_p; ++k)
            b[k] -= psi[k][q] * dot;
        }
      return b;
    }

    /// g += the gradients whose integral is B^T y (batch @p batch).
    void
    add_columns(const unsigned int         batch,
                const std::array<VA, n_p> &y,
                VA                        *g) const
    {
      for (unsigned int q = 0; q < n_q; ++q)
        {
          VA s = psi[0][q] * y[0];
          for (unsigned int k = 1; k < n_p; ++k)
            s += psi[k][q] * y[k];
          const VA *dq = d(batch, q);
          for (unsigned int a = 0; a < 9; ++a)
            g[a * n_q + q] -= s * dq[a];
        }
    }

    /// M x with M matrix @p m of batch @p batch.
    std::array<VA, n_p>
    multiply(const unsigned int         batch,
             const Matrix               m,
             const std::array<VA, n_p> &x) const
    {
      const VA           *M = matrix(batch, m);
      std::array<VA, n_p> y;
      for (unsigned int i = 0; i < n_p; ++i)
        {
          y[i] = M[i * n_p] * x[0];
          for (unsigned int j = 1; j < n_p; ++j)
            y[i] += M[i * n_p + j] * x[j];
        }
      return y;
    }

    /// The augmented Lagrangian's term: @p g += the gradients whose
    /// integral is B^T Gamma b, with @p b = B u the rows of the input (taken
    /// by rows() before g was overwritten).
    void
    add_augmentation(const unsigned int         batch,
                     const std::array<VA, n_p> &b,
                     VA                        *out) const
    {
      add_columns(batch, multiply(batch, gamma_inverse_weight, b), out);
    }

    /// Lane @p lane of batch @p batch from the points' J F^-T (@p
    /// cofactor), weights W (@p augmentation_weight: 1/kappa + 1/mu) and
    /// Schur weights w, and 1/kappa: the three matrices (d is set by the
    /// caller, vectorized). @p JxW per point of the lane.
    void
    set_matrices(const unsigned int         batch,
                 const unsigned int         lane,
                 const std::vector<double> &JxW,
                 const std::vector<double> &augmentation_weight,
                 const std::vector<double> &schur_weight,
                 const double               inverse_kappa,
                 const double               gamma)
    {
      dealii::FullMatrix<double> M(n_p, n_p), W(n_p, n_p), S(n_p, n_p);
      for (unsigned int q = 0; q < n_q; ++q)
        for (unsigned int i = 0; i < n_p; ++i)
          for (unsigned int j = 0; j < n_p; ++j)
            {
              const double pp = psi[i][q] * psi[j][q] * JxW[q];
              M(i, j) += pp;
              W(i, j) += augmentation_weight[q] * pp;
              S(i, j) -= schur_weight[q] * pp;
            }
      W.gauss_jordan();
      S.gauss_jordan();
      for (unsigned int i = 0; i < n_p; ++i)
        for (unsigned int j = 0; j < n_p; ++j)
          {
            matrix(batch, gamma_inverse_weight)[i * n_p + j][lane] =
              gamma * W(i, j);
            matrix(batch, pressure_block)[i * n_p + j][lane] =
              -inverse_kappa * M(i, j);
            matrix(batch, inverse_schur)[i * n_p + j][lane] = S(i, j);
          }
    }

    /// d of point @p q from J F^-T (@p cofactor), the inverse Jacobian and
    /// JxW (vectorized over the lanes of the batch).
    template <typename Grad>
    void
    set_d(const unsigned int batch,
          const unsigned int q,
          const Grad        &cofactor,
          const Grad        &inverse_jacobian,
          const VA          &JxW)
    {
      VA *dq = d(batch, q);
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int alpha = 0; alpha < 3; ++alpha)
          {
            VA sum = 0.0;
            for (unsigned int J = 0; J < 3; ++J)
              sum += cofactor[i][J] * inverse_jacobian[J][alpha];
            dq[3 * i + alpha] = JxW * sum;
          }
    }

    /// psi[k][q]: the pressure shape functions at the points.
    std::vector<std::array<double, n_q>> psi;
    dealii::AlignedVector<VA>            storage;
  };
} // namespace systole::Mechanics::internal
