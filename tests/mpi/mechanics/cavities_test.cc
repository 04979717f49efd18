#include <deal.II/base/mpi.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "support/mechanics_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

namespace
{
  /// The two-cavity problem on @p comm, solved for
  /// W_i(p) = V0_i +- 8 % V0_endo + c_i p_i; returns the pressures.
  dealii::Vector<double>
  compliant_two_cavity_pressures(const MPI_Comm comm)
  {
    test_support::VentricleMechanics s(comm);
    s.use_two_cavities();
    const auto                   problem = s.problem();
    const dealii::Vector<double> V0      = problem->cavity_volumes();
    const double                 dV      = 0.08 * V0[0];
    dealii::Vector<double>       p(2);
    problem->solve_cavities(test_support::linear_compliance(V0,
                                                            {dV, -dV},
                                                            {5.0, 3.0}),
                            0.0,
                            p);
    return p;
  }
} // namespace

TEST_CASE("Two cavities on 2 ranks: volumes, Jacobian and pressures",
          "[mpi][mechanics]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);

  // Half of the endocardium is refused on 2 ranks as on 1, with the same
  // count of open rim edges (each counted once over the ranks).
  const auto refusal = [](const MPI_Comm comm) {
    test_support::VentricleMechanics split(comm);
    split.split_endocardium();
    try
      {
        split.problem();
      }
    catch (const std::exception &e)
      {
        const std::string message = e.what();
        const auto        colon   = message.find("'base': ");
        return message.substr(colon, message.find(" edges") - colon);
      }
    return std::string("no error");
  };
  const std::string parallel_count = refusal(MPI_COMM_WORLD);
  CHECK(parallel_count.find("'base': ") == 0);
  CHECK(parallel_count == refusal(MPI_COMM_SELF));

  // The k-cavity bordered Jacobian on a partitioned mesh.
  const auto [e1, e2] =
    test_support::two_cavity_jacobian_errors(MPI_COMM_WORLD);
  CHECK(std::log2(e1[0] / e2[0]) == Approx(2.0).margin(0.2));
  CHECK(e2[1] < 1e-7);

  // The compliant solve: the same pressures as on one rank.
  const auto parallel = compliant_two_cavity_pressures(MPI_COMM_WORLD);
  const auto serial   = compliant_two_cavity_pressures(MPI_COMM_SELF);
  CHECK(parallel[0] == Approx(serial[0]).epsilon(1e-9));
  CHECK(parallel[1] == Approx(serial[1]).epsilon(1e-9));
}

namespace
{
  /// Both ventricles of the BiV mesh on @p comm (Q1), solved for
  /// W = V0 (1.06, 1.08) + 20 p; returns the pressures.
  dealii::Vector<double>
  compliant_biv_pressures(const MPI_Comm comm)
  {
    test_support::VentricleMechanics s(comm);
    s.use_biventricular_mesh(SYSTOLE_SOURCE_DIR "/meshes/biv_hex_coarse.msh");
    const auto                   problem = s.problem(1);
    const dealii::Vector<double> V0      = problem->cavity_volumes();
    dealii::Vector<double>       p(2);
    problem->solve_cavities(test_support::linear_compliance(V0,
                                                            {0.06 * V0[0],
                                                             0.08 * V0[1]},
                                                            {20.0, 20.0}),
                            0.0,
                            p);
    return p;
  }
} // namespace

TEST_CASE("Both BiV cavities on 2 ranks: Jacobian and pressures as on 1 rank",
          "[mpi][mechanics][biv]")
{
  REQUIRE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 2);
  const std::string mesh = SYSTOLE_SOURCE_DIR "/meshes/biv_hex_coarse.msh";
  const auto [e1, e2] =
    test_support::biventricular_jacobian_errors(mesh, MPI_COMM_WORLD);
  CHECK(std::log2(e1[0] / e2[0]) == Approx(2.0).margin(0.2));
  CHECK(e2[1] < 1e-7);
  // (The FD direction follows the DoF numbering, which depends on the
  // partition: the errors themselves differ from those of 1 rank.)

  const auto parallel = compliant_biv_pressures(MPI_COMM_WORLD);
  const auto serial   = compliant_biv_pressures(MPI_COMM_SELF);
  CHECK(parallel[0] == Approx(serial[0]).epsilon(1e-9));
  CHECK(parallel[1] == Approx(serial[1]).epsilon(1e-9));
}
