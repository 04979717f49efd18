#include "base/units.h"
#include "circulation/closed_loop.h"
#include "circulation/model_summary.h"
#include "circulation/windkessel_model.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace systole;
using namespace systole::Circulation;

namespace
{
  using Vector = dealii::Vector<double>;

  /// A 3-element Windkessel behind an external LV: states lv_volume and
  /// arterial_pressure, valves 0 mitral and 1 aortic.
  WindkesselModel
  external_lv_windkessel()
  {
    WindkesselModel::Parameters p;
    p.n_elements          = 3;
    p.left_ventricle_kind = CavityKind::external;
    return WindkesselModel(p);
  }

  /// Feeds @p recorder one sample of the Windkessel model: LV volume and
  /// pressure, arterial pressure (mL, mmHg).
  void
  add_sample(const Model       &model,
             ModelBeatRecorder &recorder,
             const double       t,
             const double       V_mL,
             const double       p_mmHg,
             const double       arterial_mmHg)
  {
    Vector y(model.n_states()), p(1), outputs;
    y[0] = Units::mL_to_mm3(V_mL);
    y[1] = Units::mmHg_to_kPa(arterial_mmHg);
    p[0] = Units::mmHg_to_kPa(p_mmHg);
    model.evaluate_outputs({t, y, p}, outputs);
    recorder.add(t, y, p, outputs);
  }

  /// The summary row by name; checks that the names are unique and that
  /// every column has a unit.
  std::map<std::string, double>
  by_name(const std::vector<SummaryColumn> &row)
  {
    std::map<std::string, double> values;
    for (const auto &column : row)
      {
        CHECK(values.emplace(column.name, column.value).second);
        CHECK_FALSE(column.unit.empty());
      }
    return values;
  }

  std::vector<std::string>
  names(const std::vector<SummaryColumn> &row)
  {
    std::vector<std::string> n;
    for (const auto &column : row)
      n.push_back(column.name);
    return n;
  }

  constexpr unsigned int mitral = 0, aortic = 1;
} // namespace

