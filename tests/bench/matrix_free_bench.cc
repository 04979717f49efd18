// Benchmark of the matrix-free mechanics tangent (not a test: run by hand,
// not by ctest): on the distorted Q2 box of the matrix-free tests (MappingQ2,
// every cell general), linearized at a smooth finite displacement, the time
// of one application of the tangent, matrix-free with the cached 9 x 9
// tangent, matrix-free recomputing the law, and the PETSc sparse matrix of
// the same operator (assembled with FEValues, tests/support); memory per DOF
// of each; set-up (MatrixFree initialization and update() vs sparsity and
// assembly); and a STREAM triad timed in the same run, from which the
// fraction of the memory-bandwidth roofline of each variant follows (bytes a
// variant must move per application / time / triad bandwidth).
// docs/verification.md ("Mechanics: the matrix-free tangent") has the
// numbers.
//
// With --problem: the mechanics' own tangents of a Mechanics::Problem (a box
// of n^3 Q2 cells on its MappingQCache, the Guccione law of the tests with a
// fibre frame rotating along z, Simo-Taylor penalty, x = 0 fixed, 10 kPa of
// active tension, at a smooth displacement): the assembled PETSc matrix
// (ProblemChecks::assembled_tangent()) against the general cached matrix-free
// tangent filled by the Problem's point kernel
// (ProblemChecks::matrix_free_tangent()), in double and single precision.
//
//   [mpirun -np 2] build/tests/systole-mf-bench [--no-sparse] n1 [n2 ...]
//   [mpirun -np 2] build/tests/systole-mf-bench --multigrid r1 [r2 ...]
//   [mpirun -np 2] build/tests/systole-mf-bench --problem n1 [n2 ...]
//
// (n: cells per direction; DOFs = 3 (2n + 1)^3. r: refinements of 2 x 2 x 2
// cells for the multigrid-preconditioned CG.)

#include <deal.II/base/mpi.h>
#include <deal.II/base/vectorization.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "base/logger.h"
#include "geometry/mesh.h"
#include "materials/guccione.h"
#include "materials/neo_hookean.h"
#include "materials/volumetric_law.h"
#include "mechanics/matrix_free_multigrid.h"
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/problem.h"
#include "mechanics/problem_checks.h"
#include "support/mechanics_fixture.h"
#include "support/penalty_tangent.h"

#include "matrix_free_bench_simd.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace systole;
using Variant = Mechanics::MatrixFreeTangent::Variant;

namespace
{
  const MPI_Comm comm = MPI_COMM_WORLD;

  double
  now()
  {
    return MPI_Wtime();
  }

  /// Least wall time of @p f over all ranks (barriers around each call),
  /// repeated for about @p budget seconds and at least 3 times.
  double
  best_time(const std::function<void()> &f, const double budget = 1.0)
  {
    double       best = 1e30, total = 0;
    unsigned int reps = 0;
    while (reps < 3 || total < budget)
      {
        MPI_Barrier(comm);
        const double t0 = now();
        f();
        MPI_Barrier(comm);
        const double t = now() - t0;
        best           = std::min(best, t);
        total += t;
        ++reps;
        // Every rank takes the same decision.
        total = dealii::Utilities::MPI::max(total, comm);
      }
    return dealii::Utilities::MPI::max(best, comm);
  }

  /// STREAM triad a = b + s c on every rank at once: bytes per second of
  /// all ranks together (24 bytes per entry, STREAM's count).
  double
  triad_bandwidth()
  {
    const std::size_t   n = std::size_t(1) << 25; // 256 MiB per array
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    const double        t = best_time(
      [&]() {
        const double s = 0.5;
        for (std::size_t i = 0; i < n; ++i)
          a[i] = b[i] + s * c[i];
      },
      2.0);
    if (a[n / 2] != 2.0)
      std::abort(); // keeps the loop alive
    return 24.0 * n * dealii::Utilities::MPI::n_mpi_processes(comm) / t;
  }

  double
  sum(const double x)
  {
    return dealii::Utilities::MPI::sum(x, comm);
  }

