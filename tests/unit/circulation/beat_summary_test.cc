#include "base/units.h"
#include "circulation/beat_summary.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <set>

using namespace systole;
using namespace systole::Circulation;

namespace
{
  StepRecord
  record(const double t,
         const Phase  phase,
         const double V_mL,
         const double p_mmHg,
         const double aortic_mmHg)
  {
    StepRecord r;
    r.time            = t;
    r.phase           = phase;
    r.volume          = Units::mL_to_mm3(V_mL);
    r.pressure        = Units::mmHg_to_kPa(p_mmHg);
    r.aortic_pressure = Units::mmHg_to_kPa(aortic_mmHg);
    r.step_size       = t > 0 ? 1.0 : 0.0;
    return r;
  }

  Transition
  event(const double t, const Phase from, const Phase to, const StepRecord &r)
  {
    Transition e;
    e.time     = t;
    e.from     = from;
    e.to       = to;
    e.volume   = r.volume;
    e.pressure = r.pressure;
    return e;
  }
} // namespace

TEST_CASE("A rectangular PV loop gives the hand-computed beat summary",
          "[circulation]")
{
  // 120 mL at 10 mmHg -> 80 mmHg -> eject to 50 mL -> relax to 10 mmHg ->
  // fill to 120 mL.
  using P             = Phase;
  const StepRecord r0 = record(0, P::filling, 120, 10, 75);
  const StepRecord r1 = record(50, P::isovolumetric_contraction, 120, 80, 70);
  const StepRecord r2 = record(300, P::ejection, 50, 80, 120);
  const StepRecord r3 = record(400, P::isovolumetric_relaxation, 50, 10, 90);
  const StepRecord r4 = record(800, P::filling, 120, 10, 80);

  BeatRecorder recorder(0, 0.0, nullptr);
  recorder.add_step(r0);
  recorder.add_transition(
    event(0, P::filling, P::isovolumetric_contraction, r0));
  recorder.add_step(r1);
  recorder.add_transition(
    event(50, P::isovolumetric_contraction, P::ejection, r1));
  recorder.add_step(r2);
  recorder.add_transition(
    event(300, P::ejection, P::isovolumetric_relaxation, r2));
  recorder.add_step(r3);
  recorder.add_transition(
    event(400, P::isovolumetric_relaxation, P::filling, r3));
  recorder.add_step(r4);
  const BeatSummary s = recorder.finish(800.0, Units::mL_to_mm3(125.0), 123, 2);

  CHECK(s.mitral_valve_closed);
  CHECK(s.aortic_valve_opened);
  CHECK(s.n_steps == 4);
  CHECK(s.n_ventricle_calls == 123);
  CHECK(s.n_step_cuts == 2);

  std::map<std::string, double> c;
  std::set<std::string>         names;
  for (const auto &column : summary_columns(s))
    {
      CHECK(names.insert(column.name).second); // unique
      CHECK_FALSE(column.unit.empty());
      c[column.name] = column.value;
    }
  CHECK(c["EDV_mL"] == Approx(120.0));
  CHECK(c["ESV_mL"] == Approx(50.0));
  CHECK(c["SV_mL"] == Approx(70.0));
  CHECK(c["EF"] == Approx(100.0 * 70.0 / 120.0));
  CHECK(c["EDP_mmHg"] == Approx(10.0));
  CHECK(c["peak_pressure_mmHg"] == Approx(80.0));
  CHECK(c["stroke_work_mmHg_mL"] == Approx(70.0 * 70.0));
  CHECK(c["dpdt_max"] == Approx(70.0 / 0.050)); // mmHg/s
  CHECK(c["dpdt_min"] == Approx(-70.0 / 0.100));
  CHECK(c["filling_duration"] == Approx(400.0));
  CHECK(c["isovolumetric_contraction_duration"] == Approx(50.0));
  CHECK(c["ejection_duration"] == Approx(250.0));
  CHECK(c["isovolumetric_relaxation_duration"] == Approx(100.0));
  CHECK(c["aortic_systolic_mmHg"] == Approx(120.0));
  CHECK(c["aortic_diastolic_mmHg"] == Approx(70.0));
  CHECK(c["aortic_valve_opened"] == 1.0);
  CHECK(c["periodicity"] == Approx(5.0 / 125.0));
  CHECK(c["steps"] == 4.0);

  SECTION("the first beat has no periodicity; a beat without events no EDV")
  {
    StepRecord anchor = r4;
    anchor.time       = 2400;
    anchor.beat       = 2;
    BeatRecorder empty(3, 2400.0, &anchor);
    StepRecord   later = r4;
    later.time         = 3200;
    later.beat         = 3;
    empty.add_step(later);
    const BeatSummary e =
      empty.finish(3200.0, std::numeric_limits<double>::quiet_NaN(), 0, 0);
    CHECK(e.beat == 3);
    CHECK(e.n_steps == 1);
    CHECK_FALSE(e.mitral_valve_closed);
    CHECK(std::isnan(e.end_diastolic_volume));
    CHECK(std::isnan(e.periodicity));
    CHECK(e.phase_duration[code(Phase::filling)] == Approx(800.0));
  }
}
