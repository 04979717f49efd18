#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <type_traits>
#include <vector>

/// @file
/// A parameter list written once. A class whose Parameters struct has real
/// or integer entries keeps one table of them (name, the member that holds the
/// value, pattern, help); declare() and parse() both walk that table, so a
/// name, its default (the member's initialiser) and its help text live in one
/// place instead of a declare_entry list and a get_double list that must
/// agree. Entries of other types (selections, strings) and conditions on
/// several values stay written out beside the table.

namespace systole
{
  /// One entry of a parameter subsection whose value is a @p Number (double
  /// or long) with bounds of type @p Pattern.
  template <class Struct, typename Number, class Pattern>
  struct TableEntry
  {
    const char *name;        ///< as users write it
    Number Struct::*member;  ///< where the value goes
    Pattern         pattern; ///< its bounds
    std::string     help;    ///< meaning, units, source
  };

  /// A real entry.
  template <class Struct>
  using RealEntry = TableEntry<Struct, double, dealii::Patterns::Double>;

  /// An integer entry.
  template <class Struct>
  using IntegerEntry = TableEntry<Struct, long, dealii::Patterns::Integer>;

  /// Declares every entry of @p table in the current subsection of @p prm,
  /// with the value of its member in @p defaults (written by
  /// Patterns::Tools::to_string) as the default.
  template <class Struct, typename Number, class Pattern>
  void
  declare_entries(dealii::ParameterHandler                               &prm,
                  const std::vector<TableEntry<Struct, Number, Pattern>> &table,
                  const Struct &defaults = Struct())
  {
    for (const auto &e : table)
      prm.declare_entry(e.name,
                        dealii::Patterns::Tools::to_string(defaults.*
                                                           (e.member)),
                        e.pattern,
                        e.help);
  }

  /// Reads every entry of @p table from subsection @p path of @p prm into
  /// its member of @p values.
  template <class Struct, typename Number, class Pattern>
  void
  parse_entries(const dealii::ParameterHandler                         &prm,
                const std::vector<std::string>                         &path,
                const std::vector<TableEntry<Struct, Number, Pattern>> &table,
                Struct                                                 &values)
  {
    for (const auto &e : table)
      if constexpr (std::is_same_v<Number, double>)
        values.*(e.member) = prm.get_double(path, e.name);
      else
        values.*(e.member) = prm.get_integer(path, e.name);
  }
} // namespace systole
