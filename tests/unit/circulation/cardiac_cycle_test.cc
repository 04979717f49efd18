#include "base/errors.h"
#include "base/units.h"
#include "circulation/cardiac_cycle.h"
#include "circulation/elastance_ventricle.h"

#include "cycle_helpers.h"
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

using namespace circulation_test;

namespace
{
  struct ReferenceEvent
  {
    double time;
    Phase  from, to;
    double volume;
  };

  /// An independent solution of the same cycle: classical RK4 with a fixed
  /// step dt [ms], valve events where the switching function changes sign
  /// between two steps, located by linear interpolation (the state is
  /// interpolated linearly to the event and the integration restarts
  /// there). Written from the model equations, sharing no code with
  /// CardiacCycle (only the ventricle model).
  std::vector<ReferenceEvent>
  reference_events(const Parameters  &prm,
                   Ventricle         &ventricle,
                   const double       V0,
                   const double       onset_in_beat,
                   const unsigned int n_beats,
                   const double       dt)
  {
    const double R_s   = prm.windkessel.characteristic_impedance;
    const double R_p   = prm.windkessel.peripheral_resistance;
    const double C     = prm.windkessel.compliance;
    const double p_ven = prm.windkessel.venous_pressure;
    const double p_at  = prm.atrial_pressure;
    const double R_mv  = prm.mitral_valve_resistance;
    const double T     = prm.period;

    std::vector<ReferenceEvent> events;
    double                      V = V0, pa = prm.initial_arterial_pressure;
    Phase                       phase = Phase::filling;
    bool                        armed = false;

    const auto f = [&](const double t,
                       const double v,
                       const double a,
                       double      &dv,
                       double      &da) {
      const double p    = ventricle.pressure(t, v);
      const double q_mv = phase == Phase::filling ? (p_at - p) / R_mv : 0.0;
      const double q_ao = phase == Phase::ejection ? (p - a) / R_s : 0.0;
      dv                = q_mv - q_ao;
      da                = (q_ao - (a - p_ven) / R_p) / C;
    };
    // Switching functions of the phase: (value, direction, target).
    struct Switch
    {
      double g;
      int    direction;
      Phase  to;
    };
    const auto switches = [&](const double t, const double v, const double a) {
      const double        p = ventricle.pressure(t, v);
      std::vector<Switch> s;
      switch (phase)
        {
          case Phase::filling:
            if (armed)
              s.push_back({p - p_at, +1, Phase::isovolumetric_contraction});
            break;
          case Phase::isovolumetric_contraction:
            s.push_back({p - a, +1, Phase::ejection});
            s.push_back({p - p_at, -1, Phase::filling});
            break;
          case Phase::ejection:
            s.push_back({p - a, -1, Phase::isovolumetric_relaxation});
            break;
          case Phase::isovolumetric_relaxation:
            s.push_back({p - p_at, -1, Phase::filling});
            break;
        }
      return s;
    };
    const auto change_phase = [&](const double t, const Phase to) {
      events.push_back({t, phase, to, V});
      if (phase == Phase::filling)
        armed = false;
      phase = to;
    };

    for (unsigned int k = 0; k < n_beats; ++k)
      {
        double       t            = k * T;
        const double t_onset      = k * T + onset_in_beat;
        const double t_end        = (k + 1) * T;
        bool         onset_passed = false;
        while (t < t_end - 1e-9)
          {
            if (!onset_passed && t >= t_onset - 1e-9)
              {
                onset_passed = true;
                armed        = true;
                if (phase == Phase::filling && ventricle.pressure(t, V) >= p_at)
                  change_phase(t, Phase::isovolumetric_contraction);
              }
            const double h = std::min(dt, (onset_passed ? t_end : t_onset) - t);
            double       k1v, k1a, k2v, k2a, k3v, k3a, k4v, k4a;
            f(t, V, pa, k1v, k1a);
            f(t + h / 2, V + h / 2 * k1v, pa + h / 2 * k1a, k2v, k2a);
            f(t + h / 2, V + h / 2 * k2v, pa + h / 2 * k2a, k3v, k3a);
            f(t + h, V + h * k3v, pa + h * k3a, k4v, k4a);
            const double V1  = V + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
            const double pa1 = pa + h / 6 * (k1a + 2 * k2a + 2 * k3a + k4a);

            const auto before = switches(t, V, pa);
            const auto after  = switches(t + h, V1, pa1);
            double     theta  = 2;
            Phase      to     = phase;
            for (unsigned int i = 0; i < before.size(); ++i)
              {
                const double g0 = before[i].g * before[i].direction;
                const double g1 = after[i].g * before[i].direction;
                if (g0 < 0 && g1 >= 0 && g0 / (g0 - g1) < theta)
                  {
                    theta = g0 / (g0 - g1);
                    to    = before[i].to;
                  }
              }
            if (theta <= 1)
              {
                t += theta * h;
                V += theta * (V1 - V);
                pa += theta * (pa1 - pa);
                change_phase(t, to);
                const double p = ventricle.pressure(t, V);
                if (phase == Phase::isovolumetric_contraction && p > pa)
                  change_phase(t, Phase::ejection);
              }
            else
              {
                t += h;
                V  = V1;
                pa = pa1;
              }
          }
      }
    return events;
  }
} // namespace

