#include "materials/factory.h"

#include "materials/fung_anisotropic.h"
#include "materials/fung_isotropic.h"
#include "materials/guccione.h"
#include "materials/holzapfel_ogden.h"
#include "materials/mooney_rivlin.h"
#include "materials/neo_hookean.h"
#include "materials/st_venant_kirchhoff.h"
#include "materials/veronda_westman.h"

namespace systole::Materials
{
  namespace
  {
    /// One passive law: how users call it, what it is, and how to declare
    /// its parameters and build it.
    struct Entry
    {
      const char *name;
      const char *description; // one sentence + reference, for the docs
      void (*declare)(dealii::ParameterHandler &);
      std::unique_ptr<PassiveLaw> (*create)(const dealii::ParameterHandler &);
    };

    template <class Law>
    Entry
    entry(const char *description)
    {
      return {
        Law::law_name,
        description,
        &Law::Parameters::declare,
        [](const dealii::ParameterHandler &prm) -> std::unique_ptr<PassiveLaw> {
          return std::make_unique<Law>(Law::Parameters::parse(prm));
        }};
    }

    /// Every passive law, alphabetical (case-insensitive) by name.
    const std::vector<Entry> &
    table()
    {
      static const std::vector<Entry> entries = {
        entry<FungAnisotropic>(
          "Transversely isotropic law: the Fung isotropic matrix plus the "
          "exponential fibre term of Holzapfel, Gasser and Ogden (2000, J. "
          "Elasticity 61:1), active in tension only."),
        entry<FungIsotropic>(
          "Isotropic isochoric exponential law in the first invariant (Fung "
          "1967, Am. J. Physiol. 213:1532; Demiray 1972, J. Biomech. 5:309)."),
        entry<Guccione>(
          "Transversely isotropic Fung-type exponential law in the "
          "Green-Lagrange strain of the fibre frame (Guccione et al. 1991, "
          "J. Biomech. Eng. 113:42)."),
        entry<HolzapfelOgden>(
          "Orthotropic invariant-based exponential law with tension-only "
          "fibre and sheet terms (Holzapfel and Ogden 2009, Phil. Trans. R. "
          "Soc. A 367:3445)."),
        entry<MooneyRivlin>(
          "Isotropic isochoric law in the first and second invariants "
          "(Mooney 1940, J. Appl. Phys. 11:582)."),
        entry<NeoHookean>(
          "Isotropic isochoric law linear in the first invariant (Treloar "
          "1943; Simo and Taylor 1991, CMAME 85:273)."),
        entry<StVenantKirchhoff>(
          "Isotropic compressible law quadratic in the Green-Lagrange strain, "
          "for verification (Holzapfel 2000, Nonlinear Solid Mechanics)."),
        entry<VerondaWestman>(
          "Isotropic isochoric exponential law in the first invariant with a "
          "linear second-invariant term (Veronda and Westman 1970, J. "
          "Biomech. 3:111)."),
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
  passive_law_names()
  {
    std::vector<std::string> names;
    for (const Entry &e : table())
      names.emplace_back(e.name);
    return names;
  }


  void
  declare_parameters(dealii::ParameterHandler &prm)
  {
    std::string help = "Passive (hyperelastic) law of the myocardium; its "
                       "parameters are in the subsection of the same name. "
                       "Units: none. Choices:";
    for (const Entry &e : table())
      help += std::string(" ") + e.name + ": " + e.description;

    prm.enter_subsection("Material");
    {
      prm.declare_entry("Passive law",
                        Guccione::law_name,
                        dealii::Patterns::Selection(joined_names("|")),
                        help);
      for (const Entry &e : table())
        {
          prm.enter_subsection(e.name);
          e.declare(prm);
          prm.leave_subsection();
        }
      prm.enter_subsection("Volumetric");
      VolumetricLaw::Parameters::declare(prm);
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }


  std::unique_ptr<PassiveLaw>
  create_passive_law(const dealii::ParameterHandler &prm)
  {
    const std::string name = prm.get({"Material"}, "Passive law");
    for (const Entry &e : table())
      if (name == e.name)
        return e.create(prm);
    AssertThrow(false,
                dealii::ExcMessage("Material / Passive law = \"" + name +
                                   "\" is unknown; choose one of " +
                                   joined_names(", ") + "."));
    return nullptr;
  }


  VolumetricLaw
  create_volumetric_law(const dealii::ParameterHandler &prm)
  {
    return VolumetricLaw(VolumetricLaw::Parameters::parse(prm));
  }
} // namespace systole::Materials