  struct Row
  {
    std::string name;
    double      setup_once = 0, setup_update = 0, apply = 0;
    double      bytes_memory = 0, bytes_moved = 0;
    /// The product with the direction (locally owned entries).
    std::vector<double> result;
  };

  /// max_i |a_i - b_i| / max_i |b_i| over all ranks.
  double
  relative_difference(const std::vector<double> &a,
                      const std::vector<double> &b)
  {
    double diff = 0, scale = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      {
        diff  = std::max(diff, std::abs(a[i] - b[i]));
        scale = std::max(scale, std::abs(b[i]));
      }
    return dealii::Utilities::MPI::max(diff, comm) /
           dealii::Utilities::MPI::max(scale, comm);
  }

  void
  print(const Row                 &r,
        const double               n_dofs,
        const double               bandwidth,
        const std::vector<double> &reference)
  {
    const double difference = relative_difference(r.result, reference);
    if (dealii::Utilities::MPI::this_mpi_process(comm) != 0)
      return;
    std::printf("  %-22s init %8.3f s  update %8.3f s  apply %9.3f ms"
                "  %7.1f ns/DOF  memory %7.0f B/DOF  moved %6.0f B/DOF"
                "  %5.1f GB/s  roofline %5.1f %%  difference %.1e\n",
                r.name.c_str(),
                r.setup_once,
                r.setup_update,
                1e3 * r.apply,
                1e9 * r.apply / n_dofs,
                r.bytes_memory / n_dofs,
                r.bytes_moved / n_dofs,
                1e-9 * r.bytes_moved / r.apply,
                100.0 * r.bytes_moved / r.apply / bandwidth,
                difference);
    std::fflush(stdout);
  }

  /// The bytes one product of @p op moves: the point storage, the geometry
  /// it reads (Jacobian and JxW), the DoF indices (4 bytes per cell DoF),
  /// src read, dst written and read back (24 bytes per DOF).
  template <typename Operator>
  double
  matrix_free_bytes_moved(const Operator &op)
  {
    return sum(op.point_storage_bytes() + 8.0 * op.n_geometry_numbers() +
               4.0 * 81 * op.n_quadrature_points() / 27) +
           24.0 * op.m();
  }

  /// The library's MatrixFreeTangent behind bench::Tangent.
  class LibraryTangent : public bench::Tangent
  {
  public:
    template <typename... Args>
    LibraryTangent(Args &&...args)
      : op(std::forward<Args>(args)...)
    {}
    void
    initialize_dof_vector(bench::Vector &v) const override
    {
      op.initialize_dof_vector(v);
    }
    void
    update(const bench::Vector &u) override
    {
      op.update(u);
    }
    void
    vmult(bench::Vector &dst, const bench::Vector &src) const override
    {
      op.vmult(dst, src);
    }
    double
    m() const override
    {
      return op.m();
    }
    std::size_t
    memory_consumption() const override
    {
      return op.memory_consumption();
    }
    std::size_t
    point_storage_bytes() const override
    {
      return op.point_storage_bytes();
    }
    std::size_t
    n_quadrature_points() const override
    {
      return op.n_quadrature_points();
    }
    std::size_t
    n_geometry_numbers() const override
    {
      return op.n_geometry_numbers();
    }

  private:
    Mechanics::MatrixFreeTangent op;
  };

