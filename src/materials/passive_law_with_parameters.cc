#include "materials/passive_law_with_parameters.h"

#include <cmath>

namespace systole::Materials
{
  void
  require_in_range(const Range        range,
                   const char        *law,
                   const char        *entry,
                   const double       value,
                   const std::string &fix)
  {
    const bool positive = (range == Range::positive);
    AssertThrow(std::isfinite(value) && (positive ? value > 0.0 : value >= 0.0),
                dealii::ExcMessage(
                  std::string("Material / ") + law + " / " + entry + " = " +
                  dealii::Patterns::Tools::to_string(value) + " must be " +
                  (positive ? "> 0; " : ">= 0; ") + fix + "."));
  }
} // namespace systole::Materials
