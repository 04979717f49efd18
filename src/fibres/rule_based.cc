#include "fibres/rule_based.h"

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_tools.h>
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
#include "base/logger.h"
#include "fibres/fibre_field.h"
#include "geometry/mesh.h"

#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole::Fibres
{
  namespace
  {
    double
    seconds_since(const std::chrono::steady_clock::time_point start)
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                           start)
        .count();
    }

    std::string
    describe(const dealii::Point<3> &p)
    {
      std::ostringstream o;
      o << std::setprecision(6) << "(" << p[0] << ", " << p[1] << ", " << p[2]
        << ")";
      return o.str();
    }
  } // namespace

  std::string
  WallCoordinatesReport::summary() const
  {
    std::ostringstream o;
    const auto solver = [](const unsigned int iterations, const bool direct) {
      return direct ? std::string("MUMPS (CG failed)")
                    : std::to_string(iterations) + " CG iterations";
    };
    o << std::fixed << std::setprecision(2) << "Rule-based fibres: Q" << degree
      << ", " << n_dofs << " DOFs per solve; transmural "
      << solver(transmural_iterations, transmural_direct) << ", "
      << transmural_seconds << " s; apicobasal "
      << solver(apicobasal_iterations, apicobasal_direct) << ", "
      << apicobasal_seconds << " s; set-up " << setup_seconds << " s; apex at "
      << describe(apex) << " mm";
    if (n_tangled_cells > 0)
      o << ". WARNING: " << n_tangled_cells
        << " cell(s) of the mesh have a non-positive Jacobian at a quadrature "
           "point (tangled); the fibres near them are unreliable";
    return o.str();
  }

  struct WallCoordinates::Impl
  {
    Impl(const dealii::Triangulation<3, 3> &tria, const unsigned int degree)
      : tria(tria)
      , comm(tria.get_communicator())
      , fe(degree)
      , mapping(2)
      , dof_handler(tria)
      , evaluator(mapping, fe, dealii::update_values | dealii::update_gradients)
    {}

    const dealii::Triangulation<3, 3> &tria;
    MPI_Comm                           comm;
    dealii::FE_Q<3>                    fe;
    // Degree 2 follows curved manifolds (the generated ellipsoid); on meshes
    // without a manifold (gmsh) it is the trilinear map.
    dealii::MappingQ<3>   mapping;
    dealii::DoFHandler<3> dof_handler;
    dealii::IndexSet      owned, relevant;
    LA::MPI::Vector       transmural, apicobasal; // with ghost values
    WallCoordinatesReport report;

    // Scratch of evaluate() (the object is used from one thread).
    mutable dealii::FEPointEvaluation<1, 3>      evaluator;
    mutable std::vector<dealii::Point<3>>        unit_points;
    mutable dealii::Vector<double>               local_phi, local_psi;
    mutable std::unique_ptr<dealii::FEValues<3>> grid_values;

    struct SolveResult
    {
      unsigned int iterations = 0;     ///< of CG
      bool         direct     = false; ///< CG failed, solved by MUMPS
    };

    /// Assemble and solve -Laplace u = @p source with the (inhomogeneous)
    /// Dirichlet data in @p constraints into @p solution (owned entries).
    SolveResult
    solve(const dealii::AffineConstraints<double> &constraints,
          const double                             source,
          LA::MPI::Vector                         &solution,
          const std::string                       &what) const;

    /// The point of a 5 x 5 x 5 grid of reference points whose image is
    /// nearest to @p x: for points that the inverse mapping cannot place
    /// (tangled cells). Throws if @p x is not near @p cell at all.
    dealii::Point<3>
    nearest_grid_point(
      const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
      const dealii::Point<3>                                  &x) const;

    /// Cells with a non-positive Jacobian at a quadrature point (all ranks).
    unsigned int
    count_tangled_cells() const;

    /// The apex: the epicardial vertex farthest from the base plane (whose
    /// normal's sign does not matter).
    dealii::Point<3>
    epicardial_apex(const dealii::types::boundary_id epi,
                    const dealii::types::boundary_id base) const;

    /// The largest entry of @p u and its support point.
    std::pair<double, dealii::Point<3>>
    maximum(const LA::MPI::Vector &u) const;
  };

  WallCoordinates::Impl::SolveResult
  WallCoordinates::Impl::solve(
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

    const dealii::QGauss<3>                      quadrature(fe.degree + 1);
    dealii::FEValues<3>                          fe_values(mapping,
                                  fe,
                                  quadrature,
                                  dealii::update_values |
                                    dealii::update_gradients |
                                    dealii::update_JxW_values);
    const unsigned int                           n = fe.n_dofs_per_cell();
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

    // Directions need far less than this; the tolerance is cheap (a few CG
    // iterations) and keeps round-off out of the frames.
    dealii::SolverControl control(std::max<unsigned int>(1000,
                                                         dof_handler.n_dofs()),
                                  1e-10 * rhs.l2_norm());
    LA::SolverCG          cg(control, comm);
    LA::MPI::PreconditionAMG::AdditionalData amg_data;
    amg_data.symmetric_operator = true;
    // The usual advice for 3D problems (the default 0.25 is for 2D): much
    // cheaper V-cycles for Q2 at the same iteration count.
    amg_data.strong_threshold = 0.5;
    const LA::MPI::PreconditionAMG amg(matrix, amg_data);
    SolveResult                    result;
    try
      {
        cg.solve(matrix, solution, rhs, amg);
        result.iterations = control.last_step();
      }
    catch (const std::exception &)
      {
        // A tangled cell (Jacobian changing sign inside) makes the matrix
        // indefinite, and AMG-CG breaks down; the system is still regular.
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
  WallCoordinates::Impl::nearest_grid_point(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const dealii::Point<3>                                  &x) const
  {
    if (!grid_values)
      grid_values = std::make_unique<dealii::FEValues<3>>(
        mapping,
        fe,
        dealii::QIterated<3>(dealii::QTrapezoid<1>(), 4),
        dealii::update_quadrature_points);
    grid_values->reinit(cell);
    unsigned int best = 0;
    for (const unsigned int q : grid_values->quadrature_point_indices())
      if (grid_values->quadrature_point(q).distance(x) <
          grid_values->quadrature_point(best).distance(x))
        best = q;
    AssertThrow(grid_values->quadrature_point(best).distance(x) <
                  cell->diameter(),
                dealii::ExcMessage("Rule-based fibres: the point " +
                                   describe(x) +
                                   " is not inside the cell it was given "
                                   "with."));
    return grid_values->get_quadrature().point(best);
  }

  unsigned int
  WallCoordinates::Impl::count_tangled_cells() const
  {
    const dealii::QGauss<3> quadrature(fe.degree + 1);
    dealii::FEValues<3>     fe_values(mapping,
                                  fe,
                                  quadrature,
                                  dealii::update_JxW_values);
    unsigned int            n = 0;
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
    return dealii::Utilities::MPI::sum(n, comm);
  }

  dealii::Point<3>
  WallCoordinates::Impl::epicardial_apex(
    const dealii::types::boundary_id epi,
    const dealii::types::boundary_id base) const
  {
    // A loose planarity tolerance: only the direction is needed here.
    const Geometry::Plane plane =
      Geometry::boundary_plane(tria, base, "base", 0.05);
    std::array<double, 4> best = {{-1.0, 0.0, 0.0, 0.0}}; // distance, point
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == epi)
            for (const unsigned int v : face->vertex_indices())
              {
                const auto  &x = face->vertex(v);
                const double d = std::abs((x - plane.point) * plane.normal);
                if (d > best[0])
                  best = {{d, x[0], x[1], x[2]}};
              }
    // The first of the farthest in rank order, so all ranks agree on ties.
    const auto candidates = dealii::Utilities::MPI::all_gather(comm, best);
    best                  = candidates[0];
    for (const auto &candidate : candidates)
      if (candidate[0] > best[0])
        best = candidate;
    return dealii::Point<3>(best[1], best[2], best[3]);
  }

  std::pair<double, dealii::Point<3>>
  WallCoordinates::Impl::maximum(const LA::MPI::Vector &u) const
  {
    // value, dof index of the largest owned entry; then the rank owning the
    // global maximum finds its support point (an owned DoF lies on an owned
    // cell).
    std::pair<double, dealii::types::global_dof_index> best =
      {-std::numeric_limits<double>::max(), 0};
    for (const auto i : owned)
      if (u(i) > best.first)
        best = {u(i), i};
    for (const auto &candidate : dealii::Utilities::MPI::all_gather(comm, best))
      if (candidate.first > best.first ||
          (candidate.first == best.first && candidate.second < best.second))
        best = candidate;

    std::array<double, 4> found = {{0.0, 0.0, 0.0, 0.0}}; // found?, point
    std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
    if (owned.is_element(best.second))
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && found[0] == 0.0)
          {
            cell->get_dof_indices(dofs);
            for (unsigned int i = 0; i < dofs.size(); ++i)
              if (dofs[i] == best.second)
                {
                  const auto x = mapping.transform_unit_to_real_cell(
                    cell,
                    fe.get_unit_support_points()[i]);
                  found = {{1.0, x[0], x[1], x[2]}};
                  break;
                }
          }
    for (const auto &candidate :
         dealii::Utilities::MPI::all_gather(comm, found))
      if (candidate[0] == 1.0)
        found = candidate;
    return {best.first, dealii::Point<3>(found[1], found[2], found[3])};
  }

  WallCoordinates::WallCoordinates(const Parameters                  &params,
                                   const dealii::Triangulation<3, 3> &tria,
                                   const Geometry::BoundaryNames     &names,
                                   Logger                            *logger)
    : impl(std::make_unique<Impl>(tria, params.degree))
  {
    Impl &m = *impl;
    for (const std::string part : {"endocardium", "epicardium", "base"})
      {
        AssertThrow(names.has(part),
                    dealii::ExcMessage(
                      "Fibres / Generator = rule-based needs the boundary "
                      "parts endocardium, epicardium and base; " +
                      names.source() + " has no part '" + part + "'."));
        Geometry::require_boundary(tria, names, part);
      }
    const auto endo = names.id("endocardium"), epi = names.id("epicardium"),
               base = names.id("base");

    auto start = std::chrono::steady_clock::now();
    m.dof_handler.distribute_dofs(m.fe);
    m.owned = m.dof_handler.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(m.dof_handler, m.relevant);
    m.report.degree          = params.degree;
    m.report.n_dofs          = m.dof_handler.n_dofs();
    m.report.n_tangled_cells = m.count_tangled_cells();

    dealii::AffineConstraints<double> hanging(m.relevant);
    dealii::DoFTools::make_hanging_node_constraints(m.dof_handler, hanging);
    hanging.close();

    dealii::AffineConstraints<double> transmural_constraints(m.relevant);
    transmural_constraints.merge(hanging);
    dealii::VectorTools::interpolate_boundary_values(
      m.mapping,
      m.dof_handler,
      endo,
      dealii::Functions::ConstantFunction<3>(0.0),
      transmural_constraints);
    dealii::VectorTools::interpolate_boundary_values(
      m.mapping,
      m.dof_handler,
      epi,
      dealii::Functions::ConstantFunction<3>(1.0),
      transmural_constraints);
    transmural_constraints.close();

    const bool laplace = params.apicobasal == ApicobasalField::laplace;
    dealii::AffineConstraints<double> apicobasal_constraints(m.relevant);
    apicobasal_constraints.merge(hanging);
    dealii::VectorTools::interpolate_boundary_values(
      m.mapping,
      m.dof_handler,
      base,
      dealii::Functions::ConstantFunction<3>(laplace ? 1.0 : 0.0),
      apicobasal_constraints);
    if (laplace)
      {
        // psi = 0 at the apex vertex, on every rank that sees it.
        m.report.apex          = m.epicardial_apex(epi, base);
        const double tolerance = 1e-10 * dealii::GridTools::diameter(m.tria);
        unsigned int found     = 0;
        for (const auto &cell : m.dof_handler.active_cell_iterators())
          if (!cell->is_artificial())
            for (const unsigned int v : cell->vertex_indices())
              if (cell->vertex(v).distance(m.report.apex) < tolerance)
                {
                  const auto dof = cell->vertex_dof_index(v, 0);
                  if (!apicobasal_constraints.is_constrained(dof))
                    {
                      apicobasal_constraints.add_line(dof);
                      apicobasal_constraints.set_inhomogeneity(dof, 0.0);
                    }
                  found = 1;
                }
        AssertThrow(dealii::Utilities::MPI::max(found, m.comm) == 1,
                    dealii::ExcMessage("Rule-based fibres: no DoF at the apex "
                                       "vertex " +
                                       describe(m.report.apex) + "."));
      }
    apicobasal_constraints.close();
    m.report.setup_seconds = seconds_since(start);

    start = std::chrono::steady_clock::now();
    LA::MPI::Vector phi;
    const auto      transmural =
      m.solve(transmural_constraints, 0.0, phi, "transmural");
    m.report.transmural_iterations = transmural.iterations;
    m.report.transmural_direct     = transmural.direct;
    m.transmural.reinit(m.owned, m.relevant, m.comm);
    m.transmural                = phi;
    m.report.transmural_seconds = seconds_since(start);

    start = std::chrono::steady_clock::now();
    LA::MPI::Vector psi;
    const auto      apicobasal =
      m.solve(apicobasal_constraints, laplace ? 0.0 : 1.0, psi, "apicobasal");
    m.report.apicobasal_iterations = apicobasal.iterations;
    m.report.apicobasal_direct     = apicobasal.direct;
    if (!laplace)
      {
        // psi = 1 - u / max u: 1 on the base, 0 where u peaks (the apex).
        const auto [u_max, apex] = m.maximum(psi);
        AssertThrow(u_max > 0,
                    dealii::ExcMessage("Rule-based fibres: the apicobasal "
                                       "solve gave no positive values."));
        m.report.apex = apex;
        psi *= -1.0 / u_max;
        psi.add(1.0);
      }
    m.apicobasal.reinit(m.owned, m.relevant, m.comm);
    m.apicobasal                = psi;
    m.report.apicobasal_seconds = seconds_since(start);

    if (logger != nullptr)
      logger->line(m.report.summary());
  }

  WallCoordinates::~WallCoordinates() = default;

  const WallCoordinatesReport &
  WallCoordinates::report() const
  {
    return impl->report;
  }

  void
  WallCoordinates::evaluate(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<WallFrame>                                  &frames) const
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
    m.mapping.transform_points_real_to_unit_cell(
      cell,
      dealii::make_array_view(points),
      dealii::make_array_view(m.unit_points));
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
                  m.unit_points[i] =
                    dealii::GeometryInfo<3>::unit_cell_vertex(v);
                  vertex = true;
                }
            if (!vertex)
              try
                {
                  m.unit_points[i] =
                    m.mapping.transform_real_to_unit_cell(cell, points[i]);
                }
              catch (const dealii::Mapping<3>::ExcTransformationFailed &)
                {
                  m.unit_points[i] = m.nearest_grid_point(cell, points[i]);
                }
          }
        m.unit_points[i] =
          dealii::GeometryInfo<3>::project_to_unit_cell(m.unit_points[i]);
      }

    m.local_phi.reinit(m.fe.n_dofs_per_cell());
    m.local_psi.reinit(m.fe.n_dofs_per_cell());
    dof_cell->get_dof_values(m.transmural, m.local_phi);
    dof_cell->get_dof_values(m.apicobasal, m.local_psi);

    m.evaluator.reinit(cell, dealii::make_array_view(m.unit_points));
    const auto flags =
      dealii::EvaluationFlags::values | dealii::EvaluationFlags::gradients;
    std::vector<double>               phi(points.size()), psi(points.size());
    std::vector<dealii::Tensor<1, 3>> grad_phi(points.size()),
      grad_psi(points.size());
    m.evaluator.evaluate(dealii::make_array_view(m.local_phi), flags);
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        phi[i]      = m.evaluator.get_value(i);
        grad_phi[i] = m.evaluator.get_gradient(i);
      }
    m.evaluator.evaluate(dealii::make_array_view(m.local_psi), flags);
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        psi[i]      = m.evaluator.get_value(i);
        grad_psi[i] = m.evaluator.get_gradient(i);
      }

    frames.resize(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        WallFrame &w   = frames[i];
        w.transmural   = phi[i];
        w.apicobasal   = psi[i];
        const double g = grad_phi[i].norm();
        AssertThrow(
          std::isfinite(g) && g > 0,
          dealii::ExcMessage(
            "Rule-based fibres: the transmural gradient vanishes at " +
            describe(points[i]) + " (is the wall connected?)."));
        w.e_t = grad_phi[i] / g;
        // The wall-tangent part of grad psi. It vanishes only on the long
        // axis (the apex), where any tangent will do, as in the analytic rule.
        dealii::Tensor<1, 3> tangent =
          grad_psi[i] - (grad_psi[i] * w.e_t) * w.e_t;
        w.degenerate = !(tangent.norm() > 1e-6 * grad_psi[i].norm());
        if (w.degenerate)
          {
            unsigned int k = 0;
            for (unsigned int d = 1; d < 3; ++d)
              if (std::abs(w.e_t[d]) < std::abs(w.e_t[k]))
                k = d;
            dealii::Tensor<1, 3> axis;
            axis[k] = 1.0;
            tangent = axis - (axis * w.e_t) * w.e_t;
          }
        w.e_l = tangent / tangent.norm();
        w.e_c = dealii::cross_product_3d(w.e_l, w.e_t);
      }
  }

  RuleBased::RuleBased(const Parameters                  &params,
                       const dealii::Triangulation<3, 3> &tria,
                       const Geometry::BoundaryNames     &names,
                       Logger                            *logger)
    : params(params)
    , wall(params.coordinates, tria, names, logger)
  {}

  const WallCoordinates &
  RuleBased::coordinates() const
  {
    return wall;
  }

  FibreBasis
  RuleBased::basis(const WallFrame &w) const
  {
    // The discrete phi may leave [0, 1] by round-off (or a little more on
    // distorted cells): the helix angle stays within its end values.
    const double phi = std::max(0.0, std::min(1.0, w.transmural));
    const double alpha =
      params.alpha_endo + (params.alpha_epi - params.alpha_endo) * phi;
    FibreBasis b;
    b.f = std::sin(alpha) * w.e_l + std::cos(alpha) * w.e_c;
    const dealii::Tensor<1, 3> side = dealii::cross_product_3d(b.f, w.e_t);
    b.s = std::cos(params.beta) * w.e_t + std::sin(params.beta) * side;
    b.n = dealii::cross_product_3d(b.f, b.s);
    return b;
  }

  void
  RuleBased::operator()(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<FibreBasis>                                 &bases) const
  {
    std::vector<WallFrame> frames;
    wall.evaluate(cell, points, frames);
    bases.resize(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        bases[i] = basis(frames[i]);
        validate(bases[i], describe(points[i]) + " (rule-based generator)");
      }
  }
} // namespace systole::Fibres