  /// One matrix-free variant on @p box linearized at @p u: the library's
  /// (@p simd false; SYSTOLE_MATRIX_FREE_LANES lanes) or the benchmark's
  /// own 8-lane build.
  Row
  matrix_free_row(const test_support::BoxMechanics      &box,
                  const test_support::DistributedVector &u,
                  const test_support::DistributedVector &direction,
                  const Variant                          variant,
                  const bool                             simd)
  {
    Row                                row;
    const Mechanics::NeoHookeanPenalty law{10.0, 500.0};
    const double                       t0 = now();
    std::unique_ptr<bench::Tangent>    tangent;
#ifdef SYSTOLE_BENCH_AVX512
    if (simd)
      tangent = bench::make_simd_tangent(*box.mapping,
                                         box.dof_handler,
                                         box.constraints,
                                         law,
                                         variant);
    else
#endif
      tangent = std::make_unique<LibraryTangent>(*box.mapping,
                                                 box.dof_handler,
                                                 box.constraints,
                                                 law,
                                                 variant);
    bench::Tangent &op = *tangent;
    row.setup_once     = dealii::Utilities::MPI::max(now() - t0, comm);
    Mechanics::MatrixFreeTangent::Vector x, y;
    op.initialize_dof_vector(x);
    y.reinit(x);
    x.copy_locally_owned_data_from(u);
    row.setup_update = best_time([&]() { op.update(x); }, 0.0);
    x.copy_locally_owned_data_from(direction);
    row.apply = best_time([&]() { op.vmult(y, x); });
    row.result.assign(y.begin(), y.begin() + y.locally_owned_size());
    row.name =
      std::string(variant == Variant::cached          ? "MF cached"
                  : variant == Variant::cached_single ? "MF single"
                                                      : "MF recompute") +
      (simd ? std::string(" 8 lanes")
            : " " + std::to_string(SYSTOLE_MATRIX_FREE_LANES) + " lane(s)");
    // Memory: the operator's own data and its two vectors.
    row.bytes_memory = sum(op.memory_consumption() + x.memory_consumption() +
                           y.memory_consumption());
    row.bytes_moved  = matrix_free_bytes_moved(op);
    return row;
  }

  /// The PETSc sparse matrix of the same operator.
  Row
  sparse_row(const test_support::BoxMechanics      &box,
             const test_support::DistributedVector &u,
             const test_support::DistributedVector &direction)
  {
    Row row;
    row.name = "PETSc sparse matrix";
    const Materials::NeoHookean passive{
      Materials::NeoHookean::Parameters()}; // mu = 10 kPa
    const Materials::VolumetricLaw volumetric(
      Materials::VolumetricLaw::Form::simo_taylor,
      500.0);
    dealii::PETScWrappers::MPI::SparseMatrix K;
    const double                             t0 = now();
    test_support::setup_sparse_tangent(box.dof_handler, box.constraints, K);
    row.setup_once   = dealii::Utilities::MPI::max(now() - t0, comm);
    row.setup_update = best_time(
      [&]() {
        test_support::assemble_penalty_tangent(*box.mapping,
                                               box.dof_handler,
                                               box.constraints,
                                               u,
                                               passive,
                                               volumetric,
                                               K);
      },
      0.0);
    dealii::PETScWrappers::MPI::Vector x(box.owned, comm), y(x);
    test_support::DistributedVector    result(direction);
    test_support::sparse_vmult(K, direction, x, y, result);
    row.apply = best_time([&]() { K.vmult(y, x); });
    row.result.assign(result.begin(),
                      result.begin() + result.locally_owned_size());
    // AIJ: 8-byte value and 4-byte column index per entry, a 4-byte row
    // pointer, src read and dst written per row (and the vectors).
    const double nnz    = K.n_nonzero_elements();
    const double n_dofs = K.m();
    row.bytes_moved     = 12.0 * nnz + 20.0 * n_dofs;
    row.bytes_memory    = 12.0 * nnz + 4.0 * n_dofs + 16.0 * n_dofs;
    return row;
  }
  /// CG with the multigrid V-cycle (MatrixFreeMultigrid) on the box of 2 x
  /// 2 x 2 cells refined @p n_refinements times, at a quarter of the test
  /// displacement with kappa / mu = 10 (as the unit test): iterations to a
  /// relative residual of 1e-8 and times.
  void
  multigrid_row(const unsigned int n_refinements, const bool single)
  {
    const test_support::BoxMechanics         box(comm, 2, n_refinements);
    Mechanics::MatrixFreeMultigrid::Settings settings;
    settings.single_precision_levels  = single;
    double                         t0 = now();
    Mechanics::MatrixFreeMultigrid mg(*box.mapping,
                                      box.dof_handler,
                                      {0},
                                      Mechanics::NeoHookeanPenalty{10.0, 100.0},
                                      settings);
    const double  setup = dealii::Utilities::MPI::max(now() - t0, comm);
    bench::Vector u, b, x;
    mg.initialize_dof_vector(u);
    b.reinit(u);
    x.reinit(u);
    u.copy_locally_owned_data_from(box.interpolate(test_support::Bulge()));
    u *= 0.25;
    t0 = now();
    mg.update(u);
    const double update = dealii::Utilities::MPI::max(now() - t0, comm);
    // b = K d for a smooth d (zero on the constrained DoFs).
    auto direction = box.interpolate(test_support::Bulge());
    box.constraints.set_zero(direction);
    x.copy_locally_owned_data_from(direction);
    mg.vmult(b, x);
    unsigned int iterations = 0;
    const double solve =
      best_time([&]() { iterations = mg.solve(x, b, 1e-8); }, 0.0);
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      std::printf("  multigrid%s: refinements %u  levels %u  DOFs %u  set-up "
                  "%.3f s  update %.3f s  CG iterations %u  solve %.3f s"
                  "  (%.1f ns/DOF per iteration)\n",
                  single ? " (single-precision levels)" : "",
                  n_refinements,
                  mg.n_levels(),
                  static_cast<unsigned int>(box.dof_handler.n_dofs()),
                  setup,
                  update,
                  iterations,
                  solve,
                  1e9 * solve / iterations / box.dof_handler.n_dofs());
    std::fflush(stdout);
  }

