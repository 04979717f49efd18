#include <deal.II/base/exceptions.h>

#include "base/errors.h"
#include "io/results_file.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

using namespace systole;

TEST_CASE("A results file removed during the run stops the next row with one "
          "line",
          "[io][errors]")
{
  const std::string folder = "results_file_test_removed";
  std::filesystem::remove_all(folder);
  {
    IO::ResultsFile file(folder, "# parameters", MPI_COMM_SELF);
    file.append_timeseries({{"time", "ms", 0.0}});
    file.append_timeseries({{"time", "ms", 1.0}});
    CHECK(file.rows().timeseries == 2);
    std::filesystem::remove(folder + "/results.h5");
    std::string message;
    try
      {
        file.append_timeseries({{"time", "ms", 2.0}});
      }
    catch (const std::exception &e)
      {
        message = one_line_message(e);
      }
    CHECK_THAT(message,
               Catch::Contains("results_file_test_removed/results.h5' was "
                               "removed during the run"));
    CHECK(message.find('\n') == std::string::npos);
    // Nothing more is written, and the file (healthy, only unlinked) closes
    // as usual: the process may finalize.
    CHECK_THROWS(file.append_timeseries({{"time", "ms", 3.0}}));
    CHECK_FALSE(IO::a_results_write_failed());
  }
  std::filesystem::remove_all(folder);
}
