#include "electrophysiology/ionic_factory.h"

#include "electrophysiology/aliev_panfilov.h"
#include "electrophysiology/mitchell_schaeffer.h"
#include "electrophysiology/ten_tusscher_panfilov.h"

namespace systole::Electrophysiology
{
  namespace
  {
    /// One ionic model: its name, what it is, how to declare its parameters
    /// and how to build it (from a parameter file or with its defaults).
    struct Entry
    {
      const char *name;
      const char *description; // one sentence + reference, for the docs
      void (*declare)(dealii::ParameterHandler &);
      std::unique_ptr<IonicModel> (*create)(const dealii::ParameterHandler &);
      std::unique_ptr<IonicModel> (*create_default)();
    };

    template <class Model>
    Entry
    entry(const char *description)
    {
      return {
        Model::model_name,
        description,
        &Model::Parameters::declare,
        [](const dealii::ParameterHandler &prm) -> std::unique_ptr<IonicModel> {
          return std::make_unique<Model>(Model::Parameters::parse(prm));
        },
        []() -> std::unique_ptr<IonicModel> {
          return std::make_unique<Model>(typename Model::Parameters());
        }};
    }

    /// Every ionic model, alphabetical by name.
    const std::vector<Entry> &
    table()
    {
      static const std::vector<Entry> entries = {
        entry<AlievPanfilov>(
          "Two-variable phenomenological model, dimensionless potential "
          "u = (V + 80 mV)/100 mV and time unit 12.9 ms (Aliev and Panfilov "
          "1996, Chaos Solitons Fractals 7:293)."),
        entry<MitchellSchaeffer>(
          "Two-current phenomenological model with one gate, normalised "
          "potential in [0, 1] (Mitchell and Schaeffer 2003, Bull. Math. "
          "Biol. 65:767)."),
        entry<TenTusscherPanfilov>(
          "Human ventricular myocyte with 18 states (12 gates, advanced by "
          "Rush-Larsen, and the calcium, sodium and potassium dynamics), "
          "potential in mV, endocardial, mid-myocardial or epicardial "
          "(Cell type); the cell of the Niederer et al. 2011 benchmark "
          "(ten Tusscher and Panfilov 2006, Am. J. Physiol. Heart Circ. "
          "Physiol. 291:H1088)."),
      };
      return entries;
    }

    std::string
    joined_names(const char *separator)
    {
      std::string result;
      for (const Entry &e : table())
        result += (result.empty() ? "" : separator) + std::string(e.name);
      return result;
    }
  } // namespace


  std::vector<std::string>
  ionic_model_names()
  {
    std::vector<std::string> names;
    for (const Entry &e : table())
      names.emplace_back(e.name);
    return names;
  }


  void
  declare_ionic_model_parameters(dealii::ParameterHandler &prm)
  {
    std::string help = "Ionic model of the membrane; its parameters are in "
                       "the subsection of the same name. Units: none. "
                       "Choices:";
    for (const Entry &e : table())
      help += std::string(" ") + e.name + ": " + e.description;
    prm.declare_entry("Ionic model",
                      AlievPanfilov::model_name,
                      dealii::Patterns::Selection(joined_names("|")),
                      help);
    for (const Entry &e : table())
      {
        prm.enter_subsection(e.name);
        e.declare(prm);
        prm.leave_subsection();
      }
  }


  std::unique_ptr<IonicModel>
  create_ionic_model(const dealii::ParameterHandler &prm)
  {
    const std::string name = prm.get({"Electrophysiology"}, "Ionic model");
    for (const Entry &e : table())
      if (name == e.name)
        return e.create(prm);
    AssertThrow(false,
                dealii::ExcMessage("Electrophysiology / Ionic model = \"" +
                                   name + "\" is unknown; choose one of " +
                                   joined_names(", ") + "."));
    return nullptr;
  }


  std::unique_ptr<IonicModel>
  create_ionic_model(const std::string &name)
  {
    for (const Entry &e : table())
      if (name == e.name)
        return e.create_default();
    AssertThrow(false,
                dealii::ExcMessage("Unknown ionic model \"" + name +
                                   "\"; choose one of " + joined_names(", ") +
                                   "."));
    return nullptr;
  }
} // namespace systole::Electrophysiology
