#include "materials/tension_factory.h"

#include <deal.II/base/parameter_handler.h>

#include "materials/bestel_tension.h"
#include "materials/land.h"

#include <functional>

namespace systole::Materials
{
  namespace
  {
    /// One tension model: its name, a sentence with its reference, and how
    /// to declare its parameters and build it.
    struct Entry
    {
      const char *name;
      const char *description;
      void (*declare)(dealii::ParameterHandler &);
      std::function<std::unique_ptr<
        TensionModel>(const dealii::ParameterHandler &, const double)>
        create;
    };

    const std::vector<Entry> &
    table()
    {
      static const std::vector<Entry> entries = {
        {BestelTension::model_name,
         "the prescribed Bestel curve (Bestel, Clement and Sorine 2001) "
         "started at each point's activation time (Activation map); no "
         "length or velocity dependence",
         &Bestel::Parameters::declare,
         [](const dealii::ParameterHandler &prm, const double period) {
           return std::make_unique<BestelTension>(Bestel::Parameters::parse(
                                                    prm),
                                                  period);
         }},
        {Land::model_name,
         "the calcium-driven human cross-bridge model of Land et al. 2017 "
         "(J. Mol. Cell. Cardiol. 106:68) with length and velocity "
         "dependence (subsection Land), driven by a cell model's calcium "
         "(Problem = cell, or Problem = heartbeat with an ionic model with "
         "calcium: ten Tusscher-Panfilov; the heartbeat then always runs "
         "the electrophysiology and couples the tension two-way with the "
         "fibre stretch and its rate)",
         &Land::Parameters::declare,
         [](const dealii::ParameterHandler &prm, const double) {
           return std::make_unique<Land>(Land::Parameters::parse(prm));
         }}};
      return entries;
    }
  } // namespace

  void
  declare_tension_parameters(dealii::ParameterHandler &prm)
  {
    std::string names, help = "The active-tension model: ";
    for (const Entry &e : table())
      {
        names += (names.empty() ? "" : "|") + std::string(e.name);
        help += std::string(e.name) + ": " + e.description + "; ";
      }
    help += "Units: -.";
    prm.enter_subsection("Active tension");
    prm.declare_entry("Model",
                      BestelTension::model_name,
                      dealii::Patterns::Selection(names),
                      help);
    prm.leave_subsection();
    for (const Entry &e : table())
      e.declare(prm);
  }

  std::string
  tension_model_name(const dealii::ParameterHandler &prm)
  {
    return prm.get({"Active tension"}, "Model");
  }

  std::unique_ptr<TensionModel>
  create_tension_model(const dealii::ParameterHandler &prm, const double period)
  {
    const std::string name = tension_model_name(prm);
    for (const Entry &e : table())
      if (name == e.name)
        return e.create(prm, period);
    AssertThrow(false,
                dealii::ExcMessage("Active tension / Model: unknown model '" +
                                   name + "'."));
    return nullptr;
  }

  std::vector<std::string>
  tension_model_names()
  {
    std::vector<std::string> names;
    for (const Entry &e : table())
      names.push_back(e.name);
    return names;
  }
} // namespace systole::Materials
