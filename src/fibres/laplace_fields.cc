#include "fibres/laplace_fields.h"

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/reference_cell.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/vector.h>
#include <deal.II/matrix_free/fe_point_evaluation.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/linear_algebra.h"
#include "geometry/cell_kind.h"
#include "geometry/point_location.h"

#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole::Fibres
{
  double
  seconds_since(const std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start)
      .count();
  }


  namespace
  {
    /// The point of the reference cell @p reference nearest to @p p, for
    /// points a little outside it.
    dealii::Point<3>
    project_to_reference_cell(const dealii::ReferenceCell &reference,
                              const dealii::Point<3>      &p)
    {
      if (reference == dealii::ReferenceCells::Hexahedron)
        return dealii::GeometryInfo<3>::project_to_unit_cell(p);
      AssertThrow(reference == dealii::ReferenceCells::Tetrahedron,
                  dealii::ExcMessage("Rule-based fibres: cells must be "
                                     "hexahedra or tetrahedra."));
      // Barycentric coordinates (1 - x - y - z, x, y, z): clamping the
      // negative ones and rescaling is not the exact nearest point, but it
      // moves a point that lies a little outside by about that little.
      std::array<double, 4> lambda = {
        {1.0 - p[0] - p[1] - p[2], p[0], p[1], p[2]}};
      double sum = 0;
      for (double &l : lambda)
        {
          l = std::max(0.0, l);
          sum += l;
        }
      if (!(sum > 0))
        return dealii::Point<3>(0.25, 0.25, 0.25);
      return dealii::Point<3>(lambda[1] / sum,
                              lambda[2] / sum,
                              lambda[3] / sum);
    }

    /// A lattice of reference points of @p reference (5 x 5 x 5 on the unit
    /// cube, the points with i + j + k <= 4 on the unit tetrahedron).
    dealii::Quadrature<3>
    reference_lattice(const dealii::ReferenceCell &reference)
    {
      const bool                    simplex = reference.is_simplex();
      std::vector<dealii::Point<3>> points;
      for (unsigned int k = 0; k <= 4; ++k)
        for (unsigned int j = 0; j <= 4; ++j)
          for (unsigned int i = 0; i <= 4; ++i)
            if (!simplex || i + j + k <= 4)
              points.emplace_back(i / 4.0, j / 4.0, k / 4.0);
      return dealii::Quadrature<3>(points);
    }
  } // namespace

  struct LaplaceFields::Impl
  {
    Impl(const dealii::Triangulation<3, 3> &tria, const unsigned int degree)
      : tria(tria)
      , comm(tria.get_communicator())
      , kind(tria)
      , fe(kind.lagrange(degree))
      // Degree 2 follows curved manifolds (the generated ellipsoid); on
      // hexahedral meshes without one (gmsh) it is the trilinear map, on
      // tetrahedra the affine one.
      , mapping(kind.mapping(tria, 2))
      , quadrature(kind.cell_quadrature(degree + 1))
      , dof_handler(tria)
      , evaluator(*mapping,
                  *fe,
                  dealii::update_values | dealii::update_gradients)
    {}

    const dealii::Triangulation<3, 3>              &tria;
    MPI_Comm                                        comm;
    const Geometry::CellKind                        kind;
    const std::unique_ptr<dealii::FiniteElement<3>> fe;
    const std::unique_ptr<dealii::Mapping<3>>       mapping;
    const dealii::Quadrature<3>                     quadrature;
    dealii::DoFHandler<3>                           dof_handler;
    dealii::IndexSet                                owned, relevant;
    std::vector<LA::MPI::Vector>                    fields; // with ghost values
    std::vector<unsigned int>                       iterations;
    std::vector<bool>                               direct;
    std::vector<double>                             seconds;
    double                                          setup_seconds = 0;
    unsigned int                                    n_tangled     = 0;

    // Scratch of evaluate() (the object is used from one thread).
    mutable dealii::FEPointEvaluation<1, 3>      evaluator;
    mutable std::vector<dealii::Point<3>>        unit_points;
    mutable dealii::Vector<double>               local;
    mutable std::unique_ptr<dealii::FEValues<3>> lattice_values;

    struct SolveResult
    {
      unsigned int iterations = 0;     ///< of CG
      bool         direct     = false; ///< CG failed, solved by MUMPS
    };

    /// -Laplace u = source with @p constraints into @p solution (owned).
    SolveResult
    solve(const dealii::AffineConstraints<double> &constraints,
          const double                             source,
          LA::MPI::Vector                         &solution,
          const std::string                       &what) const;

    /// The reference point of the lattice (reference_lattice) whose image
    /// is nearest to @p x, for points the inverse mapping cannot place.
    dealii::Point<3>
    nearest_lattice_point(
      const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
      const dealii::Point<3>                                  &x) const;
  };

  LaplaceFields::Impl::SolveResult
  LaplaceFields::Impl::solve(
    const dealii::AffineConstraints<double> &constraints,
    const double                             source,
    LA::MPI::Vector                         &solution,
    const std::string                       &what) const
  {
    dealii::DynamicSparsityPattern dsp(relevant);
    dealii::DoFTools::make_sparsity_pattern(dof_handler,
                                            dsp,
                                            constraints,
                                            false);
    dealii::SparsityTools::distribute_sparsity_pattern(dsp,
                                                       owned,
                                                       comm,
                                                       relevant);
    LA::MPI::SparseMatrix matrix;
    matrix.reinit(owned, owned, dsp, comm);
    LA::MPI::Vector rhs(owned, comm);
    solution.reinit(owned, comm);

    dealii::FEValues<3>                          fe_values(*mapping,
                                  *fe,
                                  quadrature,
                                  dealii::update_values |
                                    dealii::update_gradients |
                                    dealii::update_JxW_values);
    const unsigned int                           n = fe->n_dofs_per_cell();
    dealii::FullMatrix<double>                   cell_matrix(n, n);
    dealii::Vector<double>                       cell_rhs(n);
    std::vector<dealii::types::global_dof_index> dofs(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          cell_matrix = 0;
          cell_rhs    = 0;
          for (const unsigned int q : fe_values.quadrature_point_indices())
            for (unsigned int i = 0; i < n; ++i)
              {
                for (unsigned int j = 0; j < n; ++j)
                  cell_matrix(i, j) += fe_values.shape_grad(i, q) *
                                       fe_values.shape_grad(j, q) *
                                       fe_values.JxW(q);
                cell_rhs(i) +=
                  source * fe_values.shape_value(i, q) * fe_values.JxW(q);
              }
          cell->get_dof_indices(dofs);
          constraints.distribute_local_to_global(cell_matrix,
                                                 cell_rhs,
                                                 dofs,
                                                 matrix,
                                                 rhs);
        }
    matrix.compress(dealii::VectorOperation::add);
    rhs.compress(dealii::VectorOperation::add);

    dealii::SolverControl control(std::max<unsigned int>(1000,
                                                         dof_handler.n_dofs()),
                                  1e-10 * rhs.l2_norm());
    LA::SolverCG          cg(control, comm);
    LA::MPI::PreconditionAMG::AdditionalData amg_data;
    amg_data.symmetric_operator               = true;
    amg_data.strong_threshold                 = 0.5;
    amg_data.aggressive_coarsening_num_levels = 1;
    const LA::MPI::PreconditionAMG amg(matrix, amg_data);
    SolveResult                    result;
    try
      {
        cg.solve(matrix, solution, rhs, amg);
        result.iterations = control.last_step();
      }
    catch (const std::exception &)
      {
        // A tangled cell makes the matrix indefinite and AMG-CG breaks down.
        solution = 0;
        dealii::SolverControl                    direct_control(1, 0);
        dealii::PETScWrappers::SparseDirectMUMPS direct(direct_control, comm);
        try
          {
            direct.solve(matrix, solution, rhs);
          }
        catch (const std::exception &e)
          {
            AssertThrow(false,
                        dealii::ExcMessage(
                          "Rule-based fibres: the " + what +
                          " solve failed with CG + AMG and with MUMPS (" +
                          e.what() + "). Is the mesh valid?"));
          }
        result.direct = true;
      }
    constraints.distribute(solution);
    return result;
  }

  dealii::Point<3>
  LaplaceFields::Impl::nearest_lattice_point(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const dealii::Point<3>                                  &x) const
  {
    if (!lattice_values)
      lattice_values =
        std::make_unique<dealii::FEValues<3>>(*mapping,
                                              *fe,
                                              reference_lattice(
                                                cell->reference_cell()),
                                              dealii::update_quadrature_points);
    lattice_values->reinit(cell);
    unsigned int best = 0;
    for (const unsigned int q : lattice_values->quadrature_point_indices())
      if (lattice_values->quadrature_point(q).distance(x) <
          lattice_values->quadrature_point(best).distance(x))
        best = q;
    AssertThrow(lattice_values->quadrature_point(best).distance(x) <
                  cell->diameter(),
                dealii::ExcMessage("Rule-based fibres: the point " +
                                   Geometry::format_point(x) +
                                   " is not inside the cell it was given "
                                   "with."));
    return lattice_values->get_quadrature().point(best);
  }

  LaplaceFields::LaplaceFields(const dealii::Triangulation<3, 3> &tria,
                               const unsigned int                 degree,
                               const std::vector<LaplaceProblem> &problems)
    : impl(std::make_unique<Impl>(tria, degree))
  {
    Impl      &m     = *impl;
    const auto start = std::chrono::steady_clock::now();
    m.dof_handler.distribute_dofs(*m.fe);
    m.owned = m.dof_handler.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(m.dof_handler, m.relevant);

    {
      dealii::FEValues<3> fe_values(*m.mapping,
                                    *m.fe,
                                    m.quadrature,
                                    dealii::update_JxW_values);
      unsigned int        n = 0;
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            for (const unsigned int q : fe_values.quadrature_point_indices())
              if (!(fe_values.JxW(q) > 0))
                {
                  ++n;
                  break;
                }
          }
      m.n_tangled = dealii::Utilities::MPI::sum(n, m.comm);
    }

    dealii::AffineConstraints<double> hanging(m.relevant);
    dealii::DoFTools::make_hanging_node_constraints(m.dof_handler, hanging);
    hanging.close();
    m.setup_seconds = seconds_since(start);
    for (const LaplaceProblem &problem : problems)
      {
        const auto solve_start = std::chrono::steady_clock::now();
        dealii::AffineConstraints<double> constraints(m.relevant);
        constraints.merge(hanging);
        for (const auto &[id, value] : problem.dirichlet)
          dealii::VectorTools::interpolate_boundary_values(
            *m.mapping,
            m.dof_handler,
            id,
            dealii::Functions::ConstantFunction<3>(value),
            constraints);
        for (const auto &[point, value] : problem.vertex_values)
          {
            // On every rank that sees the vertex (it may be a ghost's).
            const double tolerance = 1e-10 * dealii::GridTools::diameter(tria);
            unsigned int found     = 0;
            for (const auto &cell : m.dof_handler.active_cell_iterators())
              if (!cell->is_artificial())
                for (const unsigned int v : cell->vertex_indices())
                  if (cell->vertex(v).distance(point) < tolerance)
                    {
                      const auto dof = cell->vertex_dof_index(v, 0);
                      if (!constraints.is_constrained(dof))
                        {
                          constraints.add_line(dof);
                          constraints.set_inhomogeneity(dof, value);
                        }
                      found = 1;
                    }
            AssertThrow(dealii::Utilities::MPI::max(found, m.comm) == 1,
                        dealii::ExcMessage("Rule-based fibres: the " +
                                           problem.name +
                                           " problem has a value at " +
                                           Geometry::format_point(point) +
                                           ", which is no vertex of the "
                                           "mesh."));
          }
        constraints.close();
        LA::MPI::Vector solution;
        const auto      result =
          m.solve(constraints, problem.source, solution, problem.name);
        m.iterations.push_back(result.iterations);
        m.direct.push_back(result.direct);
        m.fields.emplace_back(m.owned, m.relevant, m.comm);
        m.fields.back() = solution;
        m.seconds.push_back(seconds_since(solve_start));
      }
  }

  LaplaceFields::~LaplaceFields() = default;

  unsigned int
  LaplaceFields::n_fields() const
  {
    return impl->fields.size();
  }

  void
  LaplaceFields::scale(const unsigned int k, const double a, const double b)
  {
    Impl           &m = *impl;
    LA::MPI::Vector u(m.owned, m.comm);
    u = m.fields[k];
    u *= a;
    u.add(b);
    m.fields[k] = u;
  }

  std::pair<double, dealii::Point<3>>
  LaplaceFields::maximum(const unsigned int k) const
  {
    const Impl                                        &m = *impl;
    const LA::MPI::Vector                             &u = m.fields[k];
    std::pair<double, dealii::types::global_dof_index> best =
      {-std::numeric_limits<double>::max(), 0};
    for (const auto i : m.owned)
      if (u(i) > best.first)
        best = {u(i), i};
    for (const auto &candidate :
         dealii::Utilities::MPI::all_gather(m.comm, best))
      if (candidate.first > best.first ||
          (candidate.first == best.first && candidate.second < best.second))
        best = candidate;

    std::array<double, 4>                        found = {{0.0, 0.0, 0.0, 0.0}};
    std::vector<dealii::types::global_dof_index> dofs(m.fe->n_dofs_per_cell());
    if (m.owned.is_element(best.second))
      for (const auto &cell : m.dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && found[0] == 0.0)
          {
            cell->get_dof_indices(dofs);
            for (unsigned int i = 0; i < dofs.size(); ++i)
              if (dofs[i] == best.second)
                {
                  const auto x = m.mapping->transform_unit_to_real_cell(
                    cell,
                    m.fe->get_unit_support_points()[i]);
                  found = {{1.0, x[0], x[1], x[2]}};
                  break;
                }
          }
    for (const auto &candidate :
         dealii::Utilities::MPI::all_gather(m.comm, found))
      if (candidate[0] == 1.0)
        found = candidate;
    return {best.first, dealii::Point<3>(found[1], found[2], found[3])};
  }

  void
  LaplaceFields::evaluate(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<std::vector<FieldValue>>                    &values) const
  {
    const Impl &m = *impl;
    AssertThrow(&cell->get_triangulation() == &m.tria,
                dealii::ExcMessage("Rule-based fibres: asked for a cell of "
                                   "another mesh than the one solved on."));
    const dealii::DoFHandler<3>::active_cell_iterator dof_cell(&m.tria,
                                                               cell->level(),
                                                               cell->index(),
                                                               &m.dof_handler);
    // Reference coordinates in this cell. The caller's mapping may differ
    // from ours (another degree): a point can then lie a little outside the
    // cell in our geometry, and is projected onto it.
    m.unit_points.resize(points.size());
    m.mapping->transform_points_real_to_unit_cell(
      cell,
      dealii::make_array_view(points),
      dealii::make_array_view(m.unit_points));
    const dealii::ReferenceCell reference = cell->reference_cell();
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        if (!std::isfinite(m.unit_points[i][0]))
          {
            // A vertex needs no inversion (and one of a tangled cell, where
            // the Jacobian vanishes, has none).
            bool vertex = false;
            for (const unsigned int v : cell->vertex_indices())
              if (cell->vertex(v).distance(points[i]) <=
                  1e-12 * cell->diameter())
                {
                  m.unit_points[i] = reference.vertex<3>(v);
                  vertex           = true;
                }
            if (!vertex)
              try
                {
                  m.unit_points[i] =
                    m.mapping->transform_real_to_unit_cell(cell, points[i]);
                }
              catch (const dealii::Mapping<3>::ExcTransformationFailed &)
                {
                  m.unit_points[i] = m.nearest_lattice_point(cell, points[i]);
                }
          }
        m.unit_points[i] =
          project_to_reference_cell(reference, m.unit_points[i]);
      }
    m.evaluator.reinit(cell, dealii::make_array_view(m.unit_points));
    const auto flags =
      dealii::EvaluationFlags::values | dealii::EvaluationFlags::gradients;
    values.resize(m.fields.size());
    m.local.reinit(m.fe->n_dofs_per_cell());
    for (unsigned int k = 0; k < m.fields.size(); ++k)
      {
        dof_cell->get_dof_values(m.fields[k], m.local);
        m.evaluator.evaluate(dealii::make_array_view(m.local), flags);
        values[k].resize(points.size());
        for (unsigned int i = 0; i < points.size(); ++i)
          values[k][i] = {m.evaluator.get_value(i),
                          m.evaluator.get_gradient(i)};
      }
  }

  std::string
  LaplaceFields::element_name() const
  {
    return (impl->kind.simplex() ? "P" : "Q") +
           std::to_string(impl->fe->degree);
  }

  unsigned long long
  LaplaceFields::n_dofs() const
  {
    return impl->dof_handler.n_dofs();
  }

  const std::vector<unsigned int> &
  LaplaceFields::iterations() const
  {
    return impl->iterations;
  }

  const std::vector<bool> &
  LaplaceFields::direct() const
  {
    return impl->direct;
  }

  const std::vector<double> &
  LaplaceFields::solve_seconds() const
  {
    return impl->seconds;
  }

  double
  LaplaceFields::setup_seconds() const
  {
    return impl->setup_seconds;
  }

  unsigned int
  LaplaceFields::n_tangled_cells() const
  {
    return impl->n_tangled;
  }
} // namespace systole::Fibres
