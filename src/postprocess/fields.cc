#include "postprocess/fields.h"

#include "base/first_members.h"

namespace systole::Postprocess
{
  Fields::Fields(std::vector<std::pair<std::string, Getter>> fields,
                 const bool                                  needs_frame)
    : fields(std::move(fields))
    , needs_frame(needs_frame)
  {}

  Needs
  Fields::needs() const
  {
    Needs n;
    n.cardiac_frame = needs_frame;
    return n;
  }

  std::vector<std::string>
  Fields::field_names() const
  {
    return first_members(fields);
  }

  double
  Fields::field_value(const unsigned int i, const PointQuantities &q) const
  {
    return fields[i].second(q);
  }
} // namespace systole::Postprocess
