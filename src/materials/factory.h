#pragma once

#include <deal.II/base/parameter_handler.h>

#include "base/registry.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"

#include <memory>
#include <string>
#include <vector>

/// @file
/// The one place that knows every passive material law (an explicit table in
/// factory.cc; no static self-registration). To add a law, see the recipe in
/// materials/passive_law.h.

namespace systole::Materials
{
  using PassiveLawRegistry =
    Registry<std::unique_ptr<PassiveLaw>(const dealii::ParameterHandler &)>;

  /// The table of passive laws (factory.cc), alphabetical, case-insensitive
  /// (a unit test checks it). The unit tests take their list of laws from its
  /// names(), so a law added to the table without test parameters and closed
  /// forms fails them.
  PassiveLawRegistry &
  passive_laws();

  /// Declares subsection "Material" with
  /// - "Passive law": a Patterns::Selection of the names of passive_laws(),
  /// default
  ///   "Guccione", whose help lists every law with its reference;
  /// - one subsection per law, named as the law ("Material / Guccione", ...),
  ///   holding that law's Parameters (all declared, so a parameter file is
  ///   fully checked whatever law it selects);
  /// - subsection "Volumetric" with "Form" and "Bulk modulus"
  ///   (VolumetricLaw::Parameters).
  /// Call once, before ParameterHandler::parse_input().
  void
  declare_parameters(dealii::ParameterHandler &prm);

  /// The law named in "Material / Passive law", built from its parsed and
  /// validated parameters (throws ExcMessage naming the entry on a bad value
  /// or an unknown name). @p prm must have been declared by
  /// declare_parameters().
  std::unique_ptr<PassiveLaw>
  create_passive_law(const dealii::ParameterHandler &prm);

  /// The volumetric law of "Material / Volumetric" (parsed and validated).
  VolumetricLaw
  create_volumetric_law(const dealii::ParameterHandler &prm);
} // namespace systole::Materials