TEST_CASE("The elastance surrogate runs through four phases per beat, at "
          "the event times of an independent fine-step solution",
          "[circulation]")
{
  Parameters prm;
  prm.n_max_beats           = 3;
  prm.periodicity_tolerance = 0; // run all beats
  const auto         sp     = surrogate_parameters();
  ElastanceVentricle ventricle(sp);
  CardiacCycle       cycle(prm, ventricle, sp.unloaded_volume, onset);
  Recorder           rec;
  const auto         stats = cycle.run(rec);

  REQUIRE(stats.n_beats == 3);
  CHECK_FALSE(stats.periodic);
  CHECK(stats.end_time == 2400.0);
  CHECK(stats.n_step_cuts == 0);

  // Phase order: 0 -> 1 -> 2 -> 3 -> 0 in every beat.
  REQUIRE(rec.transitions.size() == 12);
  for (unsigned int i = 0; i < rec.transitions.size(); ++i)
    {
      const auto &tr = rec.transitions[i];
      CAPTURE(i, tr.time);
      CHECK(tr.beat == i / 4);
      CHECK(code(tr.from) == static_cast<int>(i % 4));
      CHECK(code(tr.to) == static_cast<int>((i + 1) % 4));
    }

  // Event times against the reference (RK4, dt = 0.001 ms).
  ElastanceVentricle reference_ventricle(sp);
  const auto         reference = reference_events(prm,
                                          reference_ventricle,
                                          sp.unloaded_volume,
                                          onset,
                                          3,
                                          1e-3);
  REQUIRE(reference.size() == rec.transitions.size());
  double max_difference = 0;
  for (unsigned int i = 0; i < reference.size(); ++i)
    {
      const auto &tr = rec.transitions[i];
      CAPTURE(i, tr.time, reference[i].time);
      CHECK(tr.from == reference[i].from);
      CHECK(tr.to == reference[i].to);
      CHECK(std::abs(tr.time - reference[i].time) < 0.5);
      max_difference =
        std::max(max_difference, std::abs(tr.time - reference[i].time));
      CHECK(tr.volume ==
            Approx(reference[i].volume).margin(Units::mL_to_mm3(0.05)));
    }
  CAPTURE(max_difference);
  CHECK(max_difference < 0.3);

  // Steps never straddle a beat boundary; time increases.
  for (unsigned int i = 1; i < rec.steps.size(); ++i)
    {
      const auto &r = rec.steps[i];
      const auto &q = rec.steps[i - 1];
      REQUIRE(r.time > q.time);
      CHECK(r.step_size == Approx(r.time - q.time).epsilon(1e-12));
      CHECK(std::floor(q.time / prm.period + 1e-12) ==
            std::floor((r.time - 1e-9) / prm.period));
      CHECK(r.beat == static_cast<unsigned int>((r.time - 1e-9) / 800.0));
    }

  // V is exactly constant over steps in the isovolumetric phases.
  unsigned int n_isovolumetric = 0;
  for (unsigned int i = 1; i < rec.steps.size(); ++i)
    {
      const auto &r = rec.steps[i];
      if (r.phase == Phase::isovolumetric_contraction ||
          r.phase == Phase::isovolumetric_relaxation)
        {
          ++n_isovolumetric;
          CAPTURE(r.time);
          CHECK(std::abs(r.volume - rec.steps[i - 1].volume) <=
                1e-12 * r.volume);
          CHECK(r.flow == 0.0);
        }
    }
  CHECK(n_isovolumetric > 10);

  // Conservation: over each ejection the integrated outflow equals the
  // volume change; over the whole run inflow - outflow = V(end) - V(0).
  for (unsigned int i = 0; i < rec.transitions.size(); ++i)
    if (rec.transitions[i].to == Phase::ejection)
      {
        const StepRecord &open   = rec.record_at(rec.transitions[i]);
        const StepRecord &closed = rec.record_at(rec.transitions[i + 1]);
        const double      outflow =
          closed.cumulative_aortic_outflow - open.cumulative_aortic_outflow;
        CHECK(outflow == Approx(open.volume - closed.volume).epsilon(1e-6));
        CHECK(closed.cumulative_mitral_inflow == open.cumulative_mitral_inflow);
      }
  const StepRecord &last = rec.steps.back();
  CHECK(last.cumulative_mitral_inflow - last.cumulative_aortic_outflow ==
        Approx(last.volume - sp.unloaded_volume).epsilon(1e-10));

  // Plausible haemodynamics.
  REQUIRE(rec.beats.size() == 3);
  for (const auto &b : rec.beats)
    {
      CAPTURE(b.beat,
              Units::mm3_to_mL(b.end_diastolic_volume),
              Units::mm3_to_mL(b.end_systolic_volume),
              b.ejection_fraction,
              Units::kPa_to_mmHg(b.peak_pressure),
              b.n_steps,
              b.n_ventricle_calls);
      CHECK(b.mitral_valve_closed);
      CHECK(b.aortic_valve_opened);
      CHECK(b.ejection_fraction > 0.4);
      CHECK(b.ejection_fraction < 0.7);
      CHECK(Units::mm3_to_mL(b.end_diastolic_volume) > 100);
      CHECK(Units::mm3_to_mL(b.end_diastolic_volume) < 140);
      CHECK(Units::kPa_to_mmHg(b.peak_pressure) > 90);
      CHECK(Units::kPa_to_mmHg(b.peak_pressure) < 140);
      CHECK(Units::kPa_to_mmHg(b.end_diastolic_pressure) ==
            Approx(10.0).epsilon(1e-6));
      CHECK(b.stroke_volume > 0);
      CHECK(Units::kPa_to_mmHg(b.aortic_systolic_pressure) >
            Units::kPa_to_mmHg(b.aortic_diastolic_pressure) + 20);
      double total = 0;
      for (const double d : b.phase_duration)
        total += d;
      CHECK(total == Approx(800.0).epsilon(1e-12));
      // The loop area is about the mean ejection pressure times SV.
      CHECK(b.stroke_work > 0.5 * b.stroke_volume * b.peak_pressure);
      CHECK(b.stroke_work < b.stroke_volume * b.peak_pressure);
      CHECK(b.dpdt_max > 0);
      CHECK(b.dpdt_min < 0);
      // The cost that matters for a 3D ventricle.
      CHECK(b.n_steps < 200);
      CHECK(b.n_ventricle_calls < 4 * b.n_steps + 60);
    }
  CHECK(std::isnan(rec.beats[0].periodicity));
  CHECK(rec.beats[2].periodicity < 1e-3);
  CHECK(stats.n_ventricle_calls == ventricle.n_calls());
}

