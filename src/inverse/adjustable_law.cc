#include "inverse/adjustable_law.h"

#include <deal.II/base/parameter_handler.h>

#include "materials/factory.h"

#include <iomanip>
#include <sstream>

namespace systole::Inverse
{
  AdjustableLaw::AdjustableLaw(std::unique_ptr<Materials::PassiveLaw> law)
    : law(std::move(law))
  {}

  void
  AdjustableLaw::set(std::unique_ptr<Materials::PassiveLaw> new_law)
  {
    law = std::move(new_law);
  }

  void
  AdjustableLaw::evaluate(const Materials::PassiveInput &in,
                          Materials::PassiveOutput      &out) const
  {
    law->evaluate(in, out);
  }

  std::string
  AdjustableLaw::name() const
  {
    return law->name();
  }

  LawRebuilder::LawRebuilder(const dealii::ParameterHandler &original,
                             const std::vector<std::string> &entries,
                             const std::string              &list_entry)
    : prm(std::make_unique<dealii::ParameterHandler>())
    , law(original.get({"Material"}, "Passive law"))
    , entries(entries)
  {
    // A private copy of subsection Material: declare it, then read the run's
    // values (printed, all other subsections skipped).
    Materials::declare_parameters(*prm);
    std::ostringstream text;
    original.print_parameters(text, dealii::ParameterHandler::ShortPRM);
    prm->parse_input_from_string(text.str(), "", /*skip_undefined=*/true);

    for (const auto &entry : entries)
      {
        double value = 0;
        try
          {
            value = prm->get_double({"Material", law}, entry);
          }
        catch (const dealii::ExceptionBase &)
          {
            AssertThrow(false,
                        dealii::ExcMessage(
                          list_entry + " names '" + entry +
                          "', which is no number entry of Material / " + law +
                          " (the law of Material / Passive law): name "
                          "entries of that subsection, e.g. a, a_f for "
                          "Holzapfel-Ogden or C for Guccione."));
          }
        initial.push_back(value);
      }
  }

  LawRebuilder::~LawRebuilder() = default;

  std::unique_ptr<Materials::PassiveLaw>
  LawRebuilder::build(const std::vector<double> &values) const
  {
    AssertThrow(values.size() == entries.size(), dealii::ExcInternalError());
    prm->enter_subsection("Material");
    prm->enter_subsection(law);
    for (unsigned int i = 0; i < entries.size(); ++i)
      {
        std::ostringstream v;
        v << std::setprecision(17) << values[i];
        prm->set(entries[i], v.str());
      }
    prm->leave_subsection();
    prm->leave_subsection();
    return Materials::create_passive_law(*prm);
  }
} // namespace systole::Inverse
