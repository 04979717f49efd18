// The registry of every extension point: its errors and help, and for each
// extension point a toy entry added the way a table line adds one (name,
// sentence, parameters, builder), selected in a parameter file and built
// through the point's own factory function. Each toy is removed again, so the
// tests that walk the real tables (passive laws, postprocessors) see them
// unchanged.

#include <deal.II/base/parameter_handler.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include "base/registry.h"
#include "circulation/model_factory.h"
#include "circulation/parameters.h"
#include "electrophysiology/ionic_factory.h"
#include "fibres/fibre_field.h"
#include "materials/factory.h"
#include "materials/tension_factory.h"
#include "materials/volumetric_law.h"
#include "support/toy_tension.h"

#include "postprocess/factory.h"
#include "postprocess/fields.h"
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <sstream>

using namespace systole;

namespace
{
  /// Adds @p entry to @p registry for the lifetime of this object.
  template <class R>
  struct ToyEntry
  {
    ToyEntry(R &registry, typename R::Entry entry)
      : registry(registry)
      , name(entry.name)
    {
      registry.add(std::move(entry));
    }
    ~ToyEntry()
    {
      registry.remove(name);
    }
    R          &registry;
    std::string name;
  };

  /// Reads @p text into @p prm (declared by the caller).
  void
  parse(dealii::ParameterHandler &prm, const std::string &text)
  {
    std::istringstream in(text);
    prm.parse_input(in);
  }

  /// The message of the exception @p f throws ("" if none).
  template <class F>
  std::string
  message_of(const F &f)
  {
    try
      {
        f();
      }
    catch (const std::exception &e)
      {
        return e.what();
      }
    return "";
  }

  /// psi = c/2 (I1 - 3): S = c I, dS/dE = 0.
  class ToyLaw : public Materials::PassiveLaw
  {
  public:
    explicit ToyLaw(const double c)
      : c(c)
    {}
    void
    evaluate(const Materials::PassiveInput &in,
             Materials::PassiveOutput      &out) const override
    {
      out.psi   = 0.5 * c * (dealii::trace(transpose(in.F) * in.F) - 3.0);
      out.S     = c * dealii::unit_symmetric_tensor<3>();
      out.dS_dE = 0;
    }
    std::string
    name() const override
    {
      return "toy";
    }
    double c;
  };

  /// dv/dt = -v/tau, no states.
  class ToyCell : public Electrophysiology::IonicModel
  {
  public:
    explicit ToyCell(const double tau)
      : tau(tau)
    {}
    std::string
    name() const override
    {
      return "toy";
    }
    unsigned int
    n_states() const override
    {
      return 0;
    }
    double
    resting_potential() const override
    {
      return 0;
    }
    void
    resting_state(double *) const override
    {}
    double
    ionic_current(const double v, const double *) const override
    {
      return v / tau;
    }
    void
    state_rhs(const double, const double *, double *) const override
    {}
    double
    potential_scale_mV() const override
    {
      return 1;
    }
    double
    potential_offset_mV() const override
    {
      return 0;
    }
    double tau;
  };

  /// Declares entry "Toy value" (default @p value) in the current subsection.
  void
  declare_toy_value(dealii::ParameterHandler &prm, const double value)
  {
    prm.declare_entry("Toy value",
                      std::to_string(value),
                      dealii::Patterns::Double(),
                      "A toy. Units: -.");
  }
} // namespace


TEST_CASE("A registry finds its entries and names every valid one otherwise",
          "[base][registry]")
{
  using R = Registry<int(int)>;
  R r("Section / Choice",
      {{"b", "doubles;", nullptr, [](int x) { return 2 * x; }},
       {"a", "triples.", nullptr, [](int x) { return 3 * x; }}});
  CHECK(r.names() == std::vector<std::string>{"b", "a"});
  CHECK(r.joined_names("|") == "b|a");
  CHECK(r.create("a", 5) == 15);
  CHECK(r.contains("b"));
  CHECK_FALSE(r.contains("c"));
  const std::string msg = message_of([&] { r.find("c"); });
  CHECK(msg.find("Section / Choice = \"c\" is unknown; choose one of b, a.") !=
        std::string::npos);
  CHECK(r.help("Intro.", "Units: -.") ==
        "Intro. Choices: b: doubles; a: triples. Units: -.");
  r.add({"c", "quadruples.", nullptr, [](int x) { return 4 * x; }});
  CHECK(r.create("c", 1) == 4);
  r.remove("c");
  CHECK_FALSE(r.contains("c"));

  // The selection it declares accepts its names only.
  dealii::ParameterHandler prm;
  r.declare_selection(prm, "Choice", "a", "Intro.");
  CHECK_NOTHROW(parse(prm, "set Choice = b\n"));
  CHECK_THROWS(parse(prm, "set Choice = d\n"));
}


