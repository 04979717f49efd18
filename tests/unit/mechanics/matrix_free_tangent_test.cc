// The matrix-free tangent against an independently assembled sparse tangent
// of the same law (Systole's NeoHookean + Simo-Taylor VolumetricLaw through
// FEValues), and against central differences of its own residual.
#include <deal.II/base/mpi.h>

#include "materials/neo_hookean.h"
#include "materials/volumetric_law.h"
#include "mechanics/matrix_free_multigrid.h"
#include "mechanics/matrix_free_tangent.h"
#include "support/penalty_tangent.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace systole;
using Variant = Mechanics::MatrixFreeTangent::Variant;
using Vector  = Mechanics::MatrixFreeTangent::Vector;

namespace
{
  const Mechanics::NeoHookeanPenalty law{/*mu=*/10.0, /*kappa=*/500.0};

  /// A random vector (fixed seed, entries in [-1, 1] times @p scale), zero
  /// on the constrained DoFs.
  Vector
  random_direction(const Mechanics::MatrixFreeTangent &op,
                   const test_support::BoxMechanics   &box,
                   const double                        scale)
  {
    Vector v;
    op.initialize_dof_vector(v);
    std::mt19937                           rng(42);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (unsigned int i = 0; i < v.locally_owned_size(); ++i)
      {
        const auto global = box.owned.nth_index_in_set(i);
        v.local_element(i) =
          box.constraints.is_constrained(global) ? 0.0 : scale * uniform(rng);
      }
    return v;
  }

  /// The matrix-free operator of @p variant linearized at Bulge.
  std::unique_ptr<Mechanics::MatrixFreeTangent>
  operator_at_bulge(const test_support::BoxMechanics      &box,
                    const Variant                          variant,
                    const test_support::DistributedVector &u)
  {
    auto   op = std::make_unique<Mechanics::MatrixFreeTangent>(*box.mapping,
                                                             box.dof_handler,
                                                             box.constraints,
                                                             law,
                                                             variant);
    Vector u_mf;
    op->initialize_dof_vector(u_mf);
    u_mf.copy_locally_owned_data_from(u);
    op->update(u_mf);
    return op;
  }
} // namespace


TEST_CASE("The matrix-free tangent equals the assembled sparse tangent of the "
          "same law",
          "[mechanics][matrix-free]")
{
  const test_support::BoxMechanics box(MPI_COMM_WORLD, 4);
  const auto                       u = box.interpolate(test_support::Bulge());

  Materials::NeoHookean::Parameters neo_hookean;
  neo_hookean.mu = law.mu;
  const Materials::NeoHookean    passive(neo_hookean);
  const Materials::VolumetricLaw volumetric(
    Materials::VolumetricLaw::Form::simo_taylor,
    law.bulk_modulus);
  dealii::PETScWrappers::MPI::SparseMatrix K;
  test_support::setup_sparse_tangent(box.dof_handler, box.constraints, K);
  test_support::assemble_penalty_tangent(*box.mapping,
                                         box.dof_handler,
                                         box.constraints,
                                         u,
                                         passive,
                                         volumetric,
                                         K);
  dealii::PETScWrappers::MPI::Vector x(box.owned, MPI_COMM_WORLD), y(x);

  for (const Variant variant :
       {Variant::cached, Variant::cached_single, Variant::recompute})
    {
      const auto   op = operator_at_bulge(box, variant, u);
      const Vector v  = random_direction(*op, box, 1.0);
      Vector       mf(v), sparse(v);
      op->vmult(mf, v);
      test_support::sparse_vmult(K, v, x, y, sparse);
      const double reference = sparse.l2_norm();
      REQUIRE(reference > 1.0);
      mf -= sparse;
      const double error = mf.l2_norm() / reference;
      INFO("variant " << static_cast<int>(variant) << ": " << error);
      if (variant == Variant::cached_single)
        {
          // Rounded to single precision (unit roundoff 6e-8), not exact.
          CHECK(error < 1e-6);
          CHECK(error > 1e-12);
        }
      else
        CHECK(error < 1e-10);
    }
}


