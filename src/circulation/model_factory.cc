#include "circulation/model_factory.h"

#include <deal.II/base/parameter_handler.h>

#include "circulation/chamber_elastance.h"
#include "circulation/closed_loop.h"
#include "circulation/windkessel_model.h"

namespace systole::Circulation
{
  namespace
  {
    template <unsigned int n_elements>
    std::unique_ptr<Model>
    create_windkessel(const dealii::ParameterHandler &prm,
                      const ModelInputs              &in)
    {
      auto parameters                = WindkesselModel::Parameters::parse(prm,
                                                           n_elements,
                                                           in.period,
                                                           in.left_ventricle);
      parameters.left_ventricle_kind = in.left_kind;
      return std::make_unique<WindkesselModel>(parameters);
    }

    void
    declare_closed_loop(dealii::ParameterHandler &prm)
    {
      prm.enter_subsection("Closed loop");
      ClosedLoop::Parameters::declare(prm);
      prm.leave_subsection();
    }

  } // namespace


  ModelRegistry &
  models()
  {
    // Every model, in the order of the Selection (alphabetical).
    static ModelRegistry registry(
      "Circulation / Model",
      {
        {"2-element Windkessel",
         "the left ventricle between a constant atrial pressure and a "
         "compliance parallel to the peripheral resistance (Frank 1899), "
         "diode valves;",
         &WindkesselModel::Parameters::declare,
         &create_windkessel<2>},
        {"3-element Windkessel",
         "as the 2-element one with the characteristic impedance in series "
         "(Westerhof et al. 1971);",
         nullptr, // its entries are declared with the 2-element's
         &create_windkessel<3>},
        {"4-element Windkessel",
         "as the 3-element one with an inductance in series with the "
         "impedance, the law of reference/physiology.md (Stergiopulos et al. "
         "1999);",
         nullptr,
         &create_windkessel<4>},
        {ClosedLoop::model_name,
         "both ventricles, elastance atria, systemic and pulmonary arteries "
         "and veins (R, C, L) and four diode valves (Regazzoni et al. 2022, "
         "J. Comput. Phys. 457:111083); conserves the blood volume.",
         &declare_closed_loop,
         [](const dealii::ParameterHandler &prm,
            const ModelInputs              &in) -> std::unique_ptr<Model> {
           auto parameters                 = ClosedLoop::Parameters::parse(prm,
                                                           in.period,
                                                           in.left_ventricle,
                                                           in.right_ventricle);
           parameters.left_ventricle_kind  = in.left_kind;
           parameters.right_ventricle_kind = in.right_kind;
           return std::make_unique<ClosedLoop>(parameters);
         }},
      });
    return registry;
  }


  void
  declare_model_parameters(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Circulation");
    models().declare_selection(
      prm,
      "Model",
      ClosedLoop::model_name,
      "The 0D circulation model: of Problem = circulation alone (with "
      "elastance ventricles), and the one Problem = heartbeat couples its 3D "
      "left ventricle to (the model's lv; the other chambers stay 0D).");
    prm.enter_subsection("Left ventricle");
    ChamberElastance::Parameters::declare(prm,
                                          default_left_ventricle(),
                                          "left ventricle (0D elastance)");
    prm.leave_subsection();
    prm.enter_subsection("Right ventricle");
    ChamberElastance::Parameters::declare(prm,
                                          default_right_ventricle(),
                                          "right ventricle (0D elastance)");
    prm.leave_subsection();
    models().declare_parameters(prm, /*own_subsections=*/false);
    prm.leave_subsection();
  }


  std::unique_ptr<Model>
  create_model(const dealii::ParameterHandler &prm,
               const std::vector<std::string> &external)
  {
    ModelInputs in;
    for (const std::string &name : external)
      {
        AssertThrow(name == "lv" || name == "rv",
                    dealii::ExcMessage("A 3D ventricle must be 'lv' or 'rv', "
                                       "not '" +
                                       name + "'."));
        (name == "lv" ? in.left_kind : in.right_kind) = CavityKind::external;
      }
    in.period = prm.get_double({"Circulation"}, "Period");
    in.left_ventricle =
      ChamberElastance::Parameters::parse(prm,
                                          {"Circulation", "Left ventricle"});
    in.right_ventricle =
      ChamberElastance::Parameters::parse(prm,
                                          {"Circulation", "Right ventricle"});
    const std::string name  = prm.get({"Circulation"}, "Model");
    auto              model = models().create(name, prm, in);
    for (const std::string &cavity : external)
      {
        bool found = false;
        for (const auto &c : model->cavities())
          found = found || c.name == cavity;
        AssertThrow(found,
                    dealii::ExcMessage(
                      "Circulation / Model = " + name + " has no ventricle '" +
                      cavity +
                      "' for the 3D one: choose a model with both "
                      "ventricles (closed loop)."));
      }
    return model;
  }
} // namespace systole::Circulation
