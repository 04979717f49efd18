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
      : model_name(std::move(name))
      , tension(std::move(tension))
      , onset(onset)
    {}
    std::string
    name() const override
    {
      return model_name;
    }
    systole::Materials::TensionDrive
    drive() const override
    {
      return systole::Materials::TensionDrive::activation_time;
    }
    unsigned int
    n_states() const override
    {
      return 0;
    }
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
    std::string model_name;
    Function    tension;
    double      onset;
  };
} // namespace test_support