TEST_CASE("A rectangular PV loop gives the hand-computed model beat summary",
          "[circulation]")
{
  // 120 mL at 10 mmHg -> 80 mmHg -> eject to 50 mL -> relax to 10 mmHg ->
  // fill to 120 mL; the valve events at the corners, each with the sample
  // there, in the order the circulation run adds them (sample, then event).
  const WindkesselModel model = external_lv_windkessel();
  CHECK_FALSE(model.cavities_in_series());
  ModelBeatRecorder recorder(model, {true, false}); // filling at t = 0
  // The state at each corner: t [ms], V [mL], p [mmHg], p_ar [mmHg].
  struct Corner
  {
    double t, V, p, p_ar;
  };
  const Corner c0{0, 120, 10, 75}, c1{50, 120, 80, 70}, c2{300, 50, 80, 120},
    c3{400, 50, 10, 90}, c4{800, 120, 10, 80};
  const auto sample_and_event =
    [&](const Corner &c, const unsigned int valve, const bool opens) {
      add_sample(model, recorder, c.t, c.V, c.p, c.p_ar);
      Vector y(model.n_states()), p(1);
      y[0] = Units::mL_to_mm3(c.V);
      y[1] = Units::mmHg_to_kPa(c.p_ar);
      p[0] = Units::mmHg_to_kPa(c.p);
      recorder.add_valve_event(valve, opens, c.t, y, p);
    };

  recorder.start(0, 0.0);
  sample_and_event(c0, mitral, false);
  // An output row at the time of the event sample: a zero-length interval
  // that dp/dt must skip.
  add_sample(model, recorder, c1.t, c1.V, c1.p, c1.p_ar);
  sample_and_event(c1, aortic, true);
  sample_and_event(c2, aortic, false);
  sample_and_event(c3, mitral, true);
  add_sample(model, recorder, c4.t, c4.V, c4.p, c4.p_ar);
  const auto row = recorder.finish(800.0);
  auto       c   = by_name(row);

  CHECK(c["beat"] == 0.0);
  CHECK(c["samples"] == 6.0);
  CHECK(c["lv_EDV_mL"] == Approx(120.0));
  CHECK(c["lv_ESV_mL"] == Approx(50.0));
  CHECK(c["lv_SV_mL"] == Approx(70.0));
  CHECK(c["lv_EF"] == Approx(100.0 * 70.0 / 120.0));
  CHECK(c["lv_EDP_mmHg"] == Approx(10.0));
  CHECK(c["lv_peak_pressure_mmHg"] == Approx(80.0));
  CHECK(c["lv_stroke_work_mmHg_mL"] == Approx(70.0 * 70.0));
  CHECK(c["lv_dpdt_max"] == Approx(70.0 / 0.050)); // mmHg/s
  CHECK(c["lv_dpdt_min"] == Approx(-70.0 / 0.100));
  CHECK(c["lv_filling_duration"] == Approx(400.0));
  CHECK(c["lv_isovolumetric_contraction_duration"] == Approx(50.0));
  CHECK(c["lv_ejection_duration"] == Approx(250.0));
  CHECK(c["lv_isovolumetric_relaxation_duration"] == Approx(100.0));
  // The arterial pressure (a state) and the LV pressure (an output).
  CHECK(c["arterial_pressure_max_mmHg"] == Approx(120.0));
  CHECK(c["arterial_pressure_min_mmHg"] == Approx(70.0));
  CHECK(c["arterial_pressure_mean_mmHg"] ==
        Approx((0.5 * (75 + 70) * 50 + 0.5 * (70 + 120) * 250 +
                0.5 * (120 + 90) * 100 + 0.5 * (90 + 80) * 400) /
               800.0));
  CHECK(c["lv_pressure_max_mmHg"] == Approx(80.0));
  CHECK(c["lv_pressure_min_mmHg"] == Approx(10.0));
  // V + C p_ar, C = 1.5 mL/mmHg; the largest change is at 400 ms.
  CHECK(c["total_blood_volume_mL"] == Approx(120.0 + 1.5 * 80.0));
  CHECK(c["total_blood_volume_drift"] ==
        Approx(((120.0 + 1.5 * 75.0) - (50.0 + 1.5 * 90.0)) /
               (120.0 + 1.5 * 75.0)));
  CHECK(std::isnan(c["periodicity"]));
  CHECK(std::isnan(c["EDV_change"]));
  // One cavity: no stroke volumes to compare.
  CHECK(std::isnan(c["SV_difference"]));
  CHECK(std::isnan(recorder.periodicity()));

  SECTION("a beat without events stays in the phase the last one ended in")
  {
    recorder.start(1, 800.0);
    add_sample(model, recorder, 1600.0, 120, 10, 80);
    const auto next = recorder.finish(1600.0);
    CHECK(names(next) == names(row)); // the same columns every beat
    auto e = by_name(next);
    CHECK(e["beat"] == 1.0);
    CHECK(e["start_time"] == 800.0);
    CHECK(e["samples"] == 2.0); // the end of beat 0 and t = 1600 ms
    CHECK(e["lv_filling_duration"] == Approx(800.0));
    CHECK(e["lv_isovolumetric_contraction_duration"] == 0.0);
    CHECK(e["lv_ejection_duration"] == 0.0);
    CHECK(e["lv_isovolumetric_relaxation_duration"] == 0.0);
    // Filling throughout: no contraction to take dp/dt max from.
    CHECK(std::isnan(e["lv_dpdt_max"]));
    CHECK(e["lv_dpdt_min"] == Approx(0.0).margin(1e-12));
    // No closure: EDV is the largest volume of the beat.
    CHECK(e["lv_EDV_mL"] == Approx(120.0));
    CHECK(e["periodicity"] == Approx(0.0).margin(1e-15));
    CHECK(e["EDV_change"] == Approx(0.0).margin(1e-15));
    CHECK(std::isnan(e["SV_difference"]));
  }

  SECTION("dp/dt max is taken in contraction, dp/dt min in relaxation and "
          "filling: a jump right after the inlet valve closes is neither")
  {
    // The supports re-referred at the closure drop the pressure 1.5 mmHg
    // in 0.1 ms (-15000 mmHg/s), then it rises to 80 mmHg at 850 ms.
    recorder.start(1, 800.0);
    sample_and_event({800, 120, 10, 80}, mitral, false);
    add_sample(model, recorder, 800.1, 120, 8.5, 80);
    sample_and_event({850, 120, 80, 78}, aortic, true);
    auto e = by_name(recorder.finish(850.0));
    CHECK(e["lv_dpdt_max"] == Approx((80.0 - 8.5) / 0.0499));
    // Only zero-length intervals in filling (the end of beat 0 and the
    // closure's sample, both at 800 ms).
    CHECK(std::isnan(e["lv_dpdt_min"]));
  }
}