TEST_CASE("A toy passive law is one table line", "[base][registry]")
{
  ToyEntry                 toy(Materials::passive_laws(),
               {"toy",
                                "psi = c/2 (I1 - 3).",
                                [](dealii::ParameterHandler &prm) {
                  declare_toy_value(prm, 1.0);
                },
                                [](const dealii::ParameterHandler &prm)
                                  -> std::unique_ptr<Materials::PassiveLaw> {
                  return std::make_unique<ToyLaw>(
                    prm.get_double({"Material", "toy"}, "Toy value"));
                }});
  dealii::ParameterHandler prm;
  Materials::declare_parameters(prm);
  parse(prm,
        "subsection Material\n set Passive law = toy\n"
        " subsection toy\n  set Toy value = 3\n end\nend\n");
  const auto law = Materials::create_passive_law(prm);
  REQUIRE(law->name() == "toy");
  Materials::PassiveInput in;
  in.F = 2.0 * dealii::unit_symmetric_tensor<3>();
  Materials::PassiveOutput out;
  law->evaluate(in, out);
  CHECK(out.psi == Approx(0.5 * 3.0 * 9.0));
}


TEST_CASE("A toy volumetric form is one table line, and every form has "
          "U(1) = U'(1) = 0, U''(1) = 1 and consistent derivatives",
          "[base][registry]")
{
  ToyEntry                       toy(Materials::volumetric_forms(),
               {"toy", "(J-1)^2/2 + (J-1)^3.", nullptr, [] {
                  return Materials::VolumetricForm{
                    [](const double J) {
                      return 0.5 * (J - 1) * (J - 1) + std::pow(J - 1, 3);
                    },
                    [](const double J) {
                      return (J - 1) + 3 * (J - 1) * (J - 1);
                    },
                    [](const double J) { return 1 + 6 * (J - 1); }};
                }});
  const Materials::VolumetricLaw law({"toy", 50.0});
  CHECK(law.form_name() == "toy");
  CHECK(law.energy(1.1) == Approx(50.0 * (0.005 + 0.001)));
  for (const auto &e : Materials::volumetric_forms().all())
    {
      INFO(e.name);
      const auto form = e.create();
      CHECK(std::abs(form.energy(1.0)) < 1e-15);
      CHECK(std::abs(form.first_derivative(1.0)) < 1e-15);
      CHECK(form.second_derivative(1.0) == Approx(1.0));
      for (const double J : {0.8, 1.0, 1.3})
        {
          const double h = 1e-6;
          CHECK((form.energy(J + h) - form.energy(J - h)) / (2 * h) ==
                Approx(form.first_derivative(J)).margin(1e-8));
          CHECK((form.first_derivative(J + h) - form.first_derivative(J - h)) /
                  (2 * h) ==
                Approx(form.second_derivative(J)).margin(1e-8));
        }
    }
  CHECK(message_of([] {
          Materials::VolumetricLaw({"cubic", 1.0});
        }).find("Material / Volumetric / Form = \"cubic\" is unknown") !=
        std::string::npos);
}


TEST_CASE("A toy ionic model is one table line", "[base][registry]")
{
  ToyEntry                 toy(Electrophysiology::ionic_models(),
               {"toy",
                                "dv/dt = -v/tau.",
                                [](dealii::ParameterHandler &prm) {
                  declare_toy_value(prm, 1.0);
                },
                                [](const dealii::ParameterHandler &prm)
                                  -> std::unique_ptr<Electrophysiology::IonicModel> {
                  return std::make_unique<ToyCell>(
                    prm.get_double({"Electrophysiology", "toy"}, "Toy value"));
                }});
  dealii::ParameterHandler prm;
  prm.enter_subsection("Electrophysiology");
  Electrophysiology::declare_ionic_model_parameters(prm);
  prm.leave_subsection();
  parse(prm,
        "subsection Electrophysiology\n set Ionic model = toy\n"
        " subsection toy\n  set Toy value = 4\n end\nend\n");
  const auto model = Electrophysiology::create_ionic_model(prm);
  CHECK(model->name() == "toy");
  CHECK(model->ionic_current(2.0, nullptr) == Approx(0.5));
  CHECK(
    Electrophysiology::create_ionic_model("toy")->ionic_current(2.0, nullptr) ==
    Approx(2.0));
}


