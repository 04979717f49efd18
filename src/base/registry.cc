#include "base/registry.h"

#include <deal.II/base/parameter_handler.h>

namespace systole::internal
{
  void
  throw_unknown_name(const std::string &what,
                     const std::string &name,
                     const std::string &choices)
  {
    AssertThrow(false,
                dealii::ExcMessage(what + " = \"" + name +
                                   "\" is unknown; choose one of " + choices +
                                   "."));
    throw; // not reached
  }

  void
  declare_selection(dealii::ParameterHandler &prm,
                    const std::string        &entry,
                    const std::string        &default_name,
                    const std::string        &pattern,
                    const std::string        &help)
  {
    prm.declare_entry(entry,
                      default_name,
                      dealii::Patterns::Selection(pattern),
                      help);
  }

  void
  declare_in_subsection(
    dealii::ParameterHandler                              &prm,
    const std::string                                     &name,
    const std::function<void(dealii::ParameterHandler &)> &declare)
  {
    prm.enter_subsection(name);
    declare(prm);
    prm.leave_subsection();
  }
} // namespace systole::internal
