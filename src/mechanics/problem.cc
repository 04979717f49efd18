#include "mechanics/problem.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/errors.h"
#include "geometry/mesh.h"
#include "mechanics/problem_impl.h"

#include <chrono>
#include <iomanip>
#include <sstream>

namespace systole::Mechanics
{

  Problem::Impl::Impl(const Parameters &params,
                      dealii::parallel::distributed::Triangulation<3, 3> &tria,
                      const Geometry::BoundaryNames                      &names,
                      const unsigned int              degree,
                      const unsigned int              mapping_degree,
                      const Materials::PassiveLaw    &passive_law,
                      const Materials::VolumetricLaw &volumetric_law,
                      Logger                         &logger)
    : params(params)
    , tria(tria)
    , comm(tria.get_communicator())
    , logger(logger)
    , passive_law(passive_law)
    , volumetric_law(volumetric_law)
    , fe(dealii::FE_Q<3>(degree), 3)
    , mapping(mapping_degree)
    , dof_handler(tria)
    , n_q_1d(degree + 1)
    // The cavity volume, the pressure load and their derivatives are
    // polynomials of degree 3p - 1 per face coordinate (p the larger of the
    // two degrees): p + 1 Gauss points integrate them exactly for p <= 2.
    , n_q_face_1d(std::max(degree, mapping_degree) + 1)
    , reduced_volumetric(params.reduced_volumetric_integration && degree > 1)
  {
    mapping.initialize(dealii::MappingQ<3>(mapping_degree), tria);
  }

  Problem::Problem(const Parameters                                   &params,
                   dealii::parallel::distributed::Triangulation<3, 3> &tria,
                   const Geometry::BoundaryNames                      &names,
                   const unsigned int                                  degree,
                   const unsigned int              mapping_degree,
                   const Materials::PassiveLaw    &passive_law,
                   const Materials::VolumetricLaw &volumetric_law,
                   const FibreFunction            &fibres,
                   Logger                         &logger)
    : impl(std::make_unique<Impl>(params,
                                  tria,
                                  names,
                                  degree,
                                  mapping_degree,
                                  passive_law,
                                  volumetric_law,
                                  logger))
  {
    Impl &m = *impl;

    // Boundary parts: each named part must exist and carry faces.
    const auto ids = [&](const std::vector<std::string> &parts,
                         const std::string              &entry) {
      std::set<dealii::types::boundary_id> result;
      for (const auto &part : parts)
        {
          std::string known;
          for (const auto &name : names.names())
            known += (known.empty() ? "" : ", ") + name;
          if (!names.has(part))
            AssertThrow(false,
                        dealii::ExcMessage(
                          "Mechanics / " + entry + " names boundary part '" +
                          part + "': " + names.source() +
                          " has no such part (it has: " + known + ")."));
          Geometry::require_boundary(tria, names, part);
          result.insert(names.id(part));
        }
      return result;
    };
    m.fixed_ids   = ids(params.fixed_boundaries, "Fixed boundaries");
    m.sliding_ids = ids(params.sliding_boundaries, "Sliding boundaries");
    m.robin_ids   = ids(params.robin_boundaries, "Robin boundaries");
    if (!params.pressure_boundary.empty())
      m.pressure_id =
        *ids({params.pressure_boundary}, "Pressure boundary").begin();
    if (params.pressure_boundary == "endocardium" && names.has("base"))
      {
        Geometry::require_boundary(tria, names, "base");
        m.cavity.emplace(*m.pressure_id,
                         Geometry::boundary_plane(tria,
                                                  names.id("base"),
                                                  "base"));
      }

    // DoFs and constraints (zero displacement on fixed parts, zero normal
    // displacement on sliding ones: the Newton updates are homogeneous too).
    m.dof_handler.distribute_dofs(m.fe);
    m.owned = m.dof_handler.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(m.dof_handler, m.relevant);
    m.constraints.reinit(m.relevant);
    dealii::DoFTools::make_hanging_node_constraints(m.dof_handler,
                                                    m.constraints);
    for (const auto id : m.fixed_ids)
      dealii::VectorTools::interpolate_boundary_values(
        m.mapping,
        m.dof_handler,
        id,
        dealii::Functions::ZeroFunction<3>(3),
        m.constraints);
    if (!m.sliding_ids.empty())
      dealii::VectorTools::compute_no_normal_flux_constraints(m.dof_handler,
                                                              0,
                                                              m.sliding_ids,
                                                              m.constraints,
                                                              m.mapping);
    m.constraints.close();

    dealii::DynamicSparsityPattern dsp(m.relevant);
    dealii::DoFTools::make_sparsity_pattern(m.dof_handler,
                                            dsp,
                                            m.constraints,
                                            false);
    dealii::SparsityTools::distribute_sparsity_pattern(dsp,
                                                       m.owned,
                                                       m.comm,
                                                       m.relevant);
    m.tangent.reinit(m.owned, m.owned, dsp, m.comm);
    m.residual.reinit(m.owned, m.comm);
    m.volume_derivative.reinit(m.owned, m.comm);
    m.u_owned.reinit(m.owned, m.comm);
    m.u_saved.reinit(m.owned, m.comm);
    m.u_previous.reinit(m.owned, m.comm);
    m.u.reinit(m.owned, m.relevant, m.comm);

    // Fibre frames at the quadrature points of the locally owned cells.
    const dealii::QGauss<3> quadrature(m.n_q_1d);
    dealii::FEValues<3>     fe_values(m.mapping,
                                  m.fe,
                                  quadrature,
                                  dealii::update_quadrature_points);
    m.fibre_bases.resize(tria.n_active_cells());
    m.quadrature_points.resize(tria.n_active_cells());
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          m.quadrature_points[cell->active_cell_index()] =
            fe_values.get_quadrature_points();
          fibres(cell,
                 fe_values.get_quadrature_points(),
                 m.fibre_bases[cell->active_cell_index()]);
        }

