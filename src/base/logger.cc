#include "base/logger.h"

#include <deal.II/base/exceptions.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace systole
{
  Logger::Logger(const MPI_Comm comm, std::ostream &stream)
    : out(stream, dealii::Utilities::MPI::this_mpi_process(comm) == 0)
    , details(stream, dealii::Utilities::MPI::this_mpi_process(comm) == 0)
  {}

  dealii::ConditionalOStream &
  Logger::detail()
  {
    return details;
  }

  void
  Logger::set_details(const bool enabled)
  {
    details.set_condition(enabled && out.is_active());
  }

  dealii::ConditionalOStream &
  Logger::stream()
  {
    return out;
  }

  void
  Logger::line(const std::string &text)
  {
    out << text << std::endl;
  }

  bool
  Logger::is_root() const
  {
    return out.is_active();
  }

  namespace
  {
    std::string
    format_seconds(const double s)
    {
      std::ostringstream o;
      if (s < 0 || !std::isfinite(s))
        return "?";
      const long total = static_cast<long>(s + 0.5);
      if (total >= 3600)
        o << total / 3600 << "h" << std::setw(2) << std::setfill('0')
          << (total % 3600) / 60 << "m";
      else if (total >= 60)
        o << total / 60 << "m" << std::setw(2) << std::setfill('0')
          << total % 60 << "s";
      else
        o << total << "s";
      return o.str();
    }
  } // namespace

  Progress::Progress(Logger      &logger,
                     const Mode   mode,
                     const double start_time,
                     const double end_time,
                     const double min_interval_seconds)
    : logger(logger)
    , start_time(start_time)
    , end_time(end_time)
    , min_interval(min_interval_seconds)
    , started(std::chrono::steady_clock::now())
  {
    switch (mode)
      {
        case Mode::on:
          active = true;
          break;
        case Mode::off:
          active = false;
          break;
        case Mode::automatic:
          active = (std::getenv("CI") == nullptr) && isatty(fileno(stdout));
          break;
      }
    active = active && logger.is_root();
  }

  double
  Progress::elapsed() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         started)
      .count();
  }

  bool
  Progress::enabled() const
  {
    return active;
  }

  void
  Progress::update(const unsigned int step,
                   const double       time,
                   const std::string &activity)
  {
    if (!active)
      return;
    const double now = elapsed();
    if (now - last_print < min_interval)
      return;
    last_print = now;

    const double done = (end_time > start_time)
                          ? (time - start_time) / (end_time - start_time)
                          : 1.0;
    const double eta  = (done > 1e-6) ? now * (1.0 - done) / done : -1.0;

    std::ostringstream o;
    o << "[step " << step << "  t = " << std::fixed << std::setprecision(2)
      << time << " ms (" << std::setprecision(0) << 100.0 * done << "%)  "
      << activity << "  elapsed " << format_seconds(now) << "  ETA "
      << format_seconds(eta) << "]";
    logger.line(o.str());
  }

  Progress::Mode
  Progress::parse_mode(const std::string &text)
  {
    if (text == "on")
      return Mode::on;
    if (text == "off")
      return Mode::off;
    AssertThrow(text == "auto",
                dealii::ExcMessage(
                  "Output / Progress must be auto, on or off, not '" + text +
                  "'."));
    return Mode::automatic;
  }
} // namespace systole
