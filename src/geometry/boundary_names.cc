#include "geometry/boundary_names.h"

#include <deal.II/base/exceptions.h>

#include "base/first_members.h"

namespace systole::Geometry
{
  BoundaryNames::BoundaryNames(const std::string &source)
    : source_description(source)
  {}

  void
  BoundaryNames::add(const std::string               &name,
                     const dealii::types::boundary_id id)
  {
    ids[name] = id;
  }

  bool
  BoundaryNames::has(const std::string &name) const
  {
    return ids.count(name) > 0;
  }

  dealii::types::boundary_id
  BoundaryNames::id(const std::string &name) const
  {
    const auto it = ids.find(name);
    AssertThrow(it != ids.end(),
                dealii::ExcMessage(
                  source_description + " has no boundary part named '" + name +
                  "' (it has: " + listed() +
                  "). Tag that surface, e.g. with a gmsh Physical Surface(\"" +
                  name + "\")."));
    return it->second;
  }

  std::vector<std::string>
  BoundaryNames::names() const
  {
    return first_members(ids);
  }

  std::string
  BoundaryNames::listed() const
  {
    std::string result;
    for (const auto &entry : ids)
      result += (result.empty() ? "" : ", ") + entry.first;
    return result.empty() ? "none" : result;
  }

  const std::string &
  BoundaryNames::source() const
  {
    return source_description;
  }
} // namespace systole::Geometry
