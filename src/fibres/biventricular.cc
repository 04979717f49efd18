#include "fibres/biventricular.h"

#include <deal.II/base/parameter_handler.h>

#include "base/logger.h"
#include "fibres/frames.h"
#include "fibres/laplace_fields.h"
#include "geometry/mesh.h"
#include "geometry/point_location.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace systole::Fibres
{
  namespace
  {
    double
    dot(const Quaternion &a, const Quaternion &b)
    {
      return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    }

    /// a b (Hamilton product).
    Quaternion
    multiply(const Quaternion &a, const Quaternion &b)
    {
      return {{a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
               a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
               a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
               a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]}};
    }

    /// The field's direction, or @p fallback's where it vanishes.
    dealii::Tensor<1, 3>
    direction(const dealii::Tensor<1, 3> &v,
              const dealii::Tensor<1, 3> &fallback)
    {
      return v.norm() > 1e-12 ? v : fallback;
    }
  } // namespace

  Quaternion
  quaternion(const FibreBasis &b)
  {
    // R(i, j): column j is f, s, n.
    const auto R = [&b](const unsigned int i, const unsigned int j) {
      return j == 0 ? b.f[i] : (j == 1 ? b.s[i] : b.n[i]);
    };
    const double trace = R(0, 0) + R(1, 1) + R(2, 2);
    Quaternion   q;
    // Shepperd: divide by the largest of the four candidate components.
    if (trace >= R(0, 0) && trace >= R(1, 1) && trace >= R(2, 2))
      {
        const double w = 0.5 * std::sqrt(std::max(0.0, 1.0 + trace));
        q              = {{w,
                           (R(2, 1) - R(1, 2)) / (4 * w),
                           (R(0, 2) - R(2, 0)) / (4 * w),
                           (R(1, 0) - R(0, 1)) / (4 * w)}};
      }
    else if (R(0, 0) >= R(1, 1) && R(0, 0) >= R(2, 2))
      {
        const double x =
          0.5 * std::sqrt(std::max(0.0, 1.0 + R(0, 0) - R(1, 1) - R(2, 2)));
        q = {{(R(2, 1) - R(1, 2)) / (4 * x),
              x,
              (R(0, 1) + R(1, 0)) / (4 * x),
              (R(0, 2) + R(2, 0)) / (4 * x)}};
      }
    else if (R(1, 1) >= R(2, 2))
      {
        const double y =
          0.5 * std::sqrt(std::max(0.0, 1.0 - R(0, 0) + R(1, 1) - R(2, 2)));
        q = {{(R(0, 2) - R(2, 0)) / (4 * y),
              (R(0, 1) + R(1, 0)) / (4 * y),
              y,
              (R(1, 2) + R(2, 1)) / (4 * y)}};
      }
    else
      {
        const double z =
          0.5 * std::sqrt(std::max(0.0, 1.0 - R(0, 0) - R(1, 1) + R(2, 2)));
        q = {{(R(1, 0) - R(0, 1)) / (4 * z),
              (R(0, 2) + R(2, 0)) / (4 * z),
              (R(1, 2) + R(2, 1)) / (4 * z),
              z}};
      }
    const double norm = std::sqrt(dot(q, q));
    for (double &c : q)
      c /= norm;
    return q;
  }

  FibreBasis
  basis(const Quaternion &q)
  {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    FibreBasis   b;
    b.f = dealii::Tensor<1, 3>(
      {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)});
    b.s = dealii::Tensor<1, 3>(
      {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)});
    b.n = dealii::Tensor<1, 3>(
      {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)});
    return b;
  }

  Quaternion
  slerp(const Quaternion &q0, const Quaternion &q1, const double t)
  {
    Quaternion a = q0;
    double     c = dot(a, q1);
    if (c < 0)
      {
        for (double &x : a)
          x = -x;
        c = -c;
      }
    Quaternion q;
    if (c > 1.0 - 1e-12)
      for (unsigned int i = 0; i < 4; ++i)
        q[i] = (1 - t) * a[i] + t * q1[i];
    else
      {
        const double theta = std::acos(c), s = std::sin(theta);
        const double w0 = std::sin((1 - t) * theta) / s,
                     w1 = std::sin(t * theta) / s;
        for (unsigned int i = 0; i < 4; ++i)
          q[i] = w0 * a[i] + w1 * q1[i];
      }
    const double norm = std::sqrt(dot(q, q));
    for (double &x : q)
      x /= norm;
    return q;
  }

  FibreBasis
  bislerp(const FibreBasis &a, const FibreBasis &b, const double t)
  {
    const Quaternion qa = quaternion(a), qb = quaternion(b);
    // a turned by pi about its own f, s, n: right multiplication by i, j, k.
    Quaternion best = qa;
    for (const Quaternion &axis : {Quaternion{{0, 1, 0, 0}},
                                   Quaternion{{0, 0, 1, 0}},
                                   Quaternion{{0, 0, 0, 1}}})
      {
        const Quaternion candidate = multiply(qa, axis);
        if (std::abs(dot(candidate, qb)) > std::abs(dot(best, qb)))
          best = candidate;
      }
    return basis(slerp(best, qb, t));
  }

  FibreBasis
  wall_basis(const dealii::Tensor<1, 3> &transmural,
             const dealii::Tensor<1, 3> &apicobasal,
             const double                alpha,
             const double                beta)
  {
    const dealii::Tensor<1, 3> e_t     = transmural / transmural.norm();
    dealii::Tensor<1, 3>       tangent = apicobasal - (apicobasal * e_t) * e_t;
    if (!(tangent.norm() > 1e-6 * apicobasal.norm()))
      {
        // On the long axis (the apex) any tangent will do.
        unsigned int k = 0;
        for (unsigned int d = 1; d < 3; ++d)
          if (std::abs(e_t[d]) < std::abs(e_t[k]))
            k = d;
        dealii::Tensor<1, 3> axis;
        axis[k] = 1.0;
        tangent = axis - (axis * e_t) * e_t;
      }
    const dealii::Tensor<1, 3> e_l = tangent / tangent.norm();
    const dealii::Tensor<1, 3> e_c = dealii::cross_product_3d(e_l, e_t);
    FibreBasis                 b;
    b.f = std::sin(alpha) * e_l + std::cos(alpha) * e_c;
    const dealii::Tensor<1, 3> side = dealii::cross_product_3d(b.f, e_t);
    b.s = std::cos(beta) * e_t + std::sin(beta) * side;
    b.n = dealii::cross_product_3d(b.f, b.s);
    return b;
  }

  void
  Biventricular::Parameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Double;
    prm.enter_subsection("Fibres");
    prm.enter_subsection("Biventricular");
    const auto angle = [&prm](const std::string &entry,
                              const std::string &value,
                              const std::string &help) {
      prm.declare_entry(entry,
                        value,
                        Double(-90, 90),
                        help + " Units: degrees.");
    };
    // Defaults: the common choice of physiology.md (Bayer et al. 2012).
    angle("LV helix angle endocardium",
          "60",
          "Generator = biventricular: helix angle alpha on the LV "
          "endocardium (free wall and septal side), in the LV wall frame "
          "(normal out of the LV cavity).");
    angle("LV helix angle epicardium",
          "-60",
          "Helix angle alpha on the epicardium of the LV.");
    angle("LV sheet angle endocardium",
          "-20",
          "Sheet angle beta (rotation of the sheet about the fibre, from the "
          "wall normal) on the LV endocardium.");
    angle("LV sheet angle epicardium",
          "20",
          "Sheet angle beta on the epicardium of the LV.");
    angle("RV helix angle endocardium",
          "60",
          "Helix angle alpha on the RV endocardium (free wall and septal "
          "side), in the RV wall frame (normal out of the RV cavity; Doste "
          "et al. 2019: 90).");
    angle("RV helix angle epicardium",
          "-60",
          "Helix angle alpha on the epicardium of the RV (Doste et al. 2019: "
          "-25).");
    angle("RV sheet angle endocardium",
          "-20",
          "Sheet angle beta on the RV endocardium (Doste et al. 2019: 0).");
    angle("RV sheet angle epicardium",
          "20",
          "Sheet angle beta on the epicardium of the RV.");
    angle("Septum helix angle",
          "0",
          "Helix angle alpha in the middle of the septum (septal depth "
          "d = 1/2), in the LV wall frame; the septum turns from the LV "
          "endocardial angle through this one to the RV endocardial one.");
    angle("Septum sheet angle",
          "0",
          "Sheet angle beta in the middle of the septum.");
    prm.declare_entry("Element degree",
                      "2",
                      dealii::Patterns::Integer(1, 2),
                      "Degree of the Lagrange elements of the four Laplace "
                      "solves (phi_epi, phi_lv, phi_rv, psi). Units: -.");
    prm.leave_subsection();
    prm.leave_subsection();
  }

  Biventricular::Parameters
  Biventricular::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path   = {"Fibres", "Biventricular"};
    const double                   degree = M_PI / 180;
    const auto                     angle  = [&](const std::string &entry) {
      return prm.get_double(path, entry) * degree;
    };
    Parameters p;
    p.lv_alpha_endo = angle("LV helix angle endocardium");
    p.lv_alpha_epi  = angle("LV helix angle epicardium");
    p.lv_beta_endo  = angle("LV sheet angle endocardium");
    p.lv_beta_epi   = angle("LV sheet angle epicardium");
    p.rv_alpha_endo = angle("RV helix angle endocardium");
    p.rv_alpha_epi  = angle("RV helix angle epicardium");
    p.rv_beta_endo  = angle("RV sheet angle endocardium");
    p.rv_beta_epi   = angle("RV sheet angle epicardium");
    p.septum_alpha  = angle("Septum helix angle");
    p.septum_beta   = angle("Septum sheet angle");
    p.degree        = prm.get_integer(path, "Element degree");
    return p;
  }

  namespace
  {
    enum Field : unsigned int
    {
      epi = 0,
      lv  = 1,
      rv  = 2,
      psi = 3
    };

    using FieldValues = std::vector<std::vector<FieldValue>>;

    /// The coordinates at point @p i of the fields' values @p v.
    BiventricularCoordinates
    coordinates_at(const FieldValues &v, const unsigned int i)
    {
      BiventricularCoordinates c;
      c.phi_epi            = v[epi][i].value;
      c.phi_lv             = v[lv][i].value;
      c.phi_rv             = v[rv][i].value;
      c.psi                = v[psi][i].value;
      const double lv_part = std::max(0.0, c.phi_lv),
                   rv_part = std::max(0.0, c.phi_rv);
      if (lv_part + rv_part > 1e-8)
        c.depth = rv_part / (lv_part + rv_part);
      else
        {
          // On the epicardium both vanish: the limit of the ratio is that of
          // their normal derivatives.
          const double g_lv = v[lv][i].gradient.norm(),
                       g_rv = v[rv][i].gradient.norm();
          c.depth           = g_lv + g_rv > 0 ? g_rv / (g_lv + g_rv) : 0.5;
        }
      c.depth = std::clamp(c.depth, 0.0, 1.0);
      return c;
    }

    /// The wall frame (Biventricular::wall_frames()) at point @p i of the
    /// fields' values @p v.
    WallFrame
    wall_frame_at(const FieldValues &v, const unsigned int i)
    {
      WallFrame w;
      w.transmural = v[epi][i].value;
      w.apicobasal = v[psi][i].value;
      // wall_basis with alpha = beta = 0 is (e_c, e_t, e_t x ... ): f = e_c,
      // s = e_t.
      const dealii::Tensor<1, 3> &g = v[psi][i].gradient;
      const FibreBasis b = wall_basis(v[epi][i].gradient, g, 0.0, 0.0);
      w.e_c              = b.f;
      w.e_t              = b.s;
      w.e_l              = dealii::cross_product_3d(w.e_t, w.e_c);
      const dealii::Tensor<1, 3> tangent = g - (g * w.e_t) * w.e_t;
      w.degenerate                       = !(tangent.norm() > 1e-6 * g.norm());
      return w;
    }
  } // namespace

  Biventricular::Biventricular(const Parameters                  &params,
                               const dealii::Triangulation<3, 3> &tria,
                               const Geometry::BoundaryNames     &names,
                               Logger                            *logger)
    : params(params)
  {
    Geometry::require_boundaries(
      tria,
      names,
      {"lv_endocardium", "rv_endocardium", "epicardium", "base"},
      "Fibres / Generator = biventricular needs the boundary parts "
      "lv_endocardium, rv_endocardium, epicardium and base");
    const auto lv_endo    = names.id("lv_endocardium"),
               rv_endo    = names.id("rv_endocardium"),
               epicardium = names.id("epicardium"), base = names.id("base");

    const auto                  start = std::chrono::steady_clock::now();
    std::vector<LaplaceProblem> problems(4);
    problems[epi] = {"transmural",
                     {{lv_endo, 0.0}, {rv_endo, 0.0}, {epicardium, 1.0}},
                     0.0};
    problems[lv]  = {"LV",
                     {{lv_endo, 1.0}, {rv_endo, 0.0}, {epicardium, 0.0}},
                     0.0};
    problems[rv]  = {"RV",
                     {{lv_endo, 0.0}, {rv_endo, 1.0}, {epicardium, 0.0}},
                     0.0};
    problems[psi] = {"apicobasal", {{base, 0.0}}, 1.0};
    fields = std::make_unique<LaplaceFields>(tria, params.degree, problems);
    // psi = 1 - u / max u: 1 on the base, 0 where u peaks (the apex).
    const auto [u_max, apex] = fields->maximum(psi);
    AssertThrow(u_max > 0,
                dealii::ExcMessage("Biventricular fibres: the apicobasal "
                                   "solve gave no positive values."));
    fields->scale(psi, -1.0 / u_max, 1.0);
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
        .count();

    std::ostringstream o;
    const auto        &it = fields->iterations();
    o << std::fixed << std::setprecision(2)
      << "Biventricular fibres: " << fields->element_name() << ", "
      << fields->n_dofs()
      << " DOFs per solve; CG iterations (0: MUMPS) transmural " << it[epi]
      << ", LV " << it[lv] << ", RV " << it[rv] << ", apicobasal " << it[psi]
      << "; " << seconds << " s; apex at " << Geometry::format_point(apex)
      << " mm";
    if (fields->n_tangled_cells() > 0)
      o << ". WARNING: " << fields->n_tangled_cells()
        << " cell(s) of the mesh have a non-positive Jacobian at a quadrature "
           "point (tangled); the fibres near them are unreliable";
    report = o.str();
    if (logger != nullptr)
      logger->line(report);
  }

  Biventricular::~Biventricular() = default;

  const std::string &
  Biventricular::summary() const
  {
    return report;
  }

  void
  Biventricular::coordinates(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<BiventricularCoordinates>                   &result) const
  {
    fields->evaluate_each(cell, points, result, coordinates_at);
  }

  void
  Biventricular::wall_frames(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<WallFrame>                                  &frames) const
  {
    fields->evaluate_each(cell, points, frames, wall_frame_at);
  }

  void
  Biventricular::operator()(
    const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
    const std::vector<dealii::Point<3>>                     &points,
    std::vector<FibreBasis>                                 &bases) const
  {
    std::vector<std::vector<FieldValue>> v;
    fields->evaluate(cell, points, v);
    const Parameters &p = params;
    validated_bases(
      points,
      name,
      [&](const unsigned int i) {
        const BiventricularCoordinates c     = coordinates_at(v, i);
        const dealii::Tensor<1, 3>    &g_epi = v[epi][i].gradient,
                                   &g_psi    = v[psi][i].gradient;
        AssertThrow(g_epi.norm() > 0 && std::isfinite(g_epi.norm()),
                    dealii::ExcMessage(
                      "Biventricular fibres: the transmural gradient "
                      "vanishes at " +
                      Geometry::format_point(points[i]) +
                      " (is the wall connected?)."));
        // The septal frames, both oriented from the LV into the RV (Bayer):
        // out of the LV cavity and into the RV cavity. Where phi_lv (phi_rv)
        // is flat (the other ventricle's free wall, where its weight is 0),
        // the wall normal.
        const dealii::Tensor<1, 3> n_lv = direction(-v[lv][i].gradient, g_epi),
                                   n_rv = direction(v[rv][i].gradient, -g_epi);
        const double d                  = c.depth;
        // Angles through the septum in that orientation: the RV's own
        // (alpha, beta) are (-alpha, -beta) there.
        const auto septal =
          [d](const double lv_endo, const double mid, const double rv_endo) {
            return d <= 0.5 ? lv_endo + 2 * d * (mid - lv_endo)
                            : mid + (2 * d - 1) * (-rv_endo - mid);
          };
        const double alpha_s =
          septal(p.lv_alpha_endo, p.septum_alpha, p.rv_alpha_endo);
        const double beta_s =
          septal(p.lv_beta_endo, p.septum_beta, p.rv_beta_endo);
        const FibreBasis q_endo =
          bislerp(wall_basis(n_lv, g_psi, alpha_s, beta_s),
                  wall_basis(n_rv, g_psi, alpha_s, beta_s),
                  d);
        // Mid-wall and epicardial frames, LV and RV blended by d. Through
        // the wall in two halves: one bislerp over the whole turn would take
        // the short way for turns above 90 degrees (120 from +60 to -60).
        const auto wall = [&](const double lv_alpha,
                              const double lv_beta,
                              const double rv_alpha,
                              const double rv_beta) {
          return bislerp(wall_basis(g_epi, g_psi, lv_alpha, lv_beta),
                         wall_basis(g_epi, g_psi, rv_alpha, rv_beta),
                         d);
        };
        const FibreBasis q_mid = wall(0.5 * (p.lv_alpha_endo + p.lv_alpha_epi),
                                      0.5 * (p.lv_beta_endo + p.lv_beta_epi),
                                      0.5 * (p.rv_alpha_endo + p.rv_alpha_epi),
                                      0.5 * (p.rv_beta_endo + p.rv_beta_epi));
        const FibreBasis q_epi =
          wall(p.lv_alpha_epi, p.lv_beta_epi, p.rv_alpha_epi, p.rv_beta_epi);
        const double e = std::clamp(c.phi_epi, 0.0, 1.0);
        FibreBasis   b = e <= 0.5 ? bislerp(q_endo, q_mid, 2 * e)
                                  : bislerp(q_mid, q_epi, 2 * e - 1);
        // bislerp returns axes with arbitrary signs: take f with a positive
        // circumferential part and s out of the wall (in the frame of the
        // transmural field), flipping n along to keep n = f x s.
        const FibreBasis reference = wall_basis(g_epi, g_psi, 0.0, 0.0);
        if (b.f * reference.f < 0)
          {
            b.f = -b.f;
            b.n = -b.n;
          }
        if (b.s * reference.s < 0)
          {
            b.s = -b.s;
            b.n = -b.n;
          }
        return b;
      },
      bases);
  }
} // namespace systole::Fibres
