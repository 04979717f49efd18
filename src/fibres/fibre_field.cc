#include "fibres/fibre_field.h"

#include <deal.II/base/parameter_handler.h>

#include "base/logger.h"
#include "fibres/arostica.h"
#include "fibres/rule_based.h"
#include "geometry/mesh_file.h"

#include <cmath>
#include <memory>

namespace systole::Fibres
{
  AnalyticHelix::AnalyticHelix(const Geometry::LVShape &shape,
                               const double             alpha_endo,
                               const double             alpha_epi,
                               const double             beta)
    : shape(shape)
    , manifold(shape)
    , alpha_endo(alpha_endo)
    , alpha_epi(alpha_epi)
    , beta(beta)
  {}

  void
  AnalyticHelix::local_frame(const dealii::Point<3> &point,
                             dealii::Tensor<1, 3>   &e_u,
                             dealii::Tensor<1, 3>   &e_v,
                             double                 &t) const
  {
    // In the generator's frame (long axis z), turned back at the end.
    const dealii::Point<3> X = shape.to_generator_frame(point);
    t                        = manifold.transmural_coordinate(point);
    const double rs = shape.short_radius(t), rl = shape.long_radius(t);
    // The axis has no circumferential direction: step off it a little.
    double       x = X[0], y = X[1];
    const double rho_min = 1e-8 * rs;
    if (std::hypot(x, y) < rho_min)
      x = rho_min;
    // ... and off the apex of the spheroid (|sin u| >= 1e-6), where the
    // frame is the limit along the meridian v.
    const double sin_u_max = -1e-6;
    const double sin_u =
      std::min(sin_u_max,
               -std::sqrt(std::max(0.0, 1.0 - std::pow(X[2] / rl, 2))));
    const double cos_u = std::copysign(std::sqrt(1.0 - sin_u * sin_u), X[2]);
    const double v     = std::atan2(-y, -x); // sin u < 0
    e_u                = dealii::Tensor<1, 3>(
      {rs * cos_u * std::cos(v), rs * cos_u * std::sin(v), -rl * sin_u});
    e_v = dealii::Tensor<1, 3>(
      {-rs * sin_u * std::sin(v), rs * sin_u * std::cos(v), 0.0});
    e_u = shape.from_generator_frame(e_u / e_u.norm());
    e_v = shape.from_generator_frame(e_v / e_v.norm());
  }

  FibreBasis
  AnalyticHelix::operator()(const dealii::Point<3> &X) const
  {
    dealii::Tensor<1, 3> e_u, e_v;
    double               t;
    local_frame(X, e_u, e_v, t);
    const double alpha = alpha_endo + (alpha_epi - alpha_endo) * t;

    FibreBasis b;
    b.f = std::sin(alpha) * e_u + std::cos(alpha) * e_v;
    // Outward wall normal (e_u x e_v points into the cavity), then the sheet
    // rotated by beta about f.
    const dealii::Tensor<1, 3> normal = dealii::cross_product_3d(e_v, e_u);
    const dealii::Tensor<1, 3> side   = dealii::cross_product_3d(b.f, normal);
    b.s = std::cos(beta) * normal + std::sin(beta) * side;
    b.n = dealii::cross_product_3d(b.f, b.s);
    return b;
  }