TEST_CASE("The run stops when the end-diastolic volume is periodic",
          "[circulation]")
{
  Parameters prm;
  prm.n_max_beats           = 10;
  prm.periodicity_tolerance = 0.01;
  const auto         sp     = surrogate_parameters();
  ElastanceVentricle ventricle(sp);
  CardiacCycle       cycle(prm, ventricle, sp.unloaded_volume, onset);
  Recorder           rec;
  const auto         stats = cycle.run(rec);

  CHECK(stats.periodic);
  CHECK(stats.n_beats == rec.beats.size());
  REQUIRE(stats.n_beats >= 2);
  CHECK(stats.n_beats < 10);
  CHECK(stats.end_time == Approx(800.0 * stats.n_beats));
  CHECK(rec.beats.back().periodicity < 0.01);
  for (unsigned int k = 1; k + 1 < rec.beats.size(); ++k)
    CHECK(rec.beats[k].periodicity >= 0.01);

  SECTION("and runs the maximum number of beats otherwise")
  {
    prm.n_max_beats           = 2;
    prm.periodicity_tolerance = 1e-9;
    ElastanceVentricle v(sp);
    CardiacCycle       c(prm, v, sp.unloaded_volume, onset);
    Recorder           r;
    const auto         s = c.run(r);
    CHECK_FALSE(s.periodic);
    CHECK(s.n_beats == 2);
  }
}

