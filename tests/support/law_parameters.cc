#include "support/law_parameters.h"

#include "materials/factory.h"
#include "materials/fung_anisotropic.h"
#include "materials/fung_isotropic.h"
#include "materials/guccione.h"
#include "materials/holzapfel_ogden.h"
#include "materials/mooney_rivlin.h"
#include "materials/neo_hookean.h"
#include "materials/st_venant_kirchhoff.h"
#include "materials/veronda_westman.h"

#include <map>
#include <stdexcept>

namespace test_support
{
  namespace
  {
    using systole::Fibres::FibreBasis;
    namespace Materials = systole::Materials;

    /// A case of @p Law with @p parameters; @p variant (if any) is appended
    /// to the law's name in parentheses.
    template <class Law>
    LawCase
    law_case(const typename Law::Parameters &parameters,
             const bool                      default_parameters,
             const std::string              &variant  = "",
             std::vector<TensionSwitch>      switches = {})
    {
      return {std::string(Law::law_name) +
                (variant.empty() ? "" : " (" + variant + ")"),
              std::make_shared<Law>(parameters),
              default_parameters,
              std::move(switches)};
    }

    /// The default parameters of @p Law.
    template <class Law>
    LawCase
    defaults(const std::string &variant = "")
    {
      return law_case<Law>(typename Law::Parameters(), true, variant);
    }

    /// The fibre and sheet switches of a Holzapfel-Ogden parameter set. The
    /// logistic switch changes over |I4 - 1| ~ 1/k: the tests treat it as a
    /// blend of that width (small FD steps, states clear of it, FD inside).
    std::vector<TensionSwitch>
    switches_of(const Materials::HolzapfelOgden::Parameters &p)
    {
      const double width =
        p.switch_form == Materials::HolzapfelOgden::Parameters::Switch::logistic
          ? 1.0 / p.switch_sharpness
          : p.switch_width;
      std::vector<TensionSwitch> result;
      if (p.a_f > 0.0)
        result.push_back({&FibreBasis::f, width});
      if (p.a_s > 0.0)
        result.push_back({&FibreBasis::s, width});
      return result;
    }

    /// The parameter sets of every law, keyed by its factory name. A new
    /// law of the factory table needs an entry here (at least its
    /// defaults), or passive_law_cases() throws.
    const std::map<std::string, std::vector<LawCase>> &
    table()
    {
      using namespace Materials;
      static const std::map<std::string, std::vector<LawCase>> cases = [] {
        const HolzapfelOgden::Parameters ho;
        const HolzapfelOgden::Parameters ho_ti =
          transversely_isotropic_holzapfel_ogden();
        HolzapfelOgden::Parameters ho_logistic = arostica_holzapfel_ogden();
        ho_logistic.switch_sharpness           = 10.0;
        const FungAnisotropic::Parameters           fung;
        std::map<std::string, std::vector<LawCase>> t;
        t[FungAnisotropic::law_name] = {
          law_case<FungAnisotropic>(fung,
                                    true,
                                    "",
                                    {{&FibreBasis::f, fung.switch_width}})};
        t[FungIsotropic::law_name]  = {defaults<FungIsotropic>()};
        t[Guccione::law_name]       = {defaults<Guccione>()};
        t[HolzapfelOgden::law_name] = {
          law_case<HolzapfelOgden>(ho, true, "orthotropic", switches_of(ho)),
          law_case<HolzapfelOgden>(ho_ti,
                                   false,
                                   "transversely isotropic",
                                   switches_of(ho_ti)),
          // The logistic switch, gentler than the benchmark's k = 100 so
          // that the generic FD steps (up to 1e-2) stay asymptotic; it is
          // smooth everywhere (no interval to avoid). k = 100 across I4 = 1:
          // passive_laws_test.cc, with small steps.
          law_case<HolzapfelOgden>(ho_logistic, false, "logistic switch")};
        t[MooneyRivlin::law_name]      = {defaults<MooneyRivlin>()};
        t[NeoHookean::law_name]        = {defaults<NeoHookean>()};
        t[StVenantKirchhoff::law_name] = {defaults<StVenantKirchhoff>()};
        t[VerondaWestman::law_name]    = {defaults<VerondaWestman>()};
        return t;
      }();
      return cases;
    }
  } // namespace


  std::vector<LawCase>
  passive_law_cases()
  {
    std::vector<LawCase> result;
    for (const std::string &name : Materials::passive_laws().names())
      {
        const auto found = table().find(name);
        if (found == table().end() || found->second.empty())
          throw std::logic_error(
            "The passive law \"" + name +
            "\" of the factory table has no test parameters: add its "
            "parameter sets to tests/support/law_parameters.cc and its "
            "closed-form stress to tests/unit/materials/closed_form_test.cc.");
        for (const LawCase &c : found->second)
          result.push_back(c);
      }
    return result;
  }


  std::vector<std::string>
  laws_with_test_parameters()
  {
    std::vector<std::string> names;
    for (const auto &[name, cases] : table())
      if (!cases.empty())
        names.push_back(name);
    return names;
  }


  systole::Materials::HolzapfelOgden::Parameters
  arostica_holzapfel_ogden()
  {
    systole::Materials::HolzapfelOgden::Parameters p; // HO 2009 = Arostica
    p.switch_form =
      systole::Materials::HolzapfelOgden::Parameters::Switch::logistic;
    p.switch_sharpness = 100.0;
    return p;
  }


  systole::Materials::HolzapfelOgden::Parameters
  transversely_isotropic_holzapfel_ogden()
  {
    systole::Materials::HolzapfelOgden::Parameters p;
    p.a_s  = 0.0;
    p.a_fs = 0.0;
    return p;
  }
} // namespace test_support
