#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

/// @file
/// A parameter list written once. A class whose Parameters struct has real
/// entries keeps one table of them (name, the member that holds the value,
/// pattern, help); declare() and parse() both walk that table, so a name, its
/// default (the member's initialiser) and its help text live in one place
/// instead of a declare_entry list and a get_double list that must agree.
/// Entries of other types (selections, integers, strings) and conditions on
/// several values stay written out beside the table.

namespace systole
{
  /// One real entry of a parameter subsection.
  template <class Struct>
  struct RealEntry
  {
    const char *name;                 ///< as users write it
    double Struct::         *member;  ///< where the value goes
    dealii::Patterns::Double pattern; ///< its bounds
    std::string              help;    ///< meaning, units, source
  };

  /// Declares every entry of @p table in the current subsection of @p prm,
  /// with the value of its member in @p defaults (written by
  /// Patterns::Tools::to_string) as the default.
  template <class Struct>
  void
  declare_entries(dealii::ParameterHandler             &prm,
                  const std::vector<RealEntry<Struct>> &table,
                  const Struct                         &defaults = Struct())
  {
    for (const RealEntry<Struct> &e : table)
      prm.declare_entry(e.name,
                        dealii::Patterns::Tools::to_string(defaults.*
                                                           (e.member)),
                        e.pattern,
                        e.help);
  }

  /// Reads every entry of @p table from subsection @p path of @p prm into
  /// its member of @p values.
  template <class Struct>
  void
  parse_entries(const dealii::ParameterHandler       &prm,
                const std::vector<std::string>       &path,
                const std::vector<RealEntry<Struct>> &table,
                Struct                               &values)
  {
    for (const RealEntry<Struct> &e : table)
      values.*(e.member) = prm.get_double(path, e.name);
  }
} // namespace systole