TEST_CASE("The 2-element Windkessel gives a plausible cycle too",
          "[circulation]")
{
  Parameters prm;
  prm.windkessel.model      = Windkessel::Model::two_element;
  prm.n_max_beats           = 3;
  prm.periodicity_tolerance = 0;
  const auto         sp     = surrogate_parameters();
  ElastanceVentricle ventricle(sp);
  CardiacCycle       cycle(prm, ventricle, sp.unloaded_volume, onset);
  Recorder           rec;
  cycle.run(rec);
  REQUIRE(rec.transitions.size() == 12);
  for (const auto &b : rec.beats)
    {
      CHECK(b.aortic_valve_opened);
      CHECK(b.ejection_fraction > 0.4);
      CHECK(b.ejection_fraction < 0.75);
    }
}

namespace
{
  /// Wraps a ventricle and throws from chosen calls.
  class FailingVentricle : public Ventricle
  {
  public:
    FailingVentricle(Ventricle &inner, std::function<bool(double)> fails)
      : inner(inner)
      , fails(std::move(fails))
    {}

    double
    pressure(const double t, const double volume) override
    {
      if (fails(t))
        throw ExcNewtonDidNotConverge("test", 12, 1e-3);
      return inner.pressure(t, volume);
    }

  private:
    Ventricle                  &inner;
    std::function<bool(double)> fails;
  };
} // namespace

TEST_CASE("A recoverable ventricle failure cuts the step; repeated failures "
          "stop the run with the time",
          "[circulation]")
{
  Parameters prm;
  prm.n_max_beats           = 2;
  prm.periodicity_tolerance = 0;
  const auto sp             = surrogate_parameters();

  Recorder reference;
  {
    ElastanceVentricle v(sp);
    CardiacCycle(prm, v, sp.unloaded_volume, onset).run(reference);
  }

  SECTION("one failure during ejection")
  {
    ElastanceVentricle v(sp);
    bool               failed = false;
    FailingVentricle   failing(v, [&](const double t) {
      if (!failed && t > 450.0)
        return failed = true;
      return false;
    });
    Recorder           rec;
    const auto         stats =
      CardiacCycle(prm, failing, sp.unloaded_volume, onset).run(rec);
    CHECK(failed);
    CHECK(stats.n_step_cuts == 1);
    CHECK(rec.beats[0].n_step_cuts == 1);
    REQUIRE(rec.transitions.size() == reference.transitions.size());
    for (unsigned int i = 0; i < rec.transitions.size(); ++i)
      CHECK(rec.transitions[i].time ==
            Approx(reference.transitions[i].time).margin(0.05));
    CHECK(rec.beats[1].end_diastolic_volume ==
          Approx(reference.beats[1].end_diastolic_volume).epsilon(1e-3));
  }

  SECTION("failures at every call from t = 1000 ms")
  {
    ElastanceVentricle v(sp);
    FailingVentricle   failing(v, [](const double t) { return t > 1000.0; });
    Recorder           rec;
    CardiacCycle       cycle(prm, failing, sp.unloaded_volume, onset);
    CHECK_THROWS_WITH(cycle.run(rec),
                      Catch::Contains("ventricle failed 11 times") &&
                        Catch::Contains("at t = ") &&
                        Catch::Contains("Newton's method did not converge"));
    CHECK(rec.steps.back().time <= 1000.0);
  }

  SECTION("other exceptions propagate unchanged")
  {
    ElastanceVentricle v(sp);
    struct Throwing : Ventricle
    {
      Ventricle &inner;
      explicit Throwing(Ventricle &inner)
        : inner(inner)
      {}
      double
      pressure(const double t, const double volume) override
      {
        if (t > 500.0)
          throw std::runtime_error("mesh exploded");
        return inner.pressure(t, volume);
      }
    } throwing(v);
    Recorder     rec;
    CardiacCycle cycle(prm, throwing, sp.unloaded_volume, onset);
    CHECK_THROWS_WITH(cycle.run(rec), "mesh exploded");
  }
}

TEST_CASE("The cardiac cycle checks its arguments", "[circulation]")
{
  Parameters         prm;
  const auto         sp = surrogate_parameters();
  ElastanceVentricle ventricle(sp);
  CHECK_THROWS_WITH(CardiacCycle(prm, ventricle, -1.0, onset),
                    Catch::Contains("initial volume"));
  CHECK_THROWS_WITH(CardiacCycle(prm, ventricle, 1e4, 900.0),
                    Catch::Contains("contraction onset"));
  prm.windkessel.compliance = 0;
  CHECK_THROWS_WITH(CardiacCycle(prm, ventricle, 1e4, onset),
                    Catch::Contains("Circulation / Compliance"));
}
