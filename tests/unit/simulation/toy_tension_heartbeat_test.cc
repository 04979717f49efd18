// A tension model added through its table alone (Materials::tension_models(),
// what one table line in tension_factory.cc does) drives a coarse heartbeat:
// the heartbeat knows no concrete tension model. The toy is a prescribed
// sin^2 twitch started at each point's activation time; a beat must then
// close and open both valves and eject.

#include "materials/tension_factory.h"
#include "simulation/simulation.h"
#include "support/toy_tension.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

using namespace systole;

namespace
{
  /// T = T_max sin^2(pi s / duration) for 0 < s < duration, s the time
  /// since activation; 0 otherwise. T_max = 100 kPa, duration 350 ms.
  double
  twitch(const Materials::TensionInput &in)
  {
    const double T_max = 100, duration = 350; // [kPa], [ms]
    const double s = in.time - in.activation_time;
    return (std::isfinite(s) && s > 0 && s < duration)
             ? T_max * std::pow(std::sin(M_PI * s / duration), 2)
             : 0.0;
  }

  const char *parameter_file = R"(set Problem = heartbeat
subsection Geometry
  set Type = ellipsoid
  subsection Ellipsoid
    set Endocardium short radius = 23
    set Endocardium long radius  = 84
    set Epicardium short radius  = 33
    set Epicardium long radius   = 92
  end
end
subsection Discretization
  set Polynomial degree = 2
end
subsection Fibres
  set Generator = analytic
end
subsection Material
  set Passive law = Holzapfel-Ogden
  subsection Holzapfel-Ogden
    set a    = 2.28
    set b    = 9.726
    set a_f  = 1.685
    set b_f  = 15.779
    set a_s  = 0
    set a_fs = 0
  end
end
subsection Mechanics
  set Fixed boundaries          = base
  set Pressure boundary         = endocardium
  set Newton relative tolerance = 1e-5
  set Newton absolute tolerance = 1e-6
  set Maximum Newton iterations = 6
end
subsection Active tension
  set Model = twitch
end
subsection Circulation
  set Model                   = 3-element Windkessel
  set Mitral valve resistance = 0.03
  set Number of beats         = 1
  set Relative tolerance      = 1e-3
  set Maximum time step       = 20
end
subsection Output
  set Field output interval = 0
  set Progress              = off
end
)";
} // namespace


TEST_CASE("A tension model added through the table alone drives a heartbeat",
          "[simulation][registry]")
{
  auto &table = Materials::tension_models();
  table.add(
    {"twitch",
     "a test twitch;",
     nullptr,
     [](const dealii::ParameterHandler &, const double) {
       return std::unique_ptr<Materials::TensionModel>(
         std::make_unique<test_support::ToyTension>("twitch", &twitch, 20.0));
     }});
  const auto folder =
    std::filesystem::temp_directory_path() / "systole_toy_tension";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const auto file = folder / "twitch.prm";
  std::ofstream(file) << parameter_file
                      << "subsection Output\n  set Directory = "
                      << folder.string() << "\nend\n";
  std::ostringstream log;
  try
    {
      Simulation simulation(file.string(), MPI_COMM_WORLD, log);
      simulation.run();
    }
  catch (...)
    {
      table.remove("twitch");
      INFO(log.str());
      throw;
    }
  table.remove("twitch");
  const std::string text = log.str();
  INFO(text);
  CHECK(text.find("mitral valve closes") != std::string::npos);
  CHECK(text.find("aortic valve opens") != std::string::npos);
  CHECK(text.find("aortic valve closes") != std::string::npos);
  std::smatch m;
  REQUIRE(std::regex_search(text, m, std::regex("EF ([0-9.]+) %")));
  CHECK(std::stod(m[1]) > 20.0);
  CHECK(std::filesystem::exists(folder / "twitch" / "results.h5"));
  std::filesystem::remove_all(folder);
}
