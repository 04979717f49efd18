// Anderson acceleration (src/mechanics/anderson.h) on linear fixed-point
// iterations, where its behaviour is known in closed form: with depth >= n
// it is GMRES on the preconditioned system and reaches the fixed point of n
// unknowns in at most n + 1 updates; a plain iteration contracts only by the
// spectral radius per update.
#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/full_matrix.h>

#include "mechanics/anderson.h"

#include <catch2/catch.hpp>

#include <cmath>

namespace
{
  using systole::LA::MPI::Vector;

  /// A fixed-point problem x = M x + b with a non-symmetric M of spectral
  /// radius about @p radius (a rotation-scaling block structure plus a
  /// triangular coupling), n unknowns.
  struct LinearMap
  {
    dealii::FullMatrix<double> M;
    std::vector<double>        b;

    LinearMap(const unsigned int n, const double radius)
      : M(n, n)
      , b(n)
    {
      for (unsigned int i = 0; i < n; ++i)
        {
          // Eigenvalues spread over [-radius, radius]; small coupling above
          // the diagonal keeps the matrix non-normal.
          M(i, i) = radius * std::cos(2.0 * i + 1.0);
          for (unsigned int j = i + 1; j < n; ++j)
            M(i, j) = 0.05 * std::sin(1.0 + i + 3.0 * j);
          b[i] = 1.0 + 0.3 * i;
        }
    }

    /// f(x) = M x + b - x, the update of the plain iteration.
    void
    update(const Vector &x, Vector &f) const
    {
      const unsigned int n = b.size();
      for (unsigned int i = 0; i < n; ++i)
        {
          double sum = b[i] - x[i];
          for (unsigned int j = 0; j < n; ++j)
            sum += M(i, j) * x[j];
          f[i] = sum;
        }
      f.compress(dealii::VectorOperation::insert);
    }
  };

  /// Updates until |f| <= tol |f_0|, at most @p limit.
  unsigned int
  iterate(const LinearMap   &map,
          const unsigned int depth,
          const unsigned int limit)
  {
    const unsigned int n = map.b.size();
    dealii::IndexSet   all(n);
    all.add_range(0, n);
    Vector x(all, MPI_COMM_SELF), f(all, MPI_COMM_SELF);
    systole::Mechanics::AndersonAcceleration anderson(depth);
    map.update(x, f);
    const double f0 = f.l2_norm();
    for (unsigned int k = 0; k < limit; ++k)
      {
        anderson.accelerate(f);
        x += f;
        anderson.record_step(f);
        map.update(x, f);
        if (f.l2_norm() <= 1e-10 * f0)
          return k + 1;
      }
    return limit;
  }
} // namespace

TEST_CASE("Anderson acceleration reaches the fixed point of a linear map of "
          "n unknowns in at most n + 1 updates with depth n",
          "[mechanics][anderson]")
{
  const unsigned int n = 6;
  const LinearMap    map(n, 0.9);
  const unsigned int plain       = iterate(map, 0, 1000);
  const unsigned int accelerated = iterate(map, n, 1000);
  // Plain: the spectral radius 0.9 needs some 200 updates for 1e-10.
  CHECK(plain > 100);
  CHECK(accelerated <= n + 1);
}

TEST_CASE("Anderson acceleration with a short history halves the updates of "
          "the plain iteration on a slowly contracting linear map",
          "[mechanics][anderson]")
{
  const LinearMap    map(40, 0.8);
  const unsigned int plain       = iterate(map, 0, 1000);
  const unsigned int accelerated = iterate(map, 5, 1000);
  const unsigned int deeper      = iterate(map, 10, 1000);
  // (107, 50 and 39 updates: the eigenvalues spread over [-0.8, 0.8], and
  // even full GMRES needs some 30 iterations there.)
  CHECK(plain > 80);
  CHECK(accelerated <= plain / 2);
  CHECK(deeper < accelerated);
}

TEST_CASE("Anderson acceleration drops dependent differences instead of "
          "dividing by zero",
          "[mechanics][anderson]")
{
  // x = b (M = 0): the first update lands on the fixed point; further
  // updates are zero, so every new difference column repeats the last one.
  dealii::IndexSet all(3);
  all.add_range(0, 3);
  Vector x(all, MPI_COMM_SELF), f(all, MPI_COMM_SELF);
  systole::Mechanics::AndersonAcceleration anderson(4);
  for (unsigned int k = 0; k < 4; ++k)
    {
      for (unsigned int i = 0; i < 3; ++i)
        f[i] = (1.0 + i) - x[i];
      f.compress(dealii::VectorOperation::insert);
      anderson.accelerate(f);
      REQUIRE(std::isfinite(f.l2_norm()));
      x += f;
      anderson.record_step(f);
    }
  for (unsigned int i = 0; i < 3; ++i)
    CHECK(x[i] == Approx(1.0 + i).epsilon(1e-12));
}

TEST_CASE("Anderson acceleration combines further unknowns' updates with the "
          "coefficients of the main ones",
          "[mechanics][anderson]")
{
  // Further unknowns y = P x (P: y_0 = x_0, y_1 = 2 x_1 - x_3) carried
  // along: their updates and steps are P f and P (step), so the
  // accelerated update of y must be P times the accelerated f at every
  // update, also once the history is full and drops its oldest differences.
  const unsigned int n = 8;
  const LinearMap    map(n, 0.85);
  dealii::IndexSet   all(n);
  all.add_range(0, n);
  Vector     x(all, MPI_COMM_SELF), f(all, MPI_COMM_SELF);
  const auto project = [](const Vector &v) {
    dealii::Vector<double> y(2);
    y[0] = v[0];
    y[1] = 2.0 * v[1] - v[3];
    return y;
  };
  systole::Mechanics::AndersonAcceleration anderson(3);
  unsigned int                             accelerated = 0;
  for (unsigned int k = 0; k < 12; ++k)
    {
      map.update(x, f);
      const Vector           plain = f;
      dealii::Vector<double> g     = project(f);
      anderson.accelerate(f, &g);
      const dealii::Vector<double> expected = project(f);
      for (unsigned int i = 0; i < 2; ++i)
        CHECK(g[i] == Approx(expected[i]).margin(1e-12 * plain.l2_norm()));
      Vector difference = f;
      difference -= plain;
      if (difference.l2_norm() > 1e-8 * plain.l2_norm())
        ++accelerated;
      x += f;
      anderson.record_step(f, &g);
    }
  // (Every update after the first is accelerated.)
  CHECK(accelerated >= 10);
}
