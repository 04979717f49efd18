#pragma once

#include "base/registry.h"

#include "postprocess/postprocessor.h"

#include <memory>
#include <string>
#include <vector>

namespace systole::Postprocess
{
  /// Postprocessors take no parameters of their own (they are listed in
  /// Postprocess / List of postprocessors).
  using PostprocessorRegistry = Registry<std::unique_ptr<Postprocessor>()>;

  /// The table of postprocessors (factory.cc).
  PostprocessorRegistry &
  postprocessors();

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
