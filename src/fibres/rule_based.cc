#include "fibres/rule_based.h"

#include <deal.II/base/mpi.h>

#include "base/logger.h"
#include "fibres/frames.h"
#include "fibres/laplace_fields.h"
#include "geometry/mesh.h"
#include "geometry/point_location.h"

#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace systole::Fibres
{
  std::string
  WallCoordinatesReport::summary() const
  {
    std::ostringstream o;
    const auto solver = [](const unsigned int iterations, const bool direct) {
      return direct ? std::string("MUMPS (CG failed)")
                    : std::to_string(iterations) + " CG iterations";
    };
    o << std::fixed << std::setprecision(2) << "Rule-based fibres: " << element
      << ", " << n_dofs << " DOFs per solve; apex at "
      << Geometry::format_point(apex) << " mm\n  transmural "
      << solver(transmural_iterations, transmural_direct) << ", "
      << transmural_seconds << " s; apicobasal "
      << solver(apicobasal_iterations, apicobasal_direct) << ", "
      << apicobasal_seconds << " s; set-up " << setup_seconds << " s";
    if (n_tangled_cells > 0)
      o << ". WARNING: " << n_tangled_cells
        << " cell(s) of the mesh have a non-positive Jacobian at a quadrature "
           "point (tangled); the fibres near them are unreliable";
    return o.str();
  }

  WallFrame
  wall_frame(const FieldValue       &phi,
             const FieldValue       &psi,
             const dealii::Point<3> &where,
             const std::string      &what)
  {
    WallFrame w;
    w.transmural   = phi.value;
    w.apicobasal   = psi.value;
    const double g = phi.gradient.norm();
    AssertThrow(std::isfinite(g) && g > 0,
                dealii::ExcMessage(what +
                                   ": the transmural gradient vanishes at " +
                                   Geometry::format_point(where) +
                                   " (is the wall connected?)."));
    w.e_t = phi.gradient / g;
    // The wall-tangent part of grad psi. It vanishes only on the long axis
    // (the apex), where any tangent will do, as in the analytic rule.
    const dealii::Tensor<1, 3> &grad_psi = psi.gradient;
    dealii::Tensor<1, 3>        tangent = grad_psi - (grad_psi * w.e_t) * w.e_t;
    w.degenerate = !(tangent.norm() > 1e-6 * grad_psi.norm());
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
    return w;
  }

  struct WallCoordinates::Impl
  {
    explicit Impl(const dealii::Triangulation<3, 3> &tria)
      : tria(tria)
      , comm(tria.get_communicator())
    {}

    const dealii::Triangulation<3, 3> &tria;
    MPI_Comm                           comm;
    /// The transmural (0) and apicobasal (1) fields.
    std::unique_ptr<LaplaceFields> fields;
    WallCoordinatesReport          report;

    // Scratch of evaluate() (the object is used from one thread).
    mutable std::vector<std::vector<FieldValue>> values;

    /// The apex: the epicardial vertex farthest from the base plane (whose
    /// normal's sign does not matter).
    dealii::Point<3>
    epicardial_apex(const dealii::types::boundary_id epi,
                    const dealii::types::boundary_id base) const;
  };

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

  WallCoordinates::WallCoordinates(const Parameters                  &params,
                                   const dealii::Triangulation<3, 3> &tria,
                                   const Geometry::BoundaryNames     &names,
                                   Logger                            *logger)
    : impl(std::make_unique<Impl>(tria))
  {
    Impl &m = *impl;
    Geometry::require_boundaries(tria,
                                 names,
                                 {"endocardium", "epicardium", "base"},
                                 "Fibres / Generator = rule-based needs the "
                                 "boundary parts endocardium, epicardium and "
                                 "base");
    const auto endo = names.id("endocardium"), epi = names.id("epicardium"),
               base = names.id("base");

    const auto     start   = std::chrono::steady_clock::now();
    const bool     laplace = params.apicobasal == ApicobasalField::laplace;
    LaplaceProblem transmural{"transmural", {{endo, 0.0}, {epi, 1.0}}, 0.0};
    LaplaceProblem apicobasal{"apicobasal",
                              {{base, laplace ? 1.0 : 0.0}},
                              laplace ? 0.0 : 1.0};
    if (laplace)
      {
        // Bayer: psi = 0 at the apex vertex.
        m.report.apex = m.epicardial_apex(epi, base);
        apicobasal.vertex_values.emplace_back(m.report.apex, 0.0);
      }
    const double apex_seconds = seconds_since(start);
    m.fields =
      std::make_unique<LaplaceFields>(tria,
                                      params.degree,
                                      std::vector<LaplaceProblem>{transmural,
                                                                  apicobasal});
    const LaplaceFields &fields    = *m.fields;
    m.report.element               = fields.element_name();
    m.report.degree                = params.degree;
    m.report.n_dofs                = fields.n_dofs();
    m.report.n_tangled_cells       = fields.n_tangled_cells();
    m.report.setup_seconds         = apex_seconds + fields.setup_seconds();
    m.report.transmural_iterations = fields.iterations()[0];
    m.report.transmural_direct     = fields.direct()[0];
    m.report.transmural_seconds    = fields.solve_seconds()[0];
    m.report.apicobasal_iterations = fields.iterations()[1];
    m.report.apicobasal_direct     = fields.direct()[1];
    m.report.apicobasal_seconds    = fields.solve_seconds()[1];
    if (!laplace)
      {
        // psi = 1 - u / max u: 1 on the base, 0 where u peaks (the apex).
        const auto [u_max, apex] = m.fields->maximum(1);
        AssertThrow(u_max > 0,
                    dealii::ExcMessage("Rule-based fibres: the apicobasal "
                                       "solve gave no positive values."));
        m.report.apex = apex;
        m.fields->scale(1, -1.0 / u_max, 1.0);
      }

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
    m.fields->evaluate(cell, points, m.values);
    const auto &phi = m.values[0], &psi = m.values[1];

    frames.resize(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      frames[i] = wall_frame(phi[i], psi[i], points[i], "Rule-based fibres");
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
    validated_bases(
      points,
      name,
      [&](const unsigned int i) { return basis(frames[i]); },
      bases);
  }
} // namespace systole::Fibres
