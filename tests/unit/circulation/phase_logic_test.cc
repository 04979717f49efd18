#include "base/units.h"
#include "circulation/cardiac_cycle.h"

#include "cycle_helpers.h"
#include <catch2/catch.hpp>

#include <cmath>

using namespace circulation_test;

namespace
{
  /// sin^2 bump of height @p amplitude [mmHg] on [300, 700] ms of the beat.
  double
  bump(const double tau, const double amplitude)
  {
    if (tau < 300.0 || tau > 700.0)
      return 0.0;
    const double s = std::sin(M_PI * (tau - 300.0) / 400.0);
    return amplitude * s * s;
  }

  /// Time within the beat where the bump of @p amplitude rises through
  /// @p level [mmHg].
  double
  bump_crossing(const double level, const double amplitude)
  {
    return 300.0 + 400.0 / M_PI * std::asin(std::sqrt(level / amplitude));
  }
} // namespace

TEST_CASE("A contraction too weak to open the aortic valve gives 0 -> 1 -> 0 "
          "and the next beat proceeds",
          "[circulation]")
{
  // The mitral closure may be armed from the start of the beat (onset 0) or
  // from 300 ms: p < p_at until 300 ms either way.
  const double contraction_onset = GENERATE(0.0, onset);
  CAPTURE(contraction_onset);
  Parameters prm;
  prm.n_max_beats           = 2;
  prm.periodicity_tolerance = 0;
  // Beat 0 peaks at 49 mmHg, below p_ar (about 57 mmHg then); beat 1 at
  // 159 mmHg.
  ScriptedVentricle ventricle([](const double t) {
    const double tau       = std::fmod(t, 800.0);
    const double amplitude = t < 800.0 ? 40.0 : 150.0;
    return Units::mmHg_to_kPa(9.0 + bump(tau, amplitude));
  });
  CardiacCycle      cycle(prm, ventricle, Units::mL_to_mm3(50.0), onset);
  Recorder          rec;
  cycle.run(rec);

  REQUIRE(rec.transitions.size() == 6);
  const auto &t = rec.transitions;
  CHECK(t[0].from == Phase::filling);
  CHECK(t[0].to == Phase::isovolumetric_contraction);
  CHECK(t[1].from == Phase::isovolumetric_contraction);
  CHECK(t[1].to == Phase::filling);
  CHECK(t[0].beat == 0);
  CHECK(t[1].beat == 0);
  // p = p_at where the bump reaches 1 mmHg (analytic: p ignores V).
  CHECK(t[0].time == Approx(bump_crossing(1.0, 40.0)).margin(1e-6));
  CHECK(t[1].time == Approx(1000.0 - bump_crossing(1.0, 40.0)).margin(1e-6));
  CHECK(Units::kPa_to_mmHg(t[0].arterial_pressure) > 49.0);

  for (unsigned int i = 2; i < 6; ++i)
    {
      CHECK(t[i].beat == 1);
      CHECK(code(t[i].from) == static_cast<int>((i - 2) % 4));
      CHECK(code(t[i].to) == static_cast<int>((i - 1) % 4));
    }
  CHECK(t[2].time == Approx(800.0 + bump_crossing(1.0, 150.0)).margin(1e-6));
  CHECK(t[5].time ==
        Approx(800.0 + 1000.0 - bump_crossing(1.0, 150.0)).margin(1e-6));
  // The aortic valve opens where p crosses p_ar.
  CHECK(t[3].pressure == Approx(t[3].arterial_pressure).epsilon(1e-6));

  REQUIRE(rec.beats.size() == 2);
  const BeatSummary &weak = rec.beats[0];
  CHECK(weak.mitral_valve_closed);
  CHECK_FALSE(weak.aortic_valve_opened);
  CHECK(weak.stroke_volume == 0.0);
  CHECK(weak.end_systolic_volume == weak.end_diastolic_volume);
  CHECK(weak.phase_duration[code(Phase::ejection)] == 0.0);
  CHECK(weak.phase_duration[code(Phase::isovolumetric_contraction)] ==
        Approx(t[1].time - t[0].time).epsilon(1e-12));
  CHECK(rec.beats[1].aortic_valve_opened);
  CHECK(rec.beats[1].stroke_volume > 0);
  for (const auto &c : summary_columns(weak))
    if (c.name == "aortic_valve_opened" || c.name == "SV_mL")
      CHECK(c.value == 0.0);
}

TEST_CASE("The mitral valve does not chatter in diastasis: no closure before "
          "the contraction onset",
          "[circulation]")
{
  Parameters prm;
  prm.n_max_beats           = 2;
  prm.periodicity_tolerance = 0;
  // p oscillates around p_at by 0.5 mmHg all the time (crossing it every
  // 18.5 ms), plus a contraction from 300 ms. At 300 ms p > p_at, so the
  // mitral valve closes exactly at the onset.
  ScriptedVentricle ventricle([](const double t) {
    const double tau = std::fmod(t, 800.0);
    return Units::mmHg_to_kPa(10.0 + 0.5 * std::sin(2 * M_PI * tau / 37.0) +
                              bump(tau, 150.0));
  });
  REQUIRE(std::sin(2 * M_PI * 300.0 / 37.0) > 0);
  CardiacCycle cycle(prm, ventricle, Units::mL_to_mm3(100.0), onset);
  Recorder     rec;
  cycle.run(rec);

  REQUIRE(rec.transitions.size() == 8);
  for (unsigned int i = 0; i < 8; ++i)
    {
      const auto &tr = rec.transitions[i];
      CAPTURE(i, tr.time);
      CHECK(tr.beat == i / 4);
      CHECK(code(tr.from) == static_cast<int>(i % 4));
      CHECK(code(tr.to) == static_cast<int>((i + 1) % 4));
    }
  CHECK(rec.transitions[0].time == 300.0);
  CHECK(rec.transitions[4].time == 1100.0);
  // Filling throughout diastasis, although p crosses p_at many times.
  unsigned int n_diastolic = 0;
  for (const auto &r : rec.steps)
    if (std::fmod(r.time, 800.0) < 300.0 && r.time > 0)
      {
        ++n_diastolic;
        CHECK(r.phase == Phase::filling);
      }
  CHECK(n_diastolic > 20);
}
