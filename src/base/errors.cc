#include "base/errors.h"

#include <sstream>

namespace systole
{
  std::string
  one_line_message(const std::exception &e)
  {
    std::string text;
    if (const auto *dealii_exc =
          dynamic_cast<const dealii::ExceptionBase *>(&e))
      {
        std::ostringstream info;
        dealii_exc->print_info(info);
        text = info.str();
        if (text.find_first_not_of(" \t\n") == std::string::npos)
          text = dealii_exc->get_exc_name();
      }
    else
      text = e.what();

    // Fold all white space (deal.II messages wrap and indent) into single
    // blanks.
    std::string folded;
    bool        blank = false;
    for (const char c : text)
      {
        if (c == ' ' || c == '\n' || c == '\t' || c == '\r')
          blank = !folded.empty();
        else
          {
            if (blank)
              folded += ' ';
            folded += c;
            blank = false;
          }
      }
    return folded;
  }
} // namespace systole
