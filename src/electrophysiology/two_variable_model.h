#pragma once

#include <deal.II/base/parameter_handler.h>

#include "base/parameter_table.h"
#include "electrophysiology/ionic_model.h"

#include <string>
#include <vector>

namespace systole::Electrophysiology
{
  /// Declaring and parsing of the parameters of a model of two variables
  /// from their table @c Derived::entries() (see TwoVariableModel).
  template <class Derived>
  struct TwoVariableParameters
  {
    /// Declares the entries in the current subsection (the factory enters
    /// "Electrophysiology / <model_name>" first).
    static void
    declare(dealii::ParameterHandler &prm)
    {
      declare_entries(prm, Derived::entries());
    }

    /// Reads and validates "Electrophysiology / <model_name>".
    static Derived
    parse(const dealii::ParameterHandler &prm)
    {
      Derived p;
      parse_entries(prm,
                    {"Electrophysiology", Derived::model_name},
                    Derived::entries(),
                    p);
      p.validate();
      return p;
    }
  };

  /// What the phenomenological models of two variables share: the potential
  /// is the normalised u (rest at u = 0; V = 100 u - 80 mV, the convention
  /// of physiology.md) and there is one state variable, the recovery
  /// variable or gate. A model @c X of this kind is written as
  /// - a plain @c struct @c XParameters @c :
  ///   @c TwoVariableParameters<XParameters> with the values (each documented
  ///   with its unit and range),
  ///   @c static @c constexpr @c const @c char @c *model_name (the name in
  ///   "Electrophysiology / Ionic model" and of the model's subsection), its
  ///   table @c entries() (name, member, pattern, help) and @c validate()
  ///   (throws ExcMessage naming the entry if a value is out of range);
  /// - @c class @c X @c : @c public @c TwoVariableModel<XParameters>, which
  ///   inherits this constructor and writes resting_state(), ionic_current()
  ///   and state_rhs().
  /// AlievPanfilov and MitchellSchaeffer are written so.
  template <class ParametersType>
  class TwoVariableModel : public IonicModel
  {
  public:
    using Parameters = ParametersType;

    static constexpr const char *model_name = Parameters::model_name;

    /// @param[in] parameters validated here.
    explicit TwoVariableModel(const Parameters &parameters)
      : params(parameters)
    {
      params.validate();
    }

    /// Returns model_name.
    std::string
    name() const final
    {
      return model_name;
    }

    /// 1: the recovery variable.
    unsigned int
    n_states() const final
    {
      return 1;
    }

    /// 0.
    double
    resting_potential() const final
    {
      return 0.0;
    }

    /// 100 mV per unit of u.
    double
    potential_scale_mV() const final
    {
      return 100.0;
    }

    /// -80 mV at u = 0.
    double
    potential_offset_mV() const final
    {
      return -80.0;
    }

  protected:
    const Parameters params;
  };
} // namespace systole::Electrophysiology
