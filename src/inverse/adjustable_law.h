#pragma once

#include <deal.II/base/parameter_handler.h>

#include "materials/passive_law.h"

#include <memory>
#include <string>
#include <vector>

namespace systole::Inverse
{
  /// A passive law whose parameters can change after the mechanics was built
  /// on it: it forwards to a law it owns, which set() replaces. The
  /// mechanics keeps a reference to this object, so a calibration changes the
  /// material between solves without rebuilding DoFs, fibres or mapping.
  /// Not thread safe while set() runs (call it between solves only).
  class AdjustableLaw : public Materials::PassiveLaw
  {
  public:
    explicit AdjustableLaw(std::unique_ptr<Materials::PassiveLaw> law);

    /// Use @p law from now on.
    void
    set(std::unique_ptr<Materials::PassiveLaw> law);

    void
    evaluate(const Materials::PassiveInput &in,
             Materials::PassiveOutput      &out) const override;

    std::string
    name() const override;

  private:
    std::unique_ptr<Materials::PassiveLaw> law;
  };

  /// Builds the law of "Material / Passive law" with some of its entries
  /// ("Material / <law> / <entry>") set to new values, through the factory
  /// (so each law validates its values as when read from a file). Keeps a
  /// private copy of the Material subsection of the parameters.
  class LawRebuilder
  {
  public:
    /// @param[in] prm the run's parameters (Material declared and read)
    /// @param[in] entries names of entries of the chosen law's subsection;
    ///            throws naming @p list_entry (the parameter that lists
    ///            them) when one does not exist
    LawRebuilder(const dealii::ParameterHandler &prm,
                 const std::vector<std::string> &entries,
                 const std::string              &list_entry);
    ~LawRebuilder();

    /// The name of the law ("Holzapfel-Ogden").
    const std::string &
    law_name() const
    {
      return law;
    }

    /// The values of the entries in the parameter file.
    const std::vector<double> &
    initial_values() const
    {
      return initial;
    }

    /// The law with the entries set to @p values (in the order of the
    /// entries). Throws the law's message on an invalid value.
    std::unique_ptr<Materials::PassiveLaw>
    build(const std::vector<double> &values) const;

  private:
    std::unique_ptr<dealii::ParameterHandler> prm;
    std::string                               law;
    std::vector<std::string>                  entries;
    std::vector<double>                       initial;
  };
} // namespace systole::Inverse
