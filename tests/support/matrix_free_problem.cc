#include "support/matrix_free_problem.h"

#include <deal.II/base/mpi.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "fibres/fibre_field.h"
#include "geometry/ellipsoid.h"
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/problem_checks.h"
#include "support/mechanics_fixture.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace test_support
{
  namespace
  {
    using systole::Mechanics::MatrixFreeTangent;

    /// A displacement different from Wobble (a few tenths of a mm).
    class Twist : public dealii::Function<3>
    {
    public:
      Twist()
        : dealii::Function<3>(3)
      {}

      double
      value(const dealii::Point<3> &p, const unsigned int c) const override
      {
        return 0.4 * std::cos(0.2 * p[2] + 0.5 * c) *
               std::sin(0.15 * p[0] + 0.3 * p[1] - c);
      }
    };

    /// The largest relative difference of @p mf and @p K over three random
    /// vectors (fixed seed), zero on the constrained DoFs.
    double
    difference(const MatrixFreeTangent                        &mf,
               const dealii::PETScWrappers::MPI::SparseMatrix &K,
               const MPI_Comm                                  comm)
    {
      MatrixFreeTangent::Vector x, y;
      mf.initialize_dof_vector(x);
      y.reinit(x);
      const dealii::IndexSet             owned = x.locally_owned_elements();
      dealii::PETScWrappers::MPI::Vector x_sparse(owned, comm),
        y_sparse(owned, comm);
      std::mt19937 rng(7 + dealii::Utilities::MPI::this_mpi_process(comm));
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      double                                 diff = 0, scale = 0;
      for (unsigned int sample = 0; sample < 3; ++sample)
        {
          for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
            x.local_element(i) = uniform(rng);
          for (const unsigned int i : mf.constrained_dofs())
            x.local_element(i) = 0.0;
          for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
            x_sparse(owned.nth_index_in_set(i)) = x.local_element(i);
          x_sparse.compress(dealii::VectorOperation::insert);
          K.vmult(y_sparse, x_sparse);
          mf.vmult(y, x);
          for (unsigned int i = 0; i < y.locally_owned_size(); ++i)
            {
              const double reference = y_sparse(owned.nth_index_in_set(i));
              diff  = std::max(diff, std::abs(y.local_element(i) - reference));
              scale = std::max(scale, std::abs(reference));
            }
        }
      return dealii::Utilities::MPI::max(diff, comm) /
             dealii::Utilities::MPI::max(scale, comm);
    }
  } // namespace


  MatrixFreeProblemDifferences
  matrix_free_problem_differences(const MPI_Comm comm)
  {
    using namespace systole;
    VentricleMechanics v(comm);
    Fibres::Parameters fibre_params;
    fibre_params.generator = "rule-based";
    v.fibres               = Fibres::create_fibre_field(fibre_params,
                                          Geometry::LVShape(),
                                          v.tria,
                                          v.names);
    const auto problem     = v.problem(2);
    problem->set_displacement(Wobble());
    // A per-point tension varying in space, besides the uniform one.
    std::vector<std::vector<dealii::Point<3>>> points;
    problem->quadrature_points(points);
    std::vector<std::vector<double>> tension(points.size());
    for (unsigned int c = 0; c < points.size(); ++c)
      for (const auto &p : points[c])
        tension[c].push_back(4.0 + 3.0 * std::sin(0.4 * p[0] - 0.3 * p[2]));
    problem->set_active_tension(tension);

    constexpr double             active_tension = 10.0;
    MatrixFreeProblemDifferences result;
    const auto                  &K =
      systole::Mechanics::ProblemChecks::assembled_tangent(*problem,
                                                           0.0,
                                                           active_tension);
    const auto mf =
      Mechanics::ProblemChecks::matrix_free_tangent(*problem, active_tension);
    result.cached = difference(*mf, K, comm);
    result.single =
      difference(*Mechanics::ProblemChecks::matrix_free_tangent(*problem,
                                                                active_tension,
                                                                true),
                 K,
                 comm);
    result.other_tension =
      difference(*Mechanics::ProblemChecks::matrix_free_tangent(*problem, 0.0),
                 K,
                 comm);

    problem->set_displacement(Twist());
    const auto &K_new =
      systole::Mechanics::ProblemChecks::assembled_tangent(*problem,
                                                           0.0,
                                                           active_tension);
    result.stale = difference(*mf, K_new, comm);
    Mechanics::ProblemChecks::update_matrix_free_tangent(*problem,
                                                         *mf,
                                                         active_tension);
    result.updated = difference(*mf, K_new, comm);

    constexpr double pressure = 10.0; // [kPa] (Land problem 2)
    const auto      &K_pressure =
      systole::Mechanics::ProblemChecks::assembled_tangent(*problem,
                                                           pressure,
                                                           active_tension);
    result.pressure_left_out = difference(*mf, K_pressure, comm);
    Mechanics::ProblemChecks::update_matrix_free_tangent(*problem,
                                                         *mf,
                                                         pressure,
                                                         active_tension);
    result.pressure = difference(*mf, K_pressure, comm);
    return result;
  }
} // namespace test_support
