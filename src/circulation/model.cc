#include "circulation/model.h"

#include "base/units.h"
#include "circulation/windkessel.h"

namespace systole::Circulation
{
  const char *
  output_suffix(const Quantity q)
  {
    switch (q)
      {
        case Quantity::volume:
          return "_mL";
        case Quantity::pressure:
          return "_mmHg";
        case Quantity::flow:
          return "_mL_per_s";
      }
    return "";
  }

  const char *
  output_unit(const Quantity q)
  {
    switch (q)
      {
        case Quantity::volume:
          return "mL";
        case Quantity::pressure:
          return "mmHg";
        case Quantity::flow:
          return "mL/s";
      }
    return "-";
  }

  double
  to_output_unit(const Quantity q, const double value)
  {
    switch (q)
      {
        case Quantity::volume:
          return Units::mm3_to_mL(value);
        case Quantity::pressure:
          return Units::kPa_to_mmHg(value);
        case Quantity::flow:
          return flow_to_mL_per_s(value);
      }
    return value;
  }
} // namespace systole::Circulation
