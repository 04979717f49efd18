#pragma once

#include <deal.II/base/parameter_handler.h>

#include "base/registry.h"
#include "electrophysiology/ionic_model.h"

#include <memory>
#include <string>
#include <vector>

/// @file
/// The one place that knows every ionic model (an explicit table in
/// ionic_factory.cc). To add a model, see the recipe in ionic_model.h.

namespace systole::Electrophysiology
{
  using IonicModelRegistry =
    Registry<std::unique_ptr<IonicModel>(const dealii::ParameterHandler &)>;

  /// The table of ionic models (ionic_factory.cc), alphabetical:
  /// "Aliev-Panfilov", "Mitchell-Schaeffer", "ten Tusscher-Panfilov".
  IonicModelRegistry &
  ionic_models();

  /// Declares, in the current subsection (the caller enters
  /// "Electrophysiology"), the entry "Ionic model" (a Patterns::Selection of
  /// the names of ionic_models(), whose help lists every model with its
  /// reference) and one subsection per model, named as the model, with its
  /// parameters.
  void
  declare_ionic_model_parameters(dealii::ParameterHandler &prm);

  /// The model named in "Electrophysiology / Ionic model", built from its
  /// parsed and validated parameters.
  std::unique_ptr<IonicModel>
  create_ionic_model(const dealii::ParameterHandler &prm);

  /// The model called @p name with its default parameters (tests, tools).
  std::unique_ptr<IonicModel>
  create_ionic_model(const std::string &name);
} // namespace systole::Electrophysiology
