// The factory table of passive laws (materials/factory.cc) and the tests'
// list of laws (support/law_parameters.cc), which is generated from it: every
// law of the table must have test parameters, be buildable by name from its
// declared defaults, and behave like the law built from its Parameters().

#include <deal.II/base/parameter_handler.h>

#include "materials/factory.h"
#include "support/law_parameters.h"
#include "support/random_tensors.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <set>
#include <string>
#include <vector>

using namespace systole;

namespace
{
  std::string
  lower_case(std::string text)
  {
    for (char &c : text)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
  }
} // namespace


TEST_CASE("Every law of the factory table has test parameters and every "
          "test parameter set is a law of the table",
          "[materials][factory]")
{
  const std::vector<std::string> table = Materials::passive_laws().names();
  const std::vector<std::string> tested =
    test_support::laws_with_test_parameters();
  for (const std::string &name : table)
    {
      INFO("\"" << name << "\" is in the factory table; give it parameter "
                << "sets in tests/support/law_parameters.cc");
      CHECK(std::find(tested.begin(), tested.end(), name) != tested.end());
    }
  for (const std::string &name : tested)
    {
      INFO("\"" << name << "\" has test parameters but is not in the "
                << "factory table");
      CHECK(std::find(table.begin(), table.end(), name) != table.end());
    }

  // Each case is the law it is filed under, and each law has its defaults
  // among its cases.
  const std::vector<test_support::LawCase> cases =
    test_support::passive_law_cases();
  for (const std::string &name : table)
    {
      INFO(name);
      unsigned int n_defaults = 0;
      for (const test_support::LawCase &c : cases)
        if (c.law->name() == name)
          {
            CHECK(c.label.rfind(name, 0) == 0);
            n_defaults += c.default_parameters;
          }
      CHECK(n_defaults == 1);
    }
}


TEST_CASE("The factory table is alphabetical and its names are unique",
          "[materials][factory]")
{
  const std::vector<std::string> names = Materials::passive_laws().names();
  REQUIRE(names.size() > 1);
  for (std::size_t i = 1; i < names.size(); ++i)
    {
      INFO(names[i - 1] << " before " << names[i]);
      CHECK(lower_case(names[i - 1]) < lower_case(names[i]));
    }
  CHECK(std::set<std::string>(names.begin(), names.end()).size() ==
        names.size());
}


TEST_CASE("Every law of the factory table is built by name from its "
          "declared defaults",
          "[materials][factory]")
{
  // The declared defaults (declare) read back (parse) must give the law of
  // the default Parameters(): same name, same energy, stress and tangent.
  for (const test_support::LawCase &c : test_support::passive_law_cases())
    {
      if (!c.default_parameters)
        continue;
      DYNAMIC_SECTION(c.label)
      {
        dealii::ParameterHandler prm;
        Materials::declare_parameters(prm);
        prm.enter_subsection("Material");
        prm.set("Passive law", c.law->name());
        prm.leave_subsection();
        const auto law = Materials::create_passive_law(prm);
        REQUIRE(law != nullptr);
        CHECK(law->name() == c.law->name());
        for (const unsigned int seed : {2u, 5u, 9u})
          {
            INFO("seed " << seed);
            const auto in = test_support::random_passive_input(seed, 0.15);
            Materials::PassiveOutput by_name, direct;
            law->evaluate(in, by_name);
            c.law->evaluate(in, direct);
            CHECK(by_name.psi == Approx(direct.psi).epsilon(1e-14));
            CHECK((by_name.S - direct.S).norm() <= 1e-14 * direct.S.norm());
            CHECK((by_name.dS_dE - direct.dS_dE).norm() <=
                  1e-14 * direct.dS_dE.norm());
          }
      }
    }
}
