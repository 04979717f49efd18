#pragma once

#include <deal.II/base/parameter_handler.h>

#include "base/registry.h"
#include "circulation/chamber_elastance.h"
#include "circulation/model.h"

#include <memory>
#include <string>
#include <vector>

/// @file
/// The one place that knows every 0D circulation model (an explicit table
/// in model_factory.cc, like the passive laws'). To add a model, see the
/// recipe in circulation/model.h.

namespace systole::Circulation
{
  /// What every model gets from the shared entries of subsection
  /// Circulation.
  struct ModelInputs
  {
    double                       period; ///< [ms]
    ChamberElastance::Parameters left_ventricle, right_ventricle;
    /// The kinds of the ventricles "lv" and "rv".
    CavityKind left_kind  = CavityKind::elastance,
               right_kind = CavityKind::elastance;
  };

  using ModelRegistry =
    Registry<std::unique_ptr<Model>(const dealii::ParameterHandler &,
                                    const ModelInputs &)>;

  /// The table of circulation models (model_factory.cc), alphabetical:
  /// "2-element Windkessel", "3-element Windkessel", "4-element Windkessel",
  /// "closed loop".
  ModelRegistry &
  models();

  /// Declares, in subsection "Circulation":
  /// - "Model": a Patterns::Selection of the names of models(), default "closed
  ///   loop", whose help lists every model;
  /// - subsections "Left ventricle" and "Right ventricle": the 0D
  ///   elastance ventricles of the models (ChamberElastance rows);
  /// - every model's own entries (subsection "Closed loop", subsection
  ///   "4-element Windkessel", "Closed valve resistance"; all declared, so
  ///   a file is fully checked whatever model it selects).
  /// Call once, besides Circulation::Parameters::declare(), before
  /// ParameterHandler::parse_input().
  void
  declare_model_parameters(dealii::ParameterHandler &prm);

  /// The model named in "Circulation / Model", built from its parsed and
  /// validated parameters, with the period of "Circulation / Period". Its
  /// ventricles are 0D elastances except those named in @p external ("lv",
  /// "rv"): 3D ventricles, whose pressures are inputs (CavityKind::external).
  /// Throws ExcMessage naming the entry on a bad value, or naming the model
  /// when it has no ventricle of a name in @p external.
  std::unique_ptr<Model>
  create_model(const dealii::ParameterHandler &prm,
               const std::vector<std::string> &external = {});
} // namespace systole::Circulation
