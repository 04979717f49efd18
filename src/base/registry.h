#pragma once

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

/// @file
/// The one table machinery of every extension point (passive and volumetric
/// laws, ionic models, tension models, circulation models, fibre generators,
/// postprocessors, problem types): a name users write in a parameter file, a
/// sentence for the documentation, how to declare the entry's own parameters
/// and how to build it. Each extension point keeps one explicit table of
/// entries in its factory file (no static self-registration: the table is
/// what a newcomer reads); the parameter help, the Patterns::Selection and the
/// "unknown name" errors all come from here.
///
/// How to add an entry to an extension point: write the class (one file
/// pair), then add one line to the table of its factory; the documentation
/// and the parameter file pick it up. Tests add toy entries with add().

namespace systole
{
  namespace internal
  {
    /// Throws "<what> = "<name>" is unknown; choose one of <choices>."
    [[noreturn]] void
    throw_unknown_name(const std::string &what,
                       const std::string &name,
                       const std::string &choices);

    /// Declares the selection entry @p entry (default @p default_name,
    /// Patterns::Selection of @p pattern) with help @p help in the current
    /// subsection of @p prm.
    void
    declare_selection(dealii::ParameterHandler &prm,
                      const std::string        &entry,
                      const std::string        &default_name,
                      const std::string        &pattern,
                      const std::string        &help);

    /// Enters subsection @p name, calls @p declare, leaves it.
    void
    declare_in_subsection(
      dealii::ParameterHandler                              &prm,
      const std::string                                     &name,
      const std::function<void(dealii::ParameterHandler &)> &declare);
  } // namespace internal

  /// Named entries whose builder has the signature @p Signature, e.g.
  /// `Registry<std::unique_ptr<PassiveLaw>(const dealii::ParameterHandler &)>`.
  template <class Signature>
  class Registry
  {
  public:
    struct Entry
    {
      std::string name;        ///< as users write it in a parameter file
      std::string description; ///< one sentence + reference, for the help
      /// Declares the entry's own parameters (null: it has none, or shares
      /// another entry's).
      std::function<void(dealii::ParameterHandler &)> declare;
      std::function<Signature>                        create;
    };

    /// The entry of a class @p T built from its own parameters: @p name,
    /// @p description, T::Parameters::declare, and a builder that makes a T
    /// of T::Parameters::parse(prm) (a builder's further arguments, as the
    /// period of a tension model, are not used). For the extension points
    /// whose builders return a std::unique_ptr to a base of T.
    template <class T>
    static Entry
    entry_of(std::string name, std::string description)
    {
      return {std::move(name),
              std::move(description),
              &T::Parameters::declare,
              [](const dealii::ParameterHandler &prm, const auto &...) {
                return std::make_unique<T>(T::Parameters::parse(prm));
              }};
    }

    /// @param[in] what the parameter that chooses an entry, as errors name
    ///            it ("Material / Passive law")
    Registry(std::string what, std::vector<Entry> entries)
      : what(std::move(what))
      , entries(std::move(entries))
    {}

    /// Adds @p entry at the end (tests, extensions outside the table).
    /// Declare the parameters after adding.
    void
    add(Entry entry)
    {
      entries.push_back(std::move(entry));
    }

    /// Removes the entry called @p name if there is one (tests).
    void
    remove(const std::string &name)
    {
      for (auto e = entries.begin(); e != entries.end(); ++e)
        if (e->name == name)
          {
            entries.erase(e);
            return;
          }
    }

    const std::vector<Entry> &
    all() const
    {
      return entries;
    }

    std::vector<std::string>
    names() const
    {
      std::vector<std::string> result;
      for (const Entry &e : entries)
        result.push_back(e.name);
      return result;
    }

    /// The names joined by @p separator ("|" for a Patterns::Selection).
    std::string
    joined_names(const std::string &separator) const
    {
      std::string result;
      for (const Entry &e : entries)
        result += (result.empty() ? "" : separator) + e.name;
      return result;
    }

    bool
    contains(const std::string &name) const
    {
      for (const Entry &e : entries)
        if (e.name == name)
          return true;
      return false;
    }

    /// The entry called @p name; throws one clear line naming the parameter
    /// and every valid name otherwise.
    const Entry &
    find(const std::string &name) const
    {
      for (const Entry &e : entries)
        if (e.name == name)
          return e;
      internal::throw_unknown_name(what, name, joined_names(", "));
    }

    /// Builds the entry called @p name from @p args.
    template <class... Args>
    auto
    create(const std::string &name, Args &&...args) const
    {
      return find(name).create(std::forward<Args>(args)...);
    }

    /// @p intro followed by "Choices: <name>: <description> ..." and
    /// @p units.
    std::string
    help(const std::string &intro, const std::string &units = "") const
    {
      std::string result = intro + " Choices:";
      for (const Entry &e : entries)
        result += " " + e.name + ": " + e.description;
      return units.empty() ? result : result + " " + units;
    }

    /// Declares the selection entry @p entry in the current subsection of
    /// @p prm, its help from help(@p intro, @p units).
    void
    declare_selection(dealii::ParameterHandler &prm,
                      const std::string        &entry,
                      const std::string        &default_name,
                      const std::string        &intro,
                      const std::string        &units = "Units: none.") const
    {
      internal::declare_selection(prm,
                                  entry,
                                  default_name,
                                  joined_names("|"),
                                  help(intro, units));
    }

    /// Declares every entry's own parameters, each in a subsection named
    /// after it (@p own_subsections) or where its declare() puts them.
    void
    declare_parameters(dealii::ParameterHandler &prm,
                       const bool                own_subsections) const
    {
      for (const Entry &e : entries)
        if (e.declare && own_subsections)
          internal::declare_in_subsection(prm, e.name, e.declare);
        else if (e.declare)
          e.declare(prm);
    }

  private:
    std::string        what;
    std::vector<Entry> entries;
  };
} // namespace systole