TEST_CASE("The periodicity of a closed loop with both ventricles in 3D also "
          "asks for equal stroke volumes",
          "[circulation]")
{
  // Three beats of the closed loop with hand-made volumes (no valve events:
  // EDV and ESV are the largest and smallest volume of the beat), LV and RV
  // [mL] at t = 0, 400, 800 ms, ...:
  // beat 0: (120, 120) -> (50, 57) -> (120, 120): SVs 70 and 63;
  // beat 1: the same again: the EDVs have not changed, the SVs still differ;
  // beat 2: -> (50, 50) -> (123, 120): SVs 73 and 70, LV EDV + 2.5 %.
  const bool             rv_3d = GENERATE(true, false);
  ClosedLoop::Parameters parameters;
  parameters.left_ventricle_kind = CavityKind::external;
  if (rv_3d)
    parameters.right_ventricle_kind = CavityKind::external;
  const ClosedLoop model(parameters);
  REQUIRE(model.cavities_in_series());
  INFO((rv_3d ? "both ventricles 3D" : "the LV 3D, the RV 0D"));

  ModelBeatRecorder recorder(model, {false, false, false, false});
  Vector            y, p(2), outputs;
  model.initial_state(y);
  const auto sample = [&](const double t, const double lv, const double rv) {
    y[model.cavities()[0].volume_state] = Units::mL_to_mm3(lv);
    y[model.cavities()[1].volume_state] = Units::mL_to_mm3(rv);
    model.evaluate_outputs({t, y, p}, outputs);
    recorder.add(t, y, p, outputs);
  };
  const std::vector<std::array<double, 2>>   minima = {{{50, 57}},
                                                       {{50, 57}},
                                                       {{50, 50}}};
  const std::vector<std::array<double, 2>>   maxima = {{{120, 120}},
                                                       {{120, 120}},
                                                       {{123, 120}}};
  std::vector<std::map<std::string, double>> rows;
  sample(0.0, 120, 120);
  for (unsigned int beat = 0; beat < 3; ++beat)
    {
      recorder.start(beat, 800.0 * beat);
      sample(800.0 * beat + 400, minima[beat][0], minima[beat][1]);
      sample(800.0 * (beat + 1), maxima[beat][0], maxima[beat][1]);
      rows.push_back(by_name(recorder.finish(800.0 * (beat + 1))));
      if (beat > 0)
        CHECK(recorder.periodicity() == Approx(rows.back()["periodicity"]));
    }

  // (max - min) / mean of the two stroke volumes, 3D or not.
  CHECK(rows[0]["SV_difference"] == Approx(7.0 / 66.5));
  CHECK(rows[1]["SV_difference"] == Approx(7.0 / 66.5));
  CHECK(rows[2]["SV_difference"] == Approx(3.0 / 71.5));
  CHECK(rows[1]["EDV_change"] == Approx(0.0).margin(1e-15));
  CHECK(rows[2]["EDV_change"] == Approx(3.0 / 120.0));
  CHECK(std::isnan(rows[0]["periodicity"]));
  if (rv_3d)
    {
      // The EDVs alone would call beat 1 periodic.
      CHECK(rows[1]["periodicity"] == Approx(7.0 / 66.5));
      CHECK(rows[2]["periodicity"] == Approx(3.0 / 71.5));
    }
  else
    {
      // One 3D ventricle: the EDVs only, as before.
      CHECK(rows[1]["periodicity"] == Approx(0.0).margin(1e-15));
      CHECK(rows[2]["periodicity"] == Approx(3.0 / 120.0));
    }
}

TEST_CASE("Each cavity of a model gets its own phase durations",
          "[circulation]")
{
  ClosedLoop::Parameters parameters;
  parameters.left_ventricle_kind = parameters.right_ventricle_kind =
    CavityKind::external;
  const ClosedLoop model(parameters);
  REQUIRE(model.n_cavities() == 2);
  const unsigned int lv = 0, rv = 1;
  // Valves: mitral, aortic, tricuspid, pulmonary. The LV ejects from the
  // start; the RV fills.
  ModelBeatRecorder recorder(model, {false, true, true, false});

  Vector y, p(2), outputs;
  model.initial_state(y);
  const auto sample = [&](const double t) {
    model.evaluate_outputs({t, y, p}, outputs);
    recorder.add(t, y, p, outputs);
  };
  const auto event =
    [&](const unsigned int valve, const bool opens, const double t) {
      sample(t);
      recorder.add_valve_event(valve, opens, t, y, p);
    };

  recorder.start(0, 0.0);
  sample(0.0);
  event(model.cavities()[lv].outlet_valve, false, 100.0); // aortic closes
  event(model.cavities()[rv].inlet_valve, false, 300.0);  // tricuspid closes
  event(model.cavities()[lv].inlet_valve, true, 450.0);   // mitral opens
  sample(1000.0);
  auto c = by_name(recorder.finish(1000.0));

  CHECK(c["lv_ejection_duration"] == Approx(100.0));
  CHECK(c["lv_isovolumetric_relaxation_duration"] == Approx(350.0));
  CHECK(c["lv_filling_duration"] == Approx(550.0));
  CHECK(c["lv_isovolumetric_contraction_duration"] == 0.0);
  CHECK(c["rv_filling_duration"] == Approx(300.0));
  CHECK(c["rv_isovolumetric_contraction_duration"] == Approx(700.0));
  CHECK(c["rv_ejection_duration"] == 0.0);
  CHECK(c["rv_isovolumetric_relaxation_duration"] == 0.0);
  // Constant pressures: no dp/dt.
  CHECK(c["lv_dpdt_max"] == Approx(0.0).margin(1e-12));
  CHECK(c["rv_dpdt_min"] == Approx(0.0).margin(1e-12));
}
