#pragma once

#include "materials/tension_model.h"

#include <functional>
#include <string>
#include <utility>

namespace test_support
{
  /// A stateless tension model for the extension-point tests: driven by the
  /// activation time, its tension a given function of the step's input.
  class ToyTension : public systole::Materials::TensionModel
  {
  public:
    using Function =
      std::function<double(const systole::Materials::TensionInput &)>;

    ToyTension(std::string name, Function tension, const double onset = 0)
      : TensionModel(std::move(name),
                     systole::Materials::TensionDrive::activation_time,
                     0)
      , tension(std::move(tension))
      , onset(onset)
    {}
    void
    initial_state(double *) const override
    {}
    void
    step(const double *,
         const systole::Materials::TensionInput &in,
         double *,
         systole::Materials::TensionOutput &out) const override
    {
      out.tension           = tension(in);
      out.dtension_dstretch = 0;
    }
    double
    tension_of_state(const double *, const double) const override
    {
      return tension({});
    }
    double
    onset_delay() const override
    {
      return onset;
    }

  private:
    Function tension;
    double   onset;
  };
} // namespace test_support
