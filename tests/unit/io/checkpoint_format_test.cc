#include "io/checkpoint_format.h"

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>
#include <boost/serialization/vector.hpp>
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <vector>

using namespace systole;

namespace
{
  /// Special values and random bit patterns (every finite double is fair).
  std::vector<double>
  test_doubles()
  {
    using L               = std::numeric_limits<double>;
    std::vector<double> x = {0.0,
                             -0.0,
                             0.1,
                             1.0 / 3.0,
                             M_PI,
                             L::max(),
                             L::lowest(),
                             L::min(),
                             L::denorm_min(),
                             -L::denorm_min(),
                             L::epsilon(),
                             L::infinity(),
                             -L::infinity(),
                             L::quiet_NaN()};
    std::mt19937_64     rng(42);
    while (x.size() < 2000)
      {
        const std::uint64_t bits = rng();
        double              value;
        std::memcpy(&value, &bits, sizeof(value));
        if (std::isfinite(value))
          x.push_back(value);
      }
    return x;
  }

  void
  write_text(const std::filesystem::path &file, const std::string &text)
  {
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
  }
} // namespace

TEST_CASE("The checkpoint state text reads every double back bit for bit",
          "[io][checkpoint]")
{
  const std::vector<double> x = test_doubles();
  IO::StateWriter           writer;
  unsigned int              step = 17;
  writer.archive() & x     &step;
  const std::string         text = writer.finish();
  for (const char c : text)
    CHECK((std::isprint(static_cast<unsigned char>(c)) || c == '\n'));
  CHECK(text.rfind("systole-checkpoint " +
                     std::to_string(IO::checkpoint_format) + " ",
                   0) == 0);

  IO::StateReader       reader(text, "test");
  std::vector<double>   y;
  unsigned int          step_read = 0;
  reader.archive() & y &step_read;
  CHECK(step_read == step);
  REQUIRE(y.size() == x.size());
  unsigned int n_different = 0;
  for (unsigned int i = 0; i < x.size(); ++i)
    if (std::isnan(x[i]) ? !std::isnan(y[i])
                         : std::memcmp(&x[i], &y[i], sizeof(double)) != 0)
      ++n_different;
  CHECK(n_different == 0);
}

TEST_CASE("A checkpoint of another format is refused naming both versions",
          "[io][checkpoint]")
{
  namespace fs           = std::filesystem;
  const fs::path folder  = "checkpoint_format_test";
  const auto     current = std::to_string(IO::checkpoint_format);
  fs::remove_all(folder);

  SECTION("this format")
  {
    IO::StateWriter writer;
    write_text(folder / IO::checkpoint_state_file, writer.finish());
    CHECK(IO::checkpoint_format_fault(folder.string()).empty());
  }
  SECTION("a newer format")
  {
    write_text(folder / IO::checkpoint_state_file,
               "systole-checkpoint 99 little-endian systole 9.9 (abc)\n22 x\n");
    const std::string fault = IO::checkpoint_format_fault(folder.string());
    CHECK(fault.find("checkpoint format 99 (written by systole 9.9 (abc))") !=
          std::string::npos);
    CHECK(fault.find("reads format " + current) != std::string::npos);
  }
  SECTION("the binary format 1")
  {
    write_text(folder / "state.bin", "\x16\x00");
    const std::string fault = IO::checkpoint_format_fault(folder.string());
    CHECK(fault.find("checkpoint format 1") != std::string::npos);
    CHECK(fault.find("reads format " + current) != std::string::npos);
  }
  SECTION("not a checkpoint")
  {
    write_text(folder / IO::checkpoint_state_file, "22 serialization::archive");
    CHECK(IO::checkpoint_format_fault(folder.string()).find("unknown format") !=
          std::string::npos);
  }
  fs::remove_all(folder);
}