TEST_CASE("A toy tension model is one table line", "[base][registry]")
{
  ToyEntry toy(
    Materials::tension_models(),
    {"toy",
     "a constant tension;",
     [](dealii::ParameterHandler &prm) {
       prm.enter_subsection("Active tension");
       prm.enter_subsection("toy");
       declare_toy_value(prm, 1.0);
       prm.leave_subsection();
       prm.leave_subsection();
     },
     [](const dealii::ParameterHandler &prm,
        const double) -> std::unique_ptr<Materials::TensionModel> {
       const double T0 = prm.get_double({"Active tension", "toy"}, "Toy value");
       return std::make_unique<test_support::ToyTension>(
         "toy",
         [T0](const Materials::TensionInput &) { return T0; });
     }});
  dealii::ParameterHandler prm;
  Materials::declare_tension_parameters(prm);
  parse(prm,
        "subsection Active tension\n set Model = toy\n"
        " subsection toy\n  set Toy value = 7\n end\nend\n");
  const auto model = Materials::create_tension_model(prm, 800.0);
  CHECK(model->name() == "toy");
  CHECK(model->tension_of_state(nullptr, 1.1) == 7.0);
}


TEST_CASE("A toy circulation model is one table line", "[base][registry]")
{
  bool                     built = false;
  ToyEntry                 toy(Circulation::models(),
               {"toy",
                                "a 2-element Windkessel under another name.",
                                nullptr,
                                [&built](const dealii::ParameterHandler &prm,
                         const Circulation::ModelInputs &in) {
                  built = true;
                  return Circulation::models().create("2-element Windkessel",
                                                      prm,
                                                      in);
                }});
  dealii::ParameterHandler prm;
  Circulation::Parameters::declare(prm);
  Circulation::declare_model_parameters(prm);
  parse(prm, "subsection Circulation\n set Model = toy\nend\n");
  const auto model = Circulation::create_model(prm);
  CHECK(built);
  CHECK(model != nullptr);
}


TEST_CASE("A toy fibre generator is one table line", "[base][registry]")
{
  ToyEntry                 toy(Fibres::fibre_generators(),
               {"toy",
                                "f = e_y, s = e_z, n = e_x.",
                                nullptr,
                                [](const Fibres::Parameters &,
                   const Fibres::GeneratorInputs &) -> Fibres::FibreField {
                  return [](const auto &, const auto &points, auto &bases) {
                    Fibres::FibreBasis b;
                    b.f[1] = b.s[2] = b.n[0] = 1;
                    bases.assign(points.size(), b);
                  };
                }});
  dealii::ParameterHandler prm;
  Fibres::Parameters::declare(prm);
  parse(prm, "subsection Fibres\n set Generator = toy\nend\n");
  const auto               params = Fibres::Parameters::parse(prm);
  dealii::Triangulation<3> tria;
  dealii::GridGenerator::hyper_cube(tria);
  const Fibres::FibreField field =
    Fibres::create_fibre_field(params,
                               Geometry::LVShape(),
                               tria,
                               Geometry::BoundaryNames(),
                               nullptr);
  std::vector<Fibres::FibreBasis> bases;
  field(tria.begin_active(), {dealii::Point<3>(0.5, 0.5, 0.5)}, bases);
  REQUIRE(bases.size() == 1);
  CHECK(bases[0].f[1] == 1.0);
}


TEST_CASE("A toy postprocessor is one table line", "[base][registry]")
{
  ToyEntry toy(
    Postprocess::postprocessors(),
    {"toy", "field twice_J [-]", nullptr, [] {
       return std::unique_ptr<Postprocess::Postprocessor>(
         std::make_unique<Postprocess::Fields>(
           std::vector<std::pair<std::string, Postprocess::Fields::Getter>>{
             {"twice_J",
              [](const Postprocess::PointQuantities &q) { return 2 * q.J; }}},
           false));
     }});
  const auto p = Postprocess::create_postprocessor("toy");
  CHECK(p->field_names() == std::vector<std::string>{"twice_J"});
  CHECK(Postprocess::postprocessor_descriptions().find(
          "'toy': field twice_J [-].") != std::string::npos);
}