  void
  Parameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Fibres");
    fibre_generators().declare_selection(prm,
                                         "Generator",
                                         "cartesian",
                                         "The fibre field.",
                                         "Units: -.");
    prm.declare_entry("Helix angle endocardium",
                      "60",
                      Double(-90, 90),
                      "Helix angle alpha at the endocardium (analytic and "
                      "rule-based generators; Land problem 3: 90). Units: "
                      "degrees.");
    prm.declare_entry("Helix angle epicardium",
                      "-60",
                      Double(-90, 90),
                      "Helix angle alpha at the epicardium (Land problem 3: "
                      "-90). Units: degrees.");
    prm.declare_entry("Sheet angle",
                      "0",
                      Double(-90, 90),
                      "Rotation beta of the sheet direction about the fibre, "
                      "from the wall normal. Units: degrees.");
    prm.enter_subsection("Rule-based");
    prm.declare_entry(
      "Element degree",
      "2",
      Integer(1, 2),
      "Degree of the Lagrange elements of the rule-based generator's two "
      "solves (transmural and apex-to-base coordinates). Q1 gradients turn "
      "the frame by several degrees on meshes of 10^4 DOFs; Q2 by less "
      "than one degree (tests/unit/fibres/rule_based_test.cc). "
      "Units: -.");
    prm.declare_entry(
      "Apicobasal field",
      "poisson",
      Selection("laplace|poisson"),
      "The apex-to-base coordinate psi whose gradient, projected onto the "
      "wall, is the longitudinal direction. laplace: Bayer et al. 2012, "
      "Laplace psi = 1 on the base and 0 at the apex vertex (the epicardial "
      "vertex farthest from the base plane); the point condition is "
      "singular, and epicardial frames within 20 to 40 degrees of the apex "
      "are unreliable (tens of degrees off). poisson: -Laplace u = 1, u = 0 on "
      "the base, psi = 1 - u / max u; smooth everywhere, psi = 0 where u "
      "peaks (the apex). Units: -.");
    prm.leave_subsection();
    // (Fibres / VTU, where parse() reads it; it was declared at the top
    // level, which only a Debug build's ParameterHandler::get noticed.)
    prm.enter_subsection("VTU");
    prm.declare_entry(
      "File",
      "",
      Anything(),
      "The .vtu file with the fibre vectors: the mesh file itself "
      "(Geometry / Gmsh / Mesh file), or one with the same volume cells in "
      "the same order (its cell i gives the coarse cell i of the mesh; "
      "refined cells take their coarse cell's frame). A relative path is "
      "relative to the folder of this parameter file. Units: -.");
    prm.declare_entry(
      "Fibre array",
      "fibres",
      Anything(),
      "Name of its 3-component cell array (or point array, reduced to the "
      "dominant direction of each cell's vertices) of fibre directions f; "
      "normalized. Units: -.");
    prm.declare_entry(
      "Sheet array",
      "",
      Anything(),
      "Name of its array of sheet directions s (made orthogonal to f); "
      "empty: s is the unit vector orthogonal to f in the plane of f and "
      "the coordinate axis least aligned with it, so laws that use s "
      "(Holzapfel-Ogden's sheet terms) need this array. Units: -.");
    prm.leave_subsection();
    prm.leave_subsection();
    fibre_generators().declare_parameters(prm, /*own_subsections=*/false);
  }

  Parameters
  Parameters::parse(const dealii::ParameterHandler &prm,
                    const std::string              &base_directory)
  {
    Parameters                     p;
    const std::vector<std::string> path = {"Fibres"};
    p.generator                         = prm.get(path, "Generator");
    p.alpha_endo = prm.get_double(path, "Helix angle endocardium");
    p.alpha_epi  = prm.get_double(path, "Helix angle epicardium");
    p.beta       = prm.get_double(path, "Sheet angle");
    const std::vector<std::string> rule = {"Fibres", "Rule-based"};
    p.rule_based.degree     = prm.get_integer(rule, "Element degree");
    p.rule_based.apicobasal = prm.get(rule, "Apicobasal field") == "laplace"
                                ? ApicobasalField::laplace
                                : ApicobasalField::poisson;
    p.biventricular         = Biventricular::Parameters::parse(prm);
    p.dti                   = DTIParameters::parse(prm, base_directory);
    const std::vector<std::string> vtu = {"Fibres", "VTU"};
    p.vtu_file =
      Geometry::file_in_directory(prm.get(vtu, "File"), base_directory);
    p.vtu_fibre_array = prm.get(vtu, "Fibre array");
    p.vtu_sheet_array = prm.get(vtu, "Sheet array");
    AssertThrow(p.generator != "vtu" || !p.vtu_file.empty(),
                dealii::ExcMessage(
                  "Fibres / Generator = vtu needs Fibres / VTU / File (the "
                  ".vtu mesh file whose cell or point array holds the "
                  "fibre directions)."));
    return p;
  }

  namespace
  {
    /// The frames of Generator = vtu: per coarse cell, f from the file's
    /// fibre array, s from its sheet array (or the axis least aligned with f)
    /// made orthogonal to f, n = f x s.
    FibreField
    vtu_fibre_field(const Parameters                  &params,
                    const dealii::Triangulation<3, 3> &tria)
    {
      std::vector<dealii::Tensor<1, 3>> f =
        Geometry::read_vtu_cell_vectors(params.vtu_file,
                                        params.vtu_fibre_array);
      std::vector<dealii::Tensor<1, 3>> s;
      if (!params.vtu_sheet_array.empty())
        s = Geometry::read_vtu_cell_vectors(params.vtu_file,
                                            params.vtu_sheet_array);
      AssertThrow(f.size() == tria.n_global_coarse_cells(),
                  dealii::ExcMessage(
                    "Fibres / VTU / File '" + params.vtu_file + "' has " +
                    std::to_string(f.size()) + " volume cells, the mesh " +
                    std::to_string(tria.n_global_coarse_cells()) +
                    " coarse cells: give the mesh file itself (or one with "
                    "its cells in the same order)."));
      auto frames = std::make_shared<std::vector<FibreBasis>>(f.size());
      for (std::size_t c = 0; c < f.size(); ++c)
        {
          FibreBasis &b = (*frames)[c];
          b.f           = f[c];
          dealii::Tensor<1, 3> t;
          if (!s.empty())
            t = s[c] - (s[c] * b.f) * b.f;
          else
            {
              unsigned int k = 0;
              for (unsigned int d = 1; d < 3; ++d)
                if (std::abs(b.f[d]) < std::abs(b.f[k]))
                  k = d;
              t[k] = 1.0;
              t -= b.f[k] * b.f;
            }
          AssertThrow(t.norm() > 1e-8,
                      dealii::ExcMessage(
                        "Fibres / VTU / Sheet array '" +
                        params.vtu_sheet_array + "': the sheet of cell " +
                        std::to_string(c) +
                        " is parallel to its fibre; give a sheet direction "
                        "across the fibre."));
          b.s = t / t.norm();
          b.n = dealii::cross_product_3d(b.f, b.s);
          validate(b, "cell " + std::to_string(c) + " (vtu generator)");
        }
      return [frames](const auto &cell, const auto &points, auto &bases) {
        bases.assign(points.size(), (*frames)[cell->id().get_coarse_cell_id()]);
      };
    }
  } // namespace

  namespace
  {
    constexpr double degree = M_PI / 180.0;

    /// A generator's own object, applied cell by cell.
    template <class Rule>
    FibreField
    cellwise(const std::shared_ptr<const Rule> &rule)
    {
      return [rule](const auto &cell, const auto &points, auto &bases) {
        (*rule)(cell, points, bases);
      };
    }

    /// A rule of the point alone, every frame validated.
    FibreField
    pointwise(const std::function<FibreBasis(const dealii::Point<3> &)> &rule,
              const std::string                                         &name)
    {
      return [rule, name](const auto &, const auto &points, auto &bases) {
        validated_bases(
          points,
          name,
          [&](const unsigned int i) { return rule(points[i]); },
          bases);
      };
    }

    FibreField
    rule_based(const Parameters &params, const GeneratorInputs &in)
    {
      RuleBased::Parameters p;
      p.alpha_endo  = params.alpha_endo * degree;
      p.alpha_epi   = params.alpha_epi * degree;
      p.beta        = params.beta * degree;
      p.coordinates = params.rule_based;
      return cellwise(
        std::make_shared<const RuleBased>(p, in.tria, in.names, in.logger));
    }

    FibreField
    arostica(const Parameters &params, const GeneratorInputs &in)
    {
      Arostica::Parameters p;
      p.alpha_endo = params.alpha_endo * degree;
      p.alpha_epi  = params.alpha_epi * degree;
      p.degree     = params.rule_based.degree;
      return cellwise(std::make_shared<const Arostica>(p,
                                                       in.shape,
                                                       in.tria,
                                                       in.names,
                                                       in.logger));
    }

    FibreField
    dti(const Parameters &params, const GeneratorInputs &in)
    {
      Logger *logger = in.logger;
      return create_dti_fibre_field(params.dti,
                                    in.tria,
                                    [logger](const std::string &line) {
                                      if (logger != nullptr)
                                        logger->line(line);
                                    });
    }
  } // namespace

  FibreGeneratorRegistry &
  fibre_generators()
  {
    // Every generator, alphabetical.
    static FibreGeneratorRegistry registry(
      "Fibres / Generator",
      {{"analytic",
        "the helix rule of Land et al. 2015 problem 3 on the generated "
        "ellipsoid, helix angle linear through the wall;",
        nullptr,
        [](const Parameters &p, const GeneratorInputs &in) {
          return pointwise(AnalyticHelix(in.shape,
                                         p.alpha_endo * degree,
                                         p.alpha_epi * degree,
                                         p.beta * degree),
                           "analytic");
        }},
       {Arostica::name,
        "the rule of the Arostica et al. 2025 benchmark on a generated "
        "ventricle (Geometry / Type = arostica or ellipsoid): the transmural "
        "coordinate from a Laplace solve (0 endocardium, 1 epicardium, no "
        "flux on the base; Rule-based / Element degree), the radii and the "
        "helix angle linear in it, f = sin(alpha) e_mu + cos(alpha) e_theta, "
        "the sheet s = f x (e_mu x e_theta) in the wall (the Sheet angle does "
        "not apply);",
        nullptr,
        &arostica},
       {Biventricular::name,
        "Bayer et al. 2012 for two ventricles on a mesh with boundary parts "
        "lv_endocardium, rv_endocardium, epicardium and base (subsection "
        "Biventricular; the three angles above do not apply);",
        &Biventricular::Parameters::declare,
        [](const Parameters &p, const GeneratorInputs &in) {
          return cellwise(std::make_shared<const Biventricular>(p.biventricular,
                                                                in.tria,
                                                                in.names,
                                                                in.logger));
        }},
       {"cartesian",
        "f = e_x, s = e_y, n = e_z everywhere (Land problem 1, isotropic "
        "laws);",
        nullptr,
        [](const Parameters &, const GeneratorInputs &) {
          return pointwise(
            [](const dealii::Point<3> &) { return FibreBasis::cartesian(); },
            "cartesian");
        }},
       {"dti",
        "principal eigenvectors of a diffusion-tensor image (subsection "
        "DTI);",
        &DTIParameters::declare,
        &dti},
       {RuleBased::name,
        "the Laplace-Dirichlet rule of Bayer et al. 2012 on any LV mesh with "
        "boundary parts endocardium, epicardium and base (helix angle linear "
        "in the transmural Laplace coordinate, same conventions as "
        "analytic);",
        nullptr,
        &rule_based},
       {"vtu",
        "one frame per cell of the mesh from the vectors of a .vtu file with "
        "the mesh's cells (subsection VTU).",
        nullptr,
        [](const Parameters &p, const GeneratorInputs &in) {
          return vtu_fibre_field(p, in.tria);
        }}});
    return registry;
  }

  FibreField
  create_fibre_field(const Parameters                  &params,
                     const Geometry::LVShape           &shape,
                     const dealii::Triangulation<3, 3> &tria,
                     const Geometry::BoundaryNames     &names,
                     Logger                            *logger)
  {
    return fibre_generators().create(
      params.generator,
      params,
      GeneratorInputs{shape, tria, names, logger});
  }
} // namespace systole::Fibres