  /// The mechanics' own tangents of a Problem on a box of @p n^3 Q2 cells
  /// (see the file's comment): the assembled sparse matrix and the general
  /// cached matrix-free tangent (double, single), one row each.
  void
  problem_rows(const unsigned int n, const double bandwidth)
  {
    std::ostringstream        sink;
    Logger                    logger(comm, sink);
    const Materials::Guccione law(test_support::test_guccione_parameters());
    const Materials::VolumetricLaw volumetric(
      Materials::VolumetricLaw::Form::simo_taylor,
      100.0);
    const Fibres::FibreField fibres = test_support::rotating_fibres();
    Geometry::Parameters     geometry;
    geometry.type      = Geometry::Parameters::Type::box;
    geometry.box_upper = dealii::Point<3>(10, 10, 10);
    geometry.box_cells = {{n, n, n}};
    dealii::parallel::distributed::Triangulation<3> tria(comm);
    const auto            names = Geometry::create_mesh(geometry, tria);
    Mechanics::Parameters params;
    params.fixed_boundaries = {"x_min"};
    params.linear_solver    = "direct";
    Mechanics::Problem problem(
      {params, tria, names, 2, 2, law, volumetric, fibres, logger});
    problem.set_displacement(test_support::Wobble());
    constexpr double tension = 10.0;
    const double     n_dofs  = problem.n_dofs();
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      std::printf("problem n %u  cells %u  DOFs %.0f (Guccione, rotating "
                  "fibres, penalty, Q2 on MappingQCache)\n",
                  n,
                  tria.n_global_active_cells(),
                  n_dofs);

    // The direction: zero on the constrained DoFs.
    const std::unique_ptr<Mechanics::MatrixFreeTangent> first =
      Mechanics::ProblemChecks::matrix_free_tangent(problem, tension);
    bench::Vector direction, y;
    first->initialize_dof_vector(direction);
    y.reinit(direction);
    const dealii::IndexSet owned = direction.locally_owned_elements();
    for (unsigned int i = 0; i < direction.locally_owned_size(); ++i)
      direction.local_element(i) =
        std::sin(1.0 + 0.37 * owned.nth_index_in_set(i));
    for (const unsigned int i : first->constrained_dofs())
      direction.local_element(i) = 0.0;

    Row sparse;
    sparse.name                                       = "Problem sparse matrix";
    const dealii::PETScWrappers::MPI::SparseMatrix *K = nullptr;
    sparse.setup_update                               = best_time(
      [&]() {
        K = &systole::Mechanics::ProblemChecks::assembled_tangent(problem,
                                                                  0.0,
                                                                  tension);
      },
      0.0);
    dealii::PETScWrappers::MPI::Vector x_sparse(owned, comm),
      y_sparse(owned, comm);
    for (unsigned int i = 0; i < direction.locally_owned_size(); ++i)
      x_sparse(owned.nth_index_in_set(i)) = direction.local_element(i);
    x_sparse.compress(dealii::VectorOperation::insert);
    sparse.apply = best_time([&]() { K->vmult(y_sparse, x_sparse); });
    for (unsigned int i = 0; i < direction.locally_owned_size(); ++i)
      sparse.result.push_back(y_sparse(owned.nth_index_in_set(i)));
    // AIJ, as sparse_row().
    const double nnz    = K->n_nonzero_elements();
    sparse.bytes_moved  = 12.0 * nnz + 20.0 * n_dofs;
    sparse.bytes_memory = 12.0 * nnz + 4.0 * n_dofs + 16.0 * n_dofs;
    print(sparse, n_dofs, bandwidth, sparse.result);

    for (const bool single : {false, true})
      {
        Row                                                 row;
        const double                                        t0 = now();
        const std::unique_ptr<Mechanics::MatrixFreeTangent> op =
          Mechanics::ProblemChecks::matrix_free_tangent(problem,
                                                        tension,
                                                        single);
        // (init: MatrixFree's initialization and the first fill)
        row.setup_once   = dealii::Utilities::MPI::max(now() - t0, comm);
        row.setup_update = best_time(
          [&]() {
            Mechanics::ProblemChecks::update_matrix_free_tangent(problem,
                                                                 *op,
                                                                 tension);
          },
          0.0);
        row.apply = best_time([&]() { op->vmult(y, direction); });
        row.result.assign(y.begin(), y.begin() + y.locally_owned_size());
        row.name = single ? "Problem MF single" : "Problem MF cached";
        row.bytes_memory =
          sum(op->memory_consumption() + direction.memory_consumption() +
              y.memory_consumption());
        row.bytes_moved = matrix_free_bytes_moved(*op);
        print(row, n_dofs, bandwidth, sparse.result);
      }
  }
} // namespace


