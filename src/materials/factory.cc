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
    /// The table line of a law: its name, a sentence, its parameters.
    template <class Law>
    PassiveLawRegistry::Entry
    entry(const char *description)
    {
      return PassiveLawRegistry::entry_of<Law>(Law::law_name, description);
    }
  } // namespace


  PassiveLawRegistry &
  passive_laws()
  {
    // Every passive law, alphabetical (case-insensitive) by name.
    static PassiveLawRegistry registry(
      "Material / Passive law",
      {
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
      });
    return registry;
  }


  void
  declare_parameters(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    {
      passive_laws().declare_selection(
        prm,
        "Passive law",
        Guccione::law_name,
        "Passive (hyperelastic) law of the myocardium; its parameters are in "
        "the subsection of the same name.");
      passive_laws().declare_parameters(prm, /*own_subsections=*/true);
      prm.enter_subsection("Volumetric");
      VolumetricLaw::Parameters::declare(prm);
      prm.leave_subsection();
    }
    prm.leave_subsection();
  }


  std::unique_ptr<PassiveLaw>
  create_passive_law(const dealii::ParameterHandler &prm)
  {
    return passive_laws().create(prm.get({"Material"}, "Passive law"), prm);
  }


  VolumetricLaw
  create_volumetric_law(const dealii::ParameterHandler &prm)
  {
    return VolumetricLaw(VolumetricLaw::Parameters::parse(prm));
  }
} // namespace systole::Materials
