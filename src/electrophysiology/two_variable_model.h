#pragma once

#include "electrophysiology/ionic_model.h"

namespace systole::Electrophysiology
{
  /// What the phenomenological models of two variables share: the potential
  /// is the normalised u (rest at u = 0; V = 100 u - 80 mV, the convention
  /// of physiology.md) and there is one state variable, the recovery
  /// variable or gate. AlievPanfilov and MitchellSchaeffer derive from it
  /// and write the rest of IonicModel.
  class TwoVariableModel : public IonicModel
  {
  public:
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
  };
} // namespace systole::Electrophysiology
