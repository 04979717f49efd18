#include "fibres/arostica.h"

#include "base/logger.h"
#include "fibres/frames.h"
#include "fibres/laplace_fields.h"
#include "geometry/mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace systole::Fibres
{
  Arostica::Arostica(const Parameters                  &params,
                     const Geometry::LVShape           &shape,
                     const dealii::Triangulation<3, 3> &tria,
                     const Geometry::BoundaryNames     &names,
                     Logger                            *logger)
    : params(params)
    , shape(shape)
  {
    Geometry::require_boundaries(tria,
                                 names,
                                 {"endocardium", "epicardium"},
                                 "Fibres / Generator = arostica needs the "
                                 "boundary parts endocardium and epicardium");
    const auto start = std::chrono::steady_clock::now();
    // Zero flux on every other part (the base).
    fields = std::make_unique<LaplaceFields>(tria,
                                             params.degree,
                                             std::vector<LaplaceProblem>{
                                               {"transmural",
                                                {{names.id("endocardium"), 0.0},
                                                 {names.id("epicardium"), 1.0}},
                                                0.0}});
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();
    if (logger != nullptr)
      {
        std::ostringstream o;
        o << std::fixed << std::setprecision(2)
          << "Arostica fibres: " << fields->element_name() << ", "
          << fields->n_dofs() << " DOFs, CG iterations (0: MUMPS) "
          << fields->iterations()[0] << "; " << seconds << " s";
        logger->line(o.str());
      }
  }

  Arostica::~Arostica() = default;

  FibreBasis
  Arostica::basis(const dealii::Point<3> &point, const double t) const
  {
    // In the generator's frame (long axis z, apex at -z) the benchmark's
    // parametrisation reads x = r_s sin mu cos theta, y = r_s sin mu sin
    // theta, z = r_l cos mu (its frame is the cyclic turn (z, x, y)).
    const dealii::Point<3> X  = shape.to_generator_frame(point);
    const double           rs = shape.short_radius(t);
    const double           rl = shape.long_radius(t);
    double                 x = X[0], y = X[1];
    if (std::hypot(x, y) < 1e-8 * rs) // on the axis: step off it
      x = 1e-8 * rs;
    const double rho = std::hypot(x, y);
    // mu = -atan2(rho / r_s, z / r_l), in [-pi, 0]; sin mu < 0.
    const double a = rho / rs, b = X[2] / rl, h = std::hypot(a, b);
    const double sin_mu = -a / h, cos_mu = b / h;
    const double cos_theta = -x / rho, sin_theta = -y / rho;

    dealii::Tensor<1, 3> e_mu(
      {rs * cos_mu * cos_theta, rs * cos_mu * sin_theta, -rl * sin_mu});
    dealii::Tensor<1, 3> e_theta(
      {-rs * sin_mu * sin_theta, rs * sin_mu * cos_theta, 0.0});
    e_mu /= e_mu.norm();
    e_theta /= e_theta.norm();

    const double alpha =
      params.alpha_endo + (params.alpha_epi - params.alpha_endo) * t;
    FibreBasis b_gen;
    b_gen.f = std::sin(alpha) * e_mu + std::cos(alpha) * e_theta;
    b_gen.f /= b_gen.f.norm();
    dealii::Tensor<1, 3> n_b = dealii::cross_product_3d(e_mu, e_theta);
    n_b /= n_b.norm();
    b_gen.s = dealii::cross_product_3d(b_gen.f, n_b);
    b_gen.s /= b_gen.s.norm();
    b_gen.n = -n_b;

    FibreBasis result;
    result.f = shape.from_generator_frame(b_gen.f);
    result.s = shape.from_generator_frame(b_gen.s);
    result.n = shape.from_generator_frame(b_gen.n);
    return result;
  }

  void
  Arostica::transmural(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<double>                                     &values) const
  {
    const auto clamped = [](const auto &v, const unsigned int i) {
      return std::clamp(v[0][i].value, 0.0, 1.0);
    };
    fields->evaluate_each(cell, points, values, clamped);
  }

  void
  Arostica::operator()(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<FibreBasis>                                 &bases) const
  {
    std::vector<double> t;
    transmural(cell, points, t);
    validated_bases(
      points,
      name,
      [&](const unsigned int i) { return basis(points[i], t[i]); },
      bases);
  }
} // namespace systole::Fibres