TEST_CASE("The matrix-free tangent is the derivative of the matrix-free "
          "residual (central differences of order 2)",
          "[mechanics][matrix-free][fd]")
{
  const test_support::BoxMechanics box(MPI_COMM_WORLD, 3);
  const auto                       u = box.interpolate(test_support::Bulge());

  for (const Variant variant : {Variant::cached, Variant::recompute})
    {
      const auto   op = operator_at_bulge(box, variant, u);
      const Vector v  = random_direction(*op, box, 0.01);
      Vector       Kv(v);
      op->vmult(Kv, v);
      // vmult() copies the (zero) constrained entries of v; the residual
      // has zero constrained rows: the two agree there.

      Mechanics::MatrixFreeTangent probe(*box.mapping,
                                         box.dof_handler,
                                         box.constraints,
                                         law,
                                         variant);
      Vector                       u_mf, plus, minus;
      probe.initialize_dof_vector(u_mf);
      plus.reinit(u_mf);
      minus.reinit(u_mf);
      std::vector<double> errors;
      for (const double epsilon : {0.2, 0.1, 0.05})
        {
          u_mf.copy_locally_owned_data_from(u);
          u_mf.add(epsilon, v);
          probe.update(u_mf);
          probe.residual(plus);
          u_mf.add(-2.0 * epsilon, v);
          probe.update(u_mf);
          probe.residual(minus);
          plus -= minus;
          plus /= 2.0 * epsilon;
          plus -= Kv;
          errors.push_back(plus.l2_norm() / Kv.l2_norm());
        }
      INFO("relative errors " << errors[0] << ", " << errors[1] << ", "
                              << errors[2]);
      // Observed: 1.7e-4, 4.2e-5, 1.0e-5.
      CHECK(errors[2] < 5e-5);
      for (unsigned int i = 0; i + 1 < errors.size(); ++i)
        CHECK(std::log2(errors[i] / errors[i + 1]) == Approx(2.0).margin(0.2));
    }
}


TEST_CASE("Multigrid-preconditioned CG on the matrix-free tangent converges "
          "in iterations that do not grow under refinement",
          "[mechanics][matrix-free][multigrid]")
{
  // kappa / mu = 10 at a quarter of the test displacement (strains of a few
  // per cent). At larger stresses the geometric stiffness softens K: with
  // kappa = 500 at the full displacement CG stagnates even without a
  // preconditioner (K indefinite), and with kappa = 100 at half of it the
  // V-cycle's iterations grow under refinement (41, 89; measured), the
  // coarse levels' linearizations no longer approximating the fine one.
  const Mechanics::NeoHookeanPenalty mg_law{10.0, 100.0};
  std::vector<unsigned int>          iterations;
  for (const unsigned int n_refinements : {1u, 2u})
    {
      const test_support::BoxMechanics box(MPI_COMM_WORLD, 2, n_refinements);
      Mechanics::MatrixFreeMultigrid   mg(
        *box.mapping,
        box.dof_handler,
        {0},
        mg_law,
        Mechanics::MatrixFreeMultigrid::Settings());
      REQUIRE(mg.n_levels() == n_refinements + 1);
      Vector u, v, b, x;
      mg.initialize_dof_vector(u);
      u.copy_locally_owned_data_from(box.interpolate(test_support::Bulge()));
      u *= 0.25;
      mg.update(u);
      // b = K v for a random v: the solution is v.
      v.reinit(u);
      b.reinit(u);
      x.reinit(u);
      std::mt19937                           rng(42);
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      for (unsigned int i = 0; i < v.locally_owned_size(); ++i)
        v.local_element(i) =
          box.constraints.is_constrained(box.owned.nth_index_in_set(i))
            ? 0.0
            : uniform(rng);
      mg.vmult(b, v);
      iterations.push_back(mg.solve(x, b, 1e-10));
      x -= v;
      INFO("refinements " << n_refinements << ": " << iterations.back()
                          << " CG iterations");
      CHECK(x.l2_norm() / v.l2_norm() < 1e-5);
    }
  INFO("CG iterations " << iterations[0] << ", " << iterations[1]);
  // Measured: 26 and 28.
  CHECK(iterations[1] <= iterations[0] + 5);
  CHECK(iterations[1] < 40);
}
