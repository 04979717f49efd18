#include "circulation/model.h"

#include "base/units.h"
#include "circulation/windkessel.h"

namespace systole::Circulation
{
  namespace
  {
    /// How a quantity appears in output files.
    struct OutputUnit
    {
      const char *suffix;
      const char *unit;
      /// From the internal unit (null: none, for a value out of range).
      double (*convert)(double);
    };

    OutputUnit
    output_unit_of(const Quantity q)
    {
      switch (q)
        {
          case Quantity::volume:
            return {"_mL", "mL", &Units::mm3_to_mL};
          case Quantity::pressure:
            return {"_mmHg", "mmHg", &Units::kPa_to_mmHg};
          case Quantity::flow:
            return {"_mL_per_s", "mL/s", &flow_to_mL_per_s};
        }
      return {"", "-", nullptr};
    }
  } // namespace

  const char *
  output_suffix(const Quantity q)
  {
    return output_unit_of(q).suffix;
  }

  const char *
  output_unit(const Quantity q)
  {
    return output_unit_of(q).unit;
  }

  double
  to_output_unit(const Quantity q, const double value)
  {
    const auto convert = output_unit_of(q).convert;
    return convert != nullptr ? convert(value) : value;
  }
} // namespace systole::Circulation