    std::string solver = params.linear_solver;
    if (solver == "auto")
      solver = m.dof_handler.n_dofs() <= params.direct_solver_limit
                 ? "direct"
                 : "iterative";
    // The tangent is symmetric when every load derives from a potential: the
    // hyperelastic energy, the springs, and a pressure on a cavity (whose load
    // is the exact derivative of the discrete cavity volume, so its tangent is
    // a Hessian). A follower pressure on an open surface is not.
    const bool symmetric = !m.pressure_id.has_value() || m.cavity.has_value();
    m.linear_solver      = create_linear_solver(solver,
                                           m.mapping,
                                           m.dof_handler,
                                           params.linear_tolerance,
                                           symmetric);
  }

  Problem::~Problem() = default;

  unsigned int
  Problem::Impl::linear_solve(LA::MPI::Vector       &x,
                              const LA::MPI::Vector &b,
                              const unsigned int     iteration,
                              const double           relative)
  {
    try
      {
        x                      = 0;
        const unsigned int its = linear_solver->solve(x, b);
        constraints.distribute(x);
        return its;
      }
    catch (const dealii::ExceptionBase &e)
      {
        AssertThrow(false,
                    ExcNewtonDidNotConverge(std::string("linear solver: ") +
                                              one_line_message(e),
                                            iteration,
                                            relative));
      }
    return 0;
  }

  NewtonReport
  Problem::solve(const double pressure, const double active_tension)
  {
    double p = pressure;
    return impl->newton(p, active_tension, nullptr);
  }

  NewtonReport
  Problem::solve_volume(const double target_volume,
                        const double active_tension,
                        double      &pressure)
  {
    AssertThrow(impl->cavity.has_value(),
                dealii::ExcMessage("A volume constraint needs a cavity (the "
                                   "pressure boundary must be the endocardium "
                                   "and the mesh must have a base)."));
    return impl->newton(pressure, active_tension, &target_volume);
  }

  NewtonReport
  Problem::Impl::newton(double       &pressure,
                        const double  active_tension,
                        const double *target_volume)
  {
    Impl           &m = *this;
    NewtonReport    report;
    LA::MPI::Vector du(m.owned, m.comm), w_volume(m.owned, m.comm);
    double          residual     = 0;
    double          volume_error = 0; // |V(u) - V_target| / V_target
    const bool      bordered     = target_volume != nullptr;

    auto &out = m.logger.detail();
    // Residual scale: the largest residual seen in this solve, and for a
    // volume-constrained solve at least the cavity pressure load |p b| (a
    // solve that starts close to equilibrium is not held to a fraction of
    // its tiny first residual).
    double     reference     = 0;
    const auto pressure_load = [&](const LA::MPI::Vector &b) {
      return bordered ? std::abs(pressure) * b.l2_norm() : 0.0;
    };
    double du_norm = 0;

    // Residual and tangent (and dV/du when bordered) at the current u; false
    // if an element inverted or the residual is not finite (decided on all
    // ranks alike).
    double     assembly_seconds = 0, solver_seconds = 0;
    const auto seconds_since = [](const auto start) {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                           start)
        .count();
    };
    // Residual (with_matrix: and tangent and dV/du) at the current u.
    const auto try_assemble = [&](double &norm, const bool with_matrix) {
      const auto start = std::chrono::steady_clock::now();
      try
        {
          norm = m.assemble(pressure,
                            active_tension,
                            with_matrix,
                            with_matrix && bordered);
          if (bordered)
            volume_error =
              (cavity_volume_now() - *target_volume) / *target_volume;
          assembly_seconds += seconds_since(start);
        }
      catch (const ExcInvertedElement &)
        {
          return false;
        }
      return std::isfinite(norm) && std::isfinite(volume_error);
    };

    // Chord iterations on the factorization of an earlier solve: residual
    // only, one back substitution per iteration, the bordered system of that
    // tangent; left as soon as they stop converging fast.
    if (bordered && m.have_factorization)
      {
        const LA::MPI::Vector u_start        = m.u_owned;
        const double          pressure_start = pressure;
        const double b0_w0 = m.factorized_volume_derivative * m.factorized_w;
        bool         ok    = try_assemble(residual, false) && b0_w0 != 0.0;
        double       start_residual                 = residual;
        constexpr unsigned int max_chord_iterations = 12;
        for (unsigned int it = 0; ok; ++it)
          {
            reference =
              std::max({reference,
                        residual,
                        pressure_load(m.factorized_volume_derivative)});
            if (std::abs(volume_error) <= volume_tolerance &&
                (residual <= m.params.newton_absolute_tolerance ||
                 residual <= m.params.newton_relative_tolerance * reference))
              {
                report.final_residual   = residual;
                report.initial_residual = start_residual;
                return report;
              }
            if (it == max_chord_iterations)
              break;
            m.residual *= -1.0;
            const auto solver_start = std::chrono::steady_clock::now();
            try
              {
                du = 0;
                m.linear_solver->solve(du, m.residual);
                m.constraints.distribute(du);
              }
            catch (const dealii::ExceptionBase &)
              {
                ok = false;
                break;
              }
            const double g = volume_error * *target_volume;
            const double dp =
              -(g + m.factorized_volume_derivative * du) / b0_w0;
            du.add(dp, m.factorized_w);
            solver_seconds += seconds_since(solver_start);
            m.u_owned.add(1.0, du);
            m.u = m.u_owned;
            pressure += dp;
            ++report.reused_iterations;
            const double previous = residual;
            ok                    = try_assemble(residual, false);
            out << "      chord " << report.reused_iterations
                << ": |R| = " << std::scientific << std::setprecision(3)
                << residual << "  |dV|/V = " << std::abs(volume_error)
                << "  p = " << pressure << std::defaultfloat << std::endl;
            // (The first iteration mostly corrects the volume, which |R|
            // does not measure: judge the rate from the second on.)
            if (ok && it > 0 && !(residual < 0.3 * previous))
              break; // slow: continue with full Newton from here
          }
        if (!ok || !(residual < start_residual))
          {
            // Failed or no better: full Newton from the start.
            m.u_owned = u_start;
            m.u       = m.u_owned;
            pressure  = pressure_start;
          }
        reference = 0;
        out << "      (" << report.reused_iterations
            << " chord iterations on the old factorization)" << std::endl;
      }

    AssertThrow(try_assemble(residual, false),
                ExcNewtonDidNotConverge("an element is inverted at the start "
                                        "of the load step",
                                        0,
                                        1.0));
    report.initial_residual = residual;
    for (unsigned int it = 0;; ++it)
      {
        reference = std::max(reference, residual);
        if (it > 0)
          reference = std::max(reference, pressure_load(m.volume_derivative));
        const double relative = residual / std::max(reference, 1e-300);
        const double u_norm   = m.u_owned.l2_norm();
        if (it > 0)
          {
            out << "      Newton " << std::setw(2) << it
                << ": |R| = " << std::scientific << std::setprecision(3)
                << residual << "  |R|/|R|max = " << relative
                << "  |du|/|u| = " << du_norm / std::max(u_norm, 1e-300);
            if (bordered)
              out << "  |dV|/V = " << std::abs(volume_error)
                  << "  p = " << pressure;
            out << std::defaultfloat << std::setprecision(2) << "  (assembly "
                << assembly_seconds << " s, solver " << solver_seconds << " s)"
                << std::endl;
          }
        // Converged: the residual fell by the relative tolerance, or is at
        // the absolute floor, or the last update was at round-off level; and
        // the cavity volume is on its target.
        const bool volume_ok =
          !bordered || std::abs(volume_error) <= volume_tolerance;
        if (volume_ok &&
            (residual <= m.params.newton_absolute_tolerance ||
             (it > 0 && (relative <= m.params.newton_relative_tolerance ||
                         du_norm <= 1e-12 * u_norm))))
          {
            report.iterations     = it;
            report.final_residual = residual;
            return report;
          }
        AssertThrow(it < m.params.max_newton_iterations,
                    ExcNewtonDidNotConverge(bordered ? "volume-constrained "
                                                       "step"
                                                     : "load step",
                                            it,
                                            relative));

        // K du = -R; bordered by the volume constraint g = V(u) - V_target:
        // [K -b; b^T 0] [du; dp] = -[R; g] with b = dV/du. Two solves with
        // one factorization: K w_R = -R, K w_b = b; then
        // dp = -(g + b.w_R) / (b.w_b), du = w_R + dp w_b.
        // The tangent (and dV/du) at this iterate; the residual again.
        try_assemble(residual, true);
        m.residual *= -1.0;
        const auto solver_start = std::chrono::steady_clock::now();
        try
          {
            m.linear_solver->setup(m.tangent);
          }
        catch (const dealii::ExceptionBase &e)
          {
            AssertThrow(false,
                        ExcNewtonDidNotConverge(std::string("linear solver: ") +
                                                  one_line_message(e),
                                                it,
                                                relative));
          }
        report.linear_iterations +=
          m.linear_solve(du, m.residual, it, relative);
        double dp = 0;
        if (bordered)
          {
            report.linear_iterations +=
              m.linear_solve(w_volume, m.volume_derivative, it, relative);
            const double g = volume_error * *target_volume;
            // b.w with the constrained entries of the distributed w: b is
            // condensed (zero there), so the plain dot product is b^T w.
            dp = -(g + m.volume_derivative * du) /
                 (m.volume_derivative * w_volume);
            du.add(dp, w_volume);
            m.factorized_volume_derivative = m.volume_derivative;
            m.factorized_w                 = w_volume;
            m.have_factorization           = true;
          }
        solver_seconds += seconds_since(solver_start);

        // Safeguarded update: halve the step while it inverts an element. (A
        // residual-norm merit test is no use here: the first iterations of a
        // load step that rotates the body raise |R| by orders of magnitude
        // on their way to the solution.)
        const LA::MPI::Vector u_start        = m.u_owned;
        const double          pressure_start = pressure;
        double                alpha          = 1.0;
        for (unsigned int cut = 0;; ++cut)
          {
            m.u_owned = u_start;
            m.u_owned.add(alpha, du);
            m.u          = m.u_owned;
            pressure     = pressure_start + alpha * dp;
            double trial = 0;
            if (try_assemble(trial, false))
              {
                residual = trial;
                break;
              }
            AssertThrow(cut < 6,
                        ExcNewtonDidNotConverge("no acceptable step length",
                                                it,
                                                relative));
            alpha *= 0.5;
          }
        if (alpha < 1.0)
          out << "      (step length " << alpha << ")" << std::endl;
        du_norm = alpha * du.l2_norm();
      }
  }

  double
  Problem::Impl::cavity_volume_now() const
  {
    return cavity->volume(mapping, dof_handler, u, n_q_face_1d);
  }

  double
  Problem::tangent_error(const double pressure,
                         const double active_tension,
                         const double h)
  {
    Impl &m = *impl;
    m.assemble(pressure, active_tension, true);
    LA::MPI::Vector d(m.owned, m.comm), Kd(m.owned, m.comm);
    for (const auto i : m.owned)
      d(i) = std::sin(1.0 + 0.37 * i) * std::cos(0.11 * i);
    d.compress(dealii::VectorOperation::insert);
    m.constraints.set_zero(d);
    m.tangent.vmult(Kd, d);

    const LA::MPI::Vector u0          = m.u_owned;
    const auto            residual_at = [&](const double step) {
      m.u_owned = u0;
      m.u_owned.add(step, d);
      m.u = m.u_owned;
      m.assemble(pressure, active_tension, false);
      return LA::MPI::Vector(m.residual);
    };
    LA::MPI::Vector difference = residual_at(h);
    difference -= residual_at(-h);
    difference /= 2.0 * h;
    m.u_owned = u0;
    m.u       = m.u_owned;

    difference -= Kd;
    return difference.l2_norm() / Kd.l2_norm();
  }

  std::array<double, 2>
  Problem::bordered_jacobian_error(const double pressure,
                                   const double active_tension,
                                   const double h)
  {
    Impl &m = *impl;
    m.assemble(pressure, active_tension, true, true);
    LA::MPI::Vector d(m.owned, m.comm), Jd(m.owned, m.comm);
    for (const auto i : m.owned)
      d(i) = std::sin(1.0 + 0.37 * i) * std::cos(0.11 * i);
    d.compress(dealii::VectorOperation::insert);
    m.constraints.set_zero(d);
    const double dp = 0.3 * std::max(std::abs(pressure), 1.0);
    // First block row: K d - b dp (R depends on p through -p b); second: b.d.
    m.tangent.vmult(Jd, d);
    Jd.add(-dp, m.volume_derivative);
    const double volume_row = m.volume_derivative * d;

    const LA::MPI::Vector u0          = m.u_owned;
    const auto            evaluate_at = [&](const double step, double &volume) {
      m.u_owned = u0;
      m.u_owned.add(step, d);
      m.u = m.u_owned;
      m.assemble(pressure + step * dp, active_tension, false);
      volume = m.cavity_volume_now();
      return LA::MPI::Vector(m.residual);
    };
    double          v_plus = 0, v_minus = 0;
    LA::MPI::Vector difference = evaluate_at(h, v_plus);
    difference -= evaluate_at(-h, v_minus);
    difference /= 2.0 * h;
    m.u_owned = u0;
    m.u       = m.u_owned;

    difference -= Jd;
    const double volume_difference = (v_plus - v_minus) / (2.0 * h);
    return {{difference.l2_norm() / Jd.l2_norm(),
             std::abs(volume_difference - volume_row) / std::abs(volume_row)}};
  }

  void
  Problem::quadrature_points(
    std::vector<std::vector<dealii::Point<3>>> &points) const
  {
    points = impl->quadrature_points;
  }

  void
  Problem::set_active_tension(std::vector<std::vector<double>> tension)
  {
    AssertThrow(tension.empty() ||
                  tension.size() == impl->quadrature_points.size(),
                dealii::ExcMessage("set_active_tension: one vector per cell "
                                   "(by active cell index) expected."));
    impl->active_tension_field = std::move(tension);
  }

  void
  Problem::set_displacement(const dealii::Function<3> &displacement)
  {
    dealii::VectorTools::interpolate(impl->mapping,
                                     impl->dof_handler,
                                     displacement,
                                     impl->u_owned);
    impl->constraints.distribute(impl->u_owned);
    impl->u = impl->u_owned;
  }

  void
  Problem::save()
  {
    impl->u_previous = impl->u_saved;
    impl->u_saved    = impl->u_owned;
    ++impl->n_saves;
  }

  void
  Problem::predict(const double ratio)
  {
    Impl &m   = *impl;
    m.u_owned = m.u_saved;
    if (m.n_saves >= 2)
      {
        m.u_owned.add(ratio, m.u_saved);
        m.u_owned.add(-ratio, m.u_previous);
      }
    m.u = m.u_owned;
  }

  void
  Problem::restore()
  {
    impl->u_owned = impl->u_saved;
    impl->u       = impl->u_owned;
  }

  bool
  Problem::has_cavity() const
  {
    return impl->cavity.has_value();
  }

  double
  Problem::cavity_volume() const
  {
    AssertThrow(impl->cavity.has_value(),
                dealii::ExcMessage("This problem has no cavity (the pressure "
                                   "boundary is not the endocardium or the "
                                   "mesh has no base)."));
    return impl->cavity->volume(impl->mapping,
                                impl->dof_handler,
                                impl->u,
                                impl->n_q_face_1d);
  }

  std::vector<dealii::Point<3>>
  Problem::deformed_positions(const std::vector<dealii::Point<3>> &points) const
  {
    const Impl        &m    = *impl;
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(m.comm);
    std::vector<dealii::Point<3>> result(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        // Every rank looks for a locally owned cell that holds the point; the
        // lowest such rank reports its value.
        std::pair<dealii::DoFHandler<3>::active_cell_iterator, dealii::Point<3>>
                     found;
        unsigned int holder = dealii::numbers::invalid_unsigned_int;
        try
          {
            const auto cells =
              dealii::GridTools::find_all_active_cells_around_point(
                m.mapping,
                m.dof_handler,
                points[i],
                1e-10);
            for (const auto &c : cells)
              if (c.first->is_locally_owned())
                {
                  found  = c;
                  holder = rank;
                  break;
                }
          }
        catch (...)
          {}
        holder = dealii::Utilities::MPI::min(holder, m.comm);
        AssertThrow(holder != dealii::numbers::invalid_unsigned_int,
                    dealii::ExcMessage(
                      "Mechanics / Tracked points: the point (" +
                      dealii::Utilities::to_string(points[i][0]) + ", " +
                      dealii::Utilities::to_string(points[i][1]) + ", " +
                      dealii::Utilities::to_string(points[i][2]) +
                      ") lies outside the mesh."));
        dealii::Tensor<1, 3> value;
        if (holder == rank)
          {
            const dealii::Quadrature<3> at(
              dealii::GeometryInfo<3>::project_to_unit_cell(found.second));
            dealii::FEValues<3> fe_values(m.mapping,
                                          m.fe,
                                          at,
                                          dealii::update_values);
            fe_values.reinit(found.first);
            std::vector<dealii::Tensor<1, 3>> u_at(1);
            fe_values[dealii::FEValuesExtractors::Vector(0)]
              .get_function_values(m.u, u_at);
            value = u_at[0];
          }
        value     = dealii::Utilities::MPI::sum(value, m.comm);
        result[i] = points[i] + value;
      }
    return result;
  }

  void
  Problem::attach_output(dealii::DataOut<3, 3> &data_out) const
  {
    data_out.attach_dof_handler(impl->dof_handler);
    const std::vector<
      dealii::DataComponentInterpretation::DataComponentInterpretation>
      vector(3,
             dealii::DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(impl->u,
                             std::vector<std::string>(3, "displacement"),
                             dealii::DataOut<3>::type_dof_data,
                             vector);
  }

  const dealii::Mapping<3, 3> &
  Problem::mapping() const
  {
    return impl->mapping;
  }

  dealii::types::global_dof_index
  Problem::n_dofs() const
  {
    return impl->dof_handler.n_dofs();
  }

  std::string
  Problem::linear_solver_name() const
  {
    return impl->linear_solver->name();
  }
} // namespace systole::Mechanics
