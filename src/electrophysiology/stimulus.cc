#include "electrophysiology/stimulus.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace systole::Electrophysiology
{
  bool
  StimulusRegion::contains(const dealii::Point<3> &p,
                           const double            distance_to_surface) const
  {
    switch (shape)
      {
        case Shape::box:
          for (unsigned int d = 0; d < 3; ++d)
            if (p[d] < lower[d] || p[d] > upper[d])
              return false;
          return true;
        case Shape::sphere:
          return p.distance(centre) <= radius;
        case Shape::surface:
          return distance_to_surface <= distance;
      }
    return false;
  }


  bool
  Stimulus::active(const double t, const double period) const
  {
    if (t < start)
      return false;
    const double since = t - start;
    if (period <= 0)
      return since < duration;
    return since - period * std::floor(since / period) < duration;
  }


  std::vector<double>
  switching_times(const std::vector<Stimulus> &stimuli,
                  const double                 period,
                  const double                 t0,
                  const double                 t1)
  {
    std::vector<double> times;
    for (const auto &s : stimuli)
      for (const double edge : {s.start, s.start + s.duration})
        {
          if (period <= 0)
            {
              if (edge > t0 && edge < t1)
                times.push_back(edge);
              continue;
            }
          // edge + k period for k >= 0 inside (t0, t1).
          const double k0 = std::max(0.0, std::floor((t0 - edge) / period));
          for (double k = k0; edge + k * period < t1; k += 1)
            if (edge + k * period > t0)
              times.push_back(edge + k * period);
        }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    return times;
  }


  namespace
  {
    const char *form =
      "'<name>: <region> from <start ms> for <duration ms> at <amplitude "
      "µA/mm³>' with <region> 'box x0 y0 z0 x1 y1 z1', 'sphere x y z r' or "
      "'surface <boundary part> <distance mm>'";

    double
    number(const std::string &word, const std::string &item)
    {
      try
        {
          std::size_t  used  = 0;
          const double value = std::stod(word, &used);
          if (used == word.size() && std::isfinite(value))
            return value;
        }
      catch (const std::exception &)
        {}
      AssertThrow(false,
                  dealii::ExcMessage(
                    "Electrophysiology / Stimuli: '" + word + "' in '" + item +
                    "' is not a number. Expected " + form + "."));
      return 0;
    }
  } // namespace


  std::vector<Stimulus>
  parse_stimuli(const std::string &text)
  {
    std::vector<Stimulus> stimuli;
    for (const auto &raw : dealii::Utilities::split_string_list(text, ';'))
      {
        const std::string item = dealii::Utilities::trim(raw);
        if (item.empty())
          continue;
        const auto bad = [&](const std::string &why) {
          AssertThrow(false,
                      dealii::ExcMessage("Electrophysiology / Stimuli: '" +
                                         item + "': " + why + ". Expected " +
                                         form + "."));
        };
        const auto colon = item.find(':');
        if (colon == std::string::npos)
          bad("no name (missing ':')");
        Stimulus s;
        s.name = dealii::Utilities::trim(item.substr(0, colon));
        if (s.name.empty())
          bad("empty name");
        for (const auto &other : stimuli)
          if (other.name == s.name)
            bad("the name '" + s.name + "' is used twice");

        std::string rest = item.substr(colon + 1);
        std::replace(rest.begin(), rest.end(), ',', ' ');
        std::istringstream       in(rest);
        std::vector<std::string> words;
        for (std::string w; in >> w;)
          words.push_back(w);

        std::size_t i    = 0;
        const auto  next = [&]() -> const std::string  &{
          if (i >= words.size())
            bad("it ends too early");
          return words[i++];
        };
        const auto value = [&]() { return number(next(), item); };

        const std::string shape = next();
        if (shape == "box")
          {
            s.region.shape = StimulusRegion::Shape::box;
            for (unsigned int d = 0; d < 3; ++d)
              s.region.lower[d] = value();
            for (unsigned int d = 0; d < 3; ++d)
              s.region.upper[d] = value();
            for (unsigned int d = 0; d < 3; ++d)
              if (s.region.upper[d] < s.region.lower[d])
                bad("the box's upper corner lies below its lower corner");
          }
        else if (shape == "sphere")
          {
            s.region.shape = StimulusRegion::Shape::sphere;
            for (unsigned int d = 0; d < 3; ++d)
              s.region.centre[d] = value();
            s.region.radius = value();
            if (!(s.region.radius > 0))
              bad("the sphere's radius must be > 0");
          }
        else if (shape == "surface")
          {
            s.region.shape         = StimulusRegion::Shape::surface;
            s.region.boundary_part = next();
            s.region.distance      = value();
            if (!(s.region.distance >= 0))
              bad("the layer thickness must be >= 0");
          }
        else
          bad("unknown region '" + shape + "'");

        bool have_start = false, have_duration = false, have_amplitude = false;
        while (i < words.size())
          {
            const std::string key = next();
            if (key == "from")
              {
                s.start    = value();
                have_start = true;
              }
            else if (key == "for")
              {
                s.duration    = value();
                have_duration = true;
              }
            else if (key == "at")
              {
                s.amplitude    = value();
                have_amplitude = true;
              }
            else
              bad("unexpected '" + key + "'");
          }
        if (!have_start || !have_duration || !have_amplitude)
          bad("'from', 'for' and 'at' are all required");
        if (!(s.duration > 0))
          bad("the duration must be > 0");
        stimuli.push_back(s);
      }
    return stimuli;
  }
} // namespace systole::Electrophysiology
