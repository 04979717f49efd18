#pragma once

#include "postprocess/postprocessor.h"

#include <memory>
#include <string>
#include <vector>

namespace systole::Postprocess
{
  /// The names of the postprocessors, alphabetical (the choices of
  /// Postprocess / List of postprocessors).
  std::vector<std::string>
  postprocessor_names();

  /// One line per postprocessor: "name: what it writes." (the help text).
  std::string
  postprocessor_descriptions();

  /// The postprocessor @p name; throws naming the valid ones otherwise.
  std::unique_ptr<Postprocessor>
  create_postprocessor(const std::string &name);
} // namespace systole::Postprocess
