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
  CHECK(p.windkessel.peripheral_resistance ==
        Approx(1.2 * 0.133322387415).epsilon(1e-14));
  CHECK(p.windkessel.compliance ==
        Approx(2000.0 / 0.133322387415).epsilon(1e-14));
  CHECK(p.atrial_pressure == Approx(7.5 * 0.133322387415).epsilon(1e-14));
  CHECK(p.initial_arterial_pressure ==
        Approx(80 * 0.133322387415).epsilon(1e-14));
  CHECK(p.steps.absolute_volume_tolerance == Approx(10.0));
  CHECK(p.steps.period == 800.0);

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
    CHECK(parsed.steps.n_max_beats == built.steps.n_max_beats);
    CHECK(parsed.steps.relative_tolerance == built.steps.relative_tolerance);
    CHECK(parsed.steps.absolute_volume_tolerance ==
          built.steps.absolute_volume_tolerance);
    CHECK(parsed.steps.max_step == built.steps.max_step);
    CHECK(parsed.steps.initial_step == built.steps.initial_step);
  }
}

TEST_CASE("Invalid circulation parameters give errors naming the entry",
          "[circulation]")
{
  // Out of the pattern's range: deal.II names the entry.
  CHECK_THAT(parse_error("  set Compliance = -1.5\n"),
             Catch::Contains("Compliance"));
  // The old heartbeat's entry is gone: Model = n-element Windkessel.
  CHECK_THAT(parse_error("  set Windkessel model = 3-element\n"),
             Catch::Contains("Windkessel model"));
  // Within the pattern but physically meaningless: our own messages.
  CHECK_THAT(parse_error("  set Compliance = 0\n"),
             Catch::Contains("Circulation / Compliance = 0 mL/mmHg") &&
               Catch::Contains("positive"));
  CHECK_THAT(parse_error("  set Peripheral resistance = 0\n"),
             Catch::Contains("Circulation / Peripheral resistance"));
  // Z_c = 0 is the 2-element model's (WindkesselModel checks it per model).
  CHECK(parse_error("  set Characteristic impedance = 0\n") == "");
  CHECK_THAT(parse_error("  set Aortic valve resistance = 0\n"),
             Catch::Contains("Circulation / Aortic valve resistance"));
  CHECK_THAT(parse_error("  set Event time tolerance = 0\n"),
             Catch::Contains("Circulation / Event time tolerance"));
  CHECK_THAT(parse_error("  set Absolute pressure tolerance = 0\n"),
             Catch::Contains("Circulation / Absolute pressure tolerance"));
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
