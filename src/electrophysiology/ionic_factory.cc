#include "electrophysiology/ionic_factory.h"

#include "electrophysiology/aliev_panfilov.h"
#include "electrophysiology/mitchell_schaeffer.h"
#include "electrophysiology/ten_tusscher_panfilov.h"

namespace systole::Electrophysiology
{
  namespace
  {
    /// The table line of a model: its name, a sentence, its parameters.
    template <class Model>
    IonicModelRegistry::Entry
    entry(const char *description)
    {
      return IonicModelRegistry::entry_of<Model>(Model::model_name,
                                                 description);
    }
  } // namespace


  IonicModelRegistry &
  ionic_models()
  {
    // Every ionic model, alphabetical by name.
    static IonicModelRegistry registry(
      "Electrophysiology / Ionic model",
      {
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
      });
    return registry;
  }


  void
  declare_ionic_model_parameters(dealii::ParameterHandler &prm)
  {
    ionic_models().declare_selection(
      prm,
      "Ionic model",
      AlievPanfilov::model_name,
      "Ionic model of the membrane; its parameters are in the subsection of "
      "the same name.");
    ionic_models().declare_parameters(prm, /*own_subsections=*/true);
  }


  std::unique_ptr<IonicModel>
  create_ionic_model(const dealii::ParameterHandler &prm)
  {
    return ionic_models().create(prm.get({"Electrophysiology"}, "Ionic model"),
                                 prm);
  }


  std::unique_ptr<IonicModel>
  create_ionic_model(const std::string &name)
  {
    // The defaults of a model: its parameters declared alone.
    const auto              &entry = ionic_models().find(name);
    dealii::ParameterHandler prm;
    prm.enter_subsection("Electrophysiology");
    prm.declare_entry("Ionic model", name);
    prm.enter_subsection(name);
    entry.declare(prm);
    prm.leave_subsection();
    prm.leave_subsection();
    return entry.create(prm);
  }
} // namespace systole::Electrophysiology
