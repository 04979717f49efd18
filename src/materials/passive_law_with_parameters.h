#pragma once

#include <deal.II/base/parameter_handler.h>

#include "materials/passive_law.h"

#include <string>

namespace systole::Materials
{
  /// What every passive law of this folder shares: it keeps the law's
  /// parameters (validated on construction) and names the law after them. A
  /// law @c X is written as
  /// - a plain @c struct @c XParameters with the values (each documented with
  ///   its unit and range) and
  ///   - @c static @c constexpr @c const @c char @c *law_name: the name in
  ///     "Material / Passive law", which is also the law's subsection
  ///     "Material / <law_name>";
  ///   - @c static @c void @c declare(dealii::ParameterHandler &prm):
  ///     declares its entries in the current subsection (the factory enters
  ///     "Material / <law_name>" first), units and range in each help text;
  ///   - @c static @c XParameters @c parse(const dealii::ParameterHandler
  ///     &prm): reads "Material / <law_name>" with the path getters and
  ///     validates;
  ///   - @c void @c validate() @c const: throws ExcMessage naming
  ///     "Material / <law_name> / <entry>" and the fix when a value is out of
  ///     range (require_in_range());
  /// - @c class @c X @c : @c public @c PassiveLawWithParameters<XParameters>,
  ///   which inherits this constructor and writes evaluate() (energy [kPa],
  ///   2nd Piola-Kirchhoff stress [kPa] and dS/dE [kPa]).
  ///
  /// X::Parameters and X::law_name are then XParameters and its law_name.
  template <class ParametersType>
  class PassiveLawWithParameters : public PassiveLaw
  {
  public:
    /// The law's parameters (see the class documentation).
    using Parameters = ParametersType;

    /// Name in the parameter file ("Material / Passive law").
    static constexpr const char *law_name = Parameters::law_name;

    /// @param[in] parameters validated (before any member of the derived
    /// law is built, so a bad value is reported under this law's name).
    explicit PassiveLawWithParameters(const Parameters &parameters)
      : params((parameters.validate(), parameters))
    {}

    /// Returns law_name.
    std::string
    name() const final
    {
      return law_name;
    }

    /// The parameters in use.
    const Parameters &
    parameters() const
    {
      return params;
    }

  protected:
    const Parameters params;
  };

  /// The range a parameter of a law must lie in.
  enum class Range
  {
    positive,    ///< finite and > 0
    non_negative ///< finite and >= 0
  };

  /// Throws ExcMessage "Material / <law> / <entry> = <value> must be > 0;
  /// <fix>." (">= 0" for Range::non_negative) unless @p value is in
  /// @p range. @p fix says what to set ("set e.g. 10 kPa").
  void
  require_in_range(const Range        range,
                   const char        *law,
                   const char        *entry,
                   const double       value,
                   const std::string &fix);
} // namespace systole::Materials
