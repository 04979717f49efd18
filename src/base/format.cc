#include "base/format.h"

#include <iomanip>
#include <sstream>

namespace systole
{
  std::string
  format_number(const double value, const int significant_digits)
  {
    std::ostringstream o;
    o << std::setprecision(significant_digits) << value;
    return o.str();
  }
} // namespace systole
