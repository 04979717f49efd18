// ImexIntegrator with adaptive steps on several ranks takes the same steps
// and reaches the same values as on one: its error norm is summed exactly.
#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>

#include "electrophysiology/arkode_adapter.h"

#include <catch2/catch.hpp>
#include <petscvec.h>

#include <cmath>
#include <vector>

using namespace systole;
using namespace systole::Electrophysiology;

#ifndef SYSTOLE_K
#  define SYSTOLE_K 1
#endif
namespace
{
  constexpr unsigned int n_components = 30011; // not divisible by 2 or 3

  /// Decoupled components y_i' = -k_i y_i + sin(k_i t), k_i spread over
  /// [0.5, 3.5] 1/ms by a hash of the global index: an error norm whose
  /// floating-point sum differs in its last bits between partitions.
  double
  rate(const unsigned int i)
  {
    return 0.5 + 3.0 * std::fmod(0.6180339887 * i * i, 1.0);
  }

  struct Run
  {
    std::vector<double> values; ///< on rank 0: every component
    unsigned long       steps = 0;
  };

  Run
  integrate(const MPI_Comm comm)
  {
    const unsigned int size  = dealii::Utilities::MPI::n_mpi_processes(comm);
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int begin = n_components * rank / size;
    const unsigned int end   = n_components * (rank + 1) / size;
    dealii::IndexSet   owned(n_components);
    owned.add_range(begin, end);
    // The owned rates, computed once (std::fmod of these large arguments at
    // every right-hand side took most of the test's time).
    std::vector<double> rates(end - begin);
    for (unsigned int i = begin; i < end; ++i)
      rates[i - begin] = rate(i);
    ImexIntegrator::Callbacks c;
    c.explicit_rhs =
      [&rates](const double t, const LA::MPI::Vector &y, LA::MPI::Vector &f) {
        const double *yv = nullptr;
        double       *fv = nullptr;
        VecGetArrayRead(static_cast<const Vec &>(y), &yv);
        VecGetArray(static_cast<const Vec &>(f), &fv);
        for (unsigned int j = 0; j < rates.size(); ++j)
          fv[j] = -rates[j] * yv[j] + std::sin(rates[j] * t);
        VecRestoreArray(static_cast<const Vec &>(f), &fv);
        VecRestoreArrayRead(static_cast<const Vec &>(y), &yv);
      };
    ImexIntegrator::Settings s;
    s.adaptive           = true;
    s.relative_tolerance = 1e-5;
    s.absolute_tolerance = 1e-7;
    s.max_step           = 1.0;
    ImexIntegrator  ode(s, c, 0.0, comm);
    LA::MPI::Vector y(owned, comm);
    y = 1.0;
    for (unsigned int k = 1; k <= 20; ++k)
      ode.evolve(y, 0.5 * k);
    Run run;
    run.steps = ode.n_steps();
    std::vector<double> local(end - begin);
    const double       *yv = nullptr;
    VecGetArrayRead(static_cast<const Vec &>(y), &yv);
    local.assign(yv, yv + (end - begin));
    VecRestoreArrayRead(static_cast<const Vec &>(y), &yv);
    const auto gathered = dealii::Utilities::MPI::gather(comm, local, 0);
    for (const auto &part : gathered)
      run.values.insert(run.values.end(), part.begin(), part.end());
    return run;
  }
} // namespace

TEST_CASE("Adaptive ARKode steps are the same on any number of ranks",
          "[mpi][ep][arkode]")
{
  const Run parallel = integrate(MPI_COMM_WORLD);
  const Run serial   = integrate(MPI_COMM_SELF);
  CHECK(parallel.steps == serial.steps);
  if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    {
      REQUIRE(parallel.values.size() == serial.values.size());
      double difference = 0;
      for (unsigned int i = 0; i < serial.values.size(); ++i)
        difference =
          std::max(difference, std::abs(parallel.values[i] - serial.values[i]));
      INFO(serial.steps << " steps");
      CHECK(difference == 0);
    }
}
