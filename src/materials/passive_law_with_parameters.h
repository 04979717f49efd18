#pragma once

#include <deal.II/base/parameter_handler.h>

#include "materials/passive_law.h"

#include <string>
#include <vector>

namespace systole::Materials
{
  /// What every passive law of this folder shares: it keeps the law's
  /// parameters (validated on construction) and names the law after them. A
  /// law @c X is written as
  /// - a plain @c struct @c XParameters @c : @c LawParameters<XParameters>
  ///   with the values (each documented with its unit and range) and
  ///   - @c static @c constexpr @c const @c char @c *law_name: the name in
  ///     "Material / Passive law", which is also the law's subsection
  ///     "Material / <law_name>";
  ///   - @c static @c const @c std::vector<LawEntry<XParameters>>
  ///     @c &entries(): one line per real entry (name, member, range, help
  ///     with units and source, the fix an error suggests), from which
  ///     LawParameters declares, parses and validates;
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

  /// One real entry of subsection "Material / <law_name>", written once:
  /// declared with Patterns::Double(0.0) and the member's value in a
  /// default-built @p ParametersType as default, read into the member, and
  /// checked against the range.
  template <class ParametersType>
  struct LawEntry
  {
    const char *name;               ///< entry name in the parameter file
    double ParametersType::*member; ///< where the value goes
    Range                   range;  ///< the range validate() requires
    std::string             help;   ///< meaning, units, source, range
    const char             *fix;    ///< what to set when out of range
  };

  /// Declaring, parsing and validating of a law's parameters from its table
  /// @c Derived::entries() (see PassiveLawWithParameters). A law with entries
  /// beyond the table (a selection, a condition on several values) hides
  /// declare_more(), parse_more() or validate_more() with its own.
  template <class Derived>
  struct LawParameters
  {
    /// Declares the entries in the current subsection (the factory enters
    /// "Material / <law_name>" first), then declare_more().
    static void
    declare(dealii::ParameterHandler &prm)
    {
      const Derived defaults;
      for (const LawEntry<Derived> &e : Derived::entries())
        prm.declare_entry(e.name,
                          dealii::Patterns::Tools::to_string(defaults.*
                                                             (e.member)),
                          dealii::Patterns::Double(0.0),
                          e.help);
      Derived::declare_more(prm);
    }

    /// Reads "Material / <law_name>" with deal.II 9.4's path getters (the
    /// table, then parse_more()) and validates.
    static Derived
    parse(const dealii::ParameterHandler &prm)
    {
      const std::vector<std::string> path = {"Material", Derived::law_name};
      Derived                        p;
      for (const LawEntry<Derived> &e : Derived::entries())
        p.*(e.member) = prm.get_double(path, e.name);
      p.parse_more(prm, path);
      p.validate();
      return p;
    }

    /// Throws ExcMessage naming "Material / <law_name> / <entry>" and the fix
    /// if a value is out of its range (in table order), then
    /// validate_more().
    void
    validate() const
    {
      const Derived &p = static_cast<const Derived &>(*this);
      for (const LawEntry<Derived> &e : Derived::entries())
        require_in_range(e.range,
                         Derived::law_name,
                         e.name,
                         p.*(e.member),
                         e.fix);
      p.validate_more();
    }

    /// Declares nothing beyond the table.
    static void
    declare_more(dealii::ParameterHandler &)
    {}

    /// Reads nothing beyond the table.
    void
    parse_more(const dealii::ParameterHandler &,
               const std::vector<std::string> &)
    {}

    /// Requires nothing beyond the ranges of the table.
    void
    validate_more() const
    {}
  };
} // namespace systole::Materials
