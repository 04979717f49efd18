#include <deal.II/base/parameter_handler.h>

#include "base/units.h"
#include "circulation/parameters.h"
#include "circulation/windkessel.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace systole;
using namespace systole::Circulation;

namespace
{
  /// Parses a "Circulation" subsection with the given extra lines.
  Parameters
  parse(const std::string &lines)
  {
    dealii::ParameterHandler prm;
    Parameters::declare(prm);
    prm.parse_input_from_string("subsection Circulation\n" + lines + "end\n");
    return Parameters::parse(prm);
  }

  /// The message of the exception that parsing @p lines throws ("" if none).
  std::string
  parse_error(const std::string &lines)
  {
    try
      {
        parse(lines);
      }
    catch (const std::exception &e)
      {
        return e.what();
      }
    return "";
  }
} // namespace

TEST_CASE("Windkessel units convert from mmHg, mL and s to kPa, mm^3 and ms",
          "[circulation]")
{
  // 1 mmHg s/mL = 0.133322387415 kPa * 1000 ms / 1000 mm^3
  CHECK(resistance_from_mmHg_s_per_mL(1.0) ==
        Approx(0.133322387415).epsilon(1e-14));
  // 1.5 mL/mmHg = 1500 mm^3 / 0.133322387415 kPa
  CHECK(compliance_from_mL_per_mmHg(1.5) == Approx(11250.92).epsilon(1e-6));
  // R C is a time: 1.0 mmHg s/mL * 1.5 mL/mmHg = 1.5 s = 1500 ms
  CHECK(resistance_from_mmHg_s_per_mL(1.0) * compliance_from_mL_per_mmHg(1.5) ==
        Approx(1500.0).epsilon(1e-14));
  CHECK(flow_to_mL_per_s(250.0) == Approx(250.0));

  const Parameters p = parse("  set Peripheral resistance = 1.2\n"
                             "  set Compliance = 2\n"
                             "  set Atrial pressure = 7.5\n"
                             "  set Absolute volume tolerance = 0.01\n");
  CHECK(p.windkessel.model == Windkessel::Model::three_element);
  CHECK(p.windkessel.peripheral_resistance ==
        Approx(1.2 * 0.133322387415).epsilon(1e-14));
  CHECK(p.windkessel.compliance ==
        Approx(2000.0 / 0.133322387415).epsilon(1e-14));
  CHECK(p.atrial_pressure == Approx(7.5 * 0.133322387415).epsilon(1e-14));
  CHECK(p.initial_arterial_pressure ==
        Approx(80 * 0.133322387415).epsilon(1e-14));
  CHECK(p.absolute_volume_tolerance == Approx(10.0));
  CHECK(p.period == 800.0);

  SECTION("the defaults of the parameter file equal the struct defaults")
  {
    const Parameters parsed = parse("");
    const Parameters built;
    CHECK(parsed.windkessel.peripheral_resistance ==
          built.windkessel.peripheral_resistance);
    CHECK(parsed.windkessel.compliance == built.windkessel.compliance);
    CHECK(parsed.windkessel.characteristic_impedance ==
          built.windkessel.characteristic_impedance);
    CHECK(parsed.windkessel.aortic_valve_resistance ==
          built.windkessel.aortic_valve_resistance);
    CHECK(parsed.mitral_valve_resistance == built.mitral_valve_resistance);
    CHECK(parsed.atrial_pressure == built.atrial_pressure);
    CHECK(parsed.initial_arterial_pressure == built.initial_arterial_pressure);
    CHECK(parsed.n_max_beats == built.n_max_beats);
    CHECK(parsed.relative_tolerance == built.relative_tolerance);
    CHECK(parsed.absolute_volume_tolerance == built.absolute_volume_tolerance);
    CHECK(parsed.max_time_step == built.max_time_step);
    CHECK(parsed.initial_time_step == built.initial_time_step);
  }
}

