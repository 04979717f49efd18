#include <deal.II/base/mpi.h>

#include "mechanics/matrix_free_tangent.h"
#include "support/penalty_tangent.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>

using namespace systole;

namespace
{
  /// A smooth direction, zero-free (so that it is the same on any
  /// partition, unlike a random vector).
  class Direction : public dealii::Function<3>
  {
  public:
    Direction()
      : dealii::Function<3>(3)
    {}

    double
    value(const dealii::Point<3> &p, const unsigned int c) const override
    {
      return 0.01 * std::sin((c + 1.0) * p[0] + 2.0 * p[1] - p[2] * c);
    }
  };

  /// |K v|, w . K v and |R(u)| of the matrix-free operator of @p variant
  /// on the box on @p comm (partition-independent numbers).
  std::array<double, 3>
  matrix_free_study(const MPI_Comm                              comm,
                    const Mechanics::MatrixFreeTangent::Variant variant)
  {
    const test_support::BoxMechanics     box(comm, 3);
    Mechanics::MatrixFreeTangent         op(*box.mapping,
                                    box.dof_handler,
                                    box.constraints,
                                    Mechanics::NeoHookeanPenalty{10.0, 500.0},
                                    variant);
    Mechanics::MatrixFreeTangent::Vector u, v, w, Kv;
    op.initialize_dof_vector(u);
    v.reinit(u);
    w.reinit(u);
    Kv.reinit(u);
    u.copy_locally_owned_data_from(box.interpolate(test_support::Bulge()));
    v.copy_locally_owned_data_from(box.interpolate(Direction()));
    w.copy_locally_owned_data_from(box.interpolate(test_support::Bulge()));
    box.constraints.set_zero(v);
    op.update(u);
    op.vmult(Kv, v);
    const double norm = Kv.l2_norm(), product = w * Kv;
    op.residual(Kv);
    return {{norm, product, Kv.l2_norm()}};
  }
} // namespace

TEST_CASE("The matrix-free tangent on 2 ranks equals the serial one",
          "[mpi][mechanics][matrix-free]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) >= 2);
  using Variant = Mechanics::MatrixFreeTangent::Variant;
  for (const Variant variant : {Variant::cached, Variant::recompute})
    {
      const auto parallel = matrix_free_study(MPI_COMM_WORLD, variant);
      const auto serial   = matrix_free_study(MPI_COMM_SELF, variant);
      REQUIRE(serial[0] > 0.0);
      for (unsigned int i = 0; i < 3; ++i)
        CHECK(parallel[i] == Approx(serial[i]).epsilon(1e-12));
    }
}
