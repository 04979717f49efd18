#pragma once

#include <deal.II/base/parameter_handler.h>

#include "base/registry.h"
#include "materials/tension_model.h"

#include <memory>
#include <string>
#include <vector>

/// @file
/// The one place that knows every active-tension model (an explicit table in
/// tension_factory.cc). To add a model, see the recipe in
/// materials/tension_model.h.

namespace systole::Materials
{
  /// Builds a model from the parameters and the beat period [ms].
  using TensionModelRegistry =
    Registry<std::unique_ptr<TensionModel>(const dealii::ParameterHandler &,
                                           const double)>;

  /// The table of tension models (tension_factory.cc).
  TensionModelRegistry &
  tension_models();

  /// Declares subsection "Active tension": "Model" (a selection of
  /// the names of tension_models(), default "Bestel"), the Bestel entries
  /// (Bestel::Parameters, which stay at the subsection's top level) and one
  /// subsection per other model ("Active tension / Land").
  void
  declare_tension_parameters(dealii::ParameterHandler &prm);

  /// The model named in "Active tension / Model", from its parsed and
  /// validated parameters. @p period: the beat period [ms] (the Bestel curve
  /// is periodic).
  std::unique_ptr<TensionModel>
  create_tension_model(const dealii::ParameterHandler &prm,
                       const double                    period);

  /// The name in "Active tension / Model".
  std::string
  tension_model_name(const dealii::ParameterHandler &prm);
} // namespace systole::Materials
