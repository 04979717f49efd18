#include "materials/tension_factory.h"

#include <deal.II/base/parameter_handler.h>

#include "materials/bestel_tension.h"
#include "materials/land.h"


namespace systole::Materials
{
  TensionModelRegistry &
  tension_models()
  {
    static TensionModelRegistry registry(
      "Active tension / Model",
      {{BestelTension::model_name,
        "the prescribed Bestel curve (Bestel, Clement and Sorine 2001) "
        "started at each point's activation time (Activation map); no "
        "length or velocity dependence;",
        &Bestel::Parameters::declare,
        [](const dealii::ParameterHandler &prm,
           const double period) -> std::unique_ptr<TensionModel> {
          return std::make_unique<BestelTension>(Bestel::Parameters::parse(prm),
                                                 period);
        }},
       TensionModelRegistry::entry_of<Land>(
         Land::model_name,
         "the calcium-driven human cross-bridge model of Land et al. 2017 "
         "(J. Mol. Cell. Cardiol. 106:68) with length and velocity "
         "dependence (subsection Land), driven by a cell model's calcium "
         "(Problem = cell, or Problem = heartbeat with an ionic model with "
         "calcium: ten Tusscher-Panfilov; the heartbeat then always runs "
         "the electrophysiology and couples the tension two-way with the "
         "fibre stretch and its rate);")});
    return registry;
  }

  void
  declare_tension_parameters(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Active tension");
    tension_models().declare_selection(prm,
                                       "Model",
                                       BestelTension::model_name,
                                       "The active-tension model.",
                                       "Units: -.");
    prm.leave_subsection();
    tension_models().declare_parameters(prm, /*own_subsections=*/false);
  }

  std::string
  tension_model_name(const dealii::ParameterHandler &prm)
  {
    return prm.get({"Active tension"}, "Model");
  }

  std::unique_ptr<TensionModel>
  create_tension_model(const dealii::ParameterHandler &prm, const double period)
  {
    return tension_models().create(tension_model_name(prm), prm, period);
  }
} // namespace systole::Materials