TEST_CASE("Windkessel right-hand side matches hand-computed values",
          "[circulation]")
{
  Windkessel::Parameters w; // R_p 1.0, C 1.5, Z_c 0.05, R_av 0.0075
  w.venous_pressure = Units::mmHg_to_kPa(5.0);

  const double p    = Units::mmHg_to_kPa(100.0);
  const double p_ar = Units::mmHg_to_kPa(80.0);

  SECTION("3-element: the series resistance is Z_c")
  {
    const Windkessel wk(w);
    // (100 - 80) mmHg / 0.05 mmHg s/mL = 400 mL/s = 400 mm^3/ms
    const double q = wk.outflow(p, p_ar);
    CHECK(q == Approx(400.0).epsilon(1e-12));
    // C dp/dt = 400 - (80 - 5) / 1.0 = 325 mL/s -> 325 / 1.5 mmHg/s
    //         = 0.216667 mmHg/ms
    CHECK(Units::kPa_to_mmHg(wk.pressure_rate(p_ar, q)) ==
          Approx(325.0 / 1.5 / 1000.0).epsilon(1e-12));
    // Root pressure: 80 + 0.05 * 400 = 100 mmHg (= p: Z_c carries all of it)
    CHECK(Units::kPa_to_mmHg(wk.root_pressure(p_ar, q)) ==
          Approx(100.0).epsilon(1e-12));
  }

  SECTION("2-element: the series resistance is the valve's")
  {
    w.model = Windkessel::Model::two_element;
    const Windkessel wk(w);
    // 20 mmHg / 0.0075 mmHg s/mL = 2666.67 mL/s
    CHECK(wk.outflow(p, p_ar) == Approx(20.0 / 0.0075).epsilon(1e-12));
    CHECK(wk.series_resistance() ==
          Approx(resistance_from_mmHg_s_per_mL(0.0075)).epsilon(1e-14));
  }

  SECTION("constant inflow: matches the analytic exponential approach")
  {
    // C p' = Q - (p - p_ven) / R_p with Q constant:
    // p(t) = p_ven + Q R_p + (p(0) - p_ven - Q R_p) exp(-t / (R_p C))
    const Windkessel wk(w);
    const double     q   = 100.0; // mm^3/ms = 100 mL/s
    const double     R   = w.peripheral_resistance;
    const double     tau = R * w.compliance; // 1500 ms
    double           pa  = p_ar;
    const double     dt  = 1.0;
    for (int i = 0; i < 1000; ++i) // RK4 to t = 1000 ms
      {
        const double k1 = wk.pressure_rate(pa, q);
        const double k2 = wk.pressure_rate(pa + 0.5 * dt * k1, q);
        const double k3 = wk.pressure_rate(pa + 0.5 * dt * k2, q);
        const double k4 = wk.pressure_rate(pa + dt * k3, q);
        pa += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      }
    const double p_inf = w.venous_pressure + q * R;
    const double exact = p_inf + (p_ar - p_inf) * std::exp(-1000.0 / tau);
    CHECK(pa == Approx(exact).epsilon(1e-12));
  }
}

TEST_CASE("Invalid circulation parameters give errors naming the entry",
          "[circulation]")
{
  // Out of the pattern's range: deal.II names the entry.
  CHECK_THAT(parse_error("  set Compliance = -1.5\n"),
             Catch::Contains("Compliance"));
  CHECK_THAT(parse_error("  set Windkessel model = 4-element\n"),
             Catch::Contains("Windkessel model"));
  // Within the pattern but physically meaningless: our own messages.
  CHECK_THAT(parse_error("  set Compliance = 0\n"),
             Catch::Contains("Circulation / Compliance = 0 mL/mmHg") &&
               Catch::Contains("positive"));
  CHECK_THAT(parse_error("  set Peripheral resistance = 0\n"),
             Catch::Contains("Circulation / Peripheral resistance"));
  CHECK_THAT(parse_error("  set Characteristic impedance = 0\n"),
             Catch::Contains("Circulation / Characteristic impedance"));
  // Z_c is not used by the 2-element model, R_av is.
  CHECK(parse_error("  set Windkessel model = 2-element\n"
                    "  set Characteristic impedance = 0\n") == "");
  CHECK_THAT(parse_error("  set Windkessel model = 2-element\n"
                         "  set Aortic valve resistance = 0\n"),
             Catch::Contains("Circulation / Aortic valve resistance"));
  CHECK_THAT(parse_error("  set Venous pressure = -2\n"),
             Catch::Contains("Venous pressure"));
  CHECK_THAT(parse_error("  set Period = 0\n"),
             Catch::Contains("Circulation / Period"));
  CHECK_THAT(parse_error("  set Initial time step = 20\n"),
             Catch::Contains("Circulation / Initial time step"));
  CHECK_THAT(parse_error("  set Maximum time step = 1000\n"),
             Catch::Contains("Circulation / Maximum time step"));
  CHECK_THAT(parse_error("  set Relative tolerance = 0\n"),
             Catch::Contains("Circulation / Relative tolerance"));

  Parameters p;
  p.windkessel.compliance = -1;
  CHECK_THROWS_WITH(p.validate(), Catch::Contains("Circulation / Compliance"));
}