int
main(int argc, char *argv[])
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool root        = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  bool       with_sparse = true, multigrid = false, with_problem = false;
  std::vector<unsigned int> sizes;
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--no-sparse") == 0)
      with_sparse = false;
    else if (std::strcmp(argv[i], "--multigrid") == 0)
      multigrid = true;
    else if (std::strcmp(argv[i], "--problem") == 0)
      with_problem = true;
    else
      sizes.push_back(std::atoi(argv[i]));
      // The 8-lane build runs only where the processor has AVX-512F.
#ifdef SYSTOLE_BENCH_AVX512
  const bool with_simd = __builtin_cpu_supports("avx512f");
#else
  const bool with_simd = false;
#endif
  if (sizes.empty())
    sizes = {9, 17, 27};

  if (multigrid)
    {
      for (const unsigned int r : sizes)
        for (const bool single : {false, true})
          multigrid_row(r, single);
      return 0;
    }
  const double bandwidth = triad_bandwidth();
  if (root)
    std::printf("ranks %u  triad %.1f GB/s  the library's matrix-free "
                "lanes %u\n",
                dealii::Utilities::MPI::n_mpi_processes(comm),
                1e-9 * bandwidth,
                static_cast<unsigned int>(SYSTOLE_MATRIX_FREE_LANES));
  if (with_problem)
    {
      for (const unsigned int n : sizes)
        problem_rows(n, bandwidth);
      return 0;
    }
  for (const unsigned int n : sizes)
    {
      const test_support::BoxMechanics box(comm, n);
      const auto   u      = box.interpolate(test_support::Bulge());
      const double n_dofs = box.dof_handler.n_dofs();
      if (root)
        std::printf("n %u  cells %u  DOFs %.0f\n",
                    n,
                    box.tria.n_global_active_cells(),
                    n_dofs);
      // The direction: u without its constrained entries (on which the
      // matrix-free identity rows and the sparse matrix's diagonal differ).
      auto direction = u;
      box.constraints.set_zero(direction);
      std::vector<Row> rows;
      if (with_sparse)
        rows.push_back(sparse_row(box, u, direction));
      for (const bool simd : {false, true})
        if (!simd || with_simd)
          for (const Variant v :
               {Variant::cached, Variant::cached_single, Variant::recompute})
            rows.push_back(matrix_free_row(box, u, direction, v, simd));
      // Differences to the first row: the sparse product if there is one.
      for (const Row &row : rows)
        print(row, n_dofs, bandwidth, rows.front().result);
    }
  return 0;
}
