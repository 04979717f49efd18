#pragma once

// Shared by the circulation tests: a surrogate ventricle with realistic
// parameters and an observer that keeps everything.

#include "base/units.h"
#include "circulation/cardiac_cycle.h"
#include "circulation/elastance_ventricle.h"

#include <functional>
#include <vector>

namespace circulation_test
{
  using namespace systole;
  using namespace systole::Circulation;

  /// Contraction onset within the beat [ms].
  constexpr double onset = 300.0;

  /// E_min 0.09, E_max 2.5 mmHg/mL, V_0 10 mL; with the default circulation
  /// this gives EDV ~ 120 mL, ESV ~ 50 mL, peak ~ 115 mmHg.
  inline ElastanceVentricle::Parameters
  surrogate_parameters()
  {
    const double per_mL = Units::mmHg / Units::mL; // mmHg/mL -> kPa/mm^3
    ElastanceVentricle::Parameters p;
    p.minimum_elastance    = 0.09 * per_mL;
    p.maximum_elastance    = 2.5 * per_mL;
    p.unloaded_volume      = Units::mL_to_mm3(10.0);
    p.period               = 800.0;
    p.contraction_onset    = onset;
    p.contraction_duration = 270.0;
    p.relaxation_duration  = 180.0;
    return p;
  }

  /// Keeps every record, transition and summary.
  struct Recorder : CardiacCycle::Observer
  {
    std::vector<StepRecord>  steps;
    std::vector<Transition>  transitions;
    std::vector<BeatSummary> beats;

    void
    on_step(const StepRecord &r) override
    {
      steps.push_back(r);
    }
    void
    on_transition(const Transition &t) override
    {
      transitions.push_back(t);
    }
    void
    on_beat(const BeatSummary &s) override
    {
      beats.push_back(s);
    }

    /// The step record at the time of transition @p i (the last record at
    /// that time).
    const StepRecord &
    record_at(const Transition &t) const
    {
      for (auto r = steps.rbegin(); r != steps.rend(); ++r)
        if (r->time == t.time)
          return *r;
      return steps.front();
    }
  };

  /// A ventricle whose pressure follows a prescribed history p(t) [kPa],
  /// whatever the volume.
  class ScriptedVentricle : public Ventricle
  {
  public:
    explicit ScriptedVentricle(std::function<double(double)> p)
      : p(std::move(p))
    {}

    double
    pressure(const double t, const double) override
    {
      return p(t);
    }

  private:
    std::function<double(double)> p;
  };
} // namespace circulation_test
