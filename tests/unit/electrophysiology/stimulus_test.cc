// Stimulus protocols: parsing, regions, time windows.
#include "electrophysiology/stimulus.h"

#include <catch2/catch.hpp>

using namespace systole::Electrophysiology;

TEST_CASE("Stimuli are parsed from their one-line form", "[ep][stimulus]")
{
  const auto s =
    parse_stimuli("corner: box 0 0 0 1.5 1.5 1.5 from 0 for 2 at 50; "
                  "apex: sphere 0,0,-20 2.5 at 30 for 1 from 5 ;"
                  "endo: surface endocardium 1 from 10 for 3 at 40");
  REQUIRE(s.size() == 3);
  CHECK(s[0].name == "corner");
  CHECK(s[0].region.shape == StimulusRegion::Shape::box);
  CHECK(s[0].region.upper[1] == 1.5);
  CHECK(s[0].duration == 2);
  CHECK(s[0].amplitude == 50);
  CHECK(s[1].region.shape == StimulusRegion::Shape::sphere);
  CHECK(s[1].region.centre[2] == -20);
  CHECK(s[1].region.radius == 2.5);
  CHECK(s[1].start == 5); // keywords in any order
  CHECK(s[2].region.shape == StimulusRegion::Shape::surface);
  CHECK(s[2].region.boundary_part == "endocardium");
  CHECK(s[2].region.distance == 1);
  CHECK(parse_stimuli("").empty());
}

TEST_CASE("Malformed stimuli are rejected with the expected form",
          "[ep][stimulus]")
{
  for (const char *text :
       {"box 0 0 0 1 1 1 from 0 for 2 at 50",       // no name
        "a: cube 0 0 0 1 1 1 from 0 for 2 at 50",   // unknown region
        "a: box 0 0 0 1 1 from 0 for 2 at 50",      // too few numbers
        "a: box 0 0 0 1 1 1 from 0 for 2",          // no amplitude
        "a: box 0 0 0 1 1 1 from 0 for 0 at 1",     // zero duration
        "a: box 1 0 0 0 1 1 from 0 for 1 at 1",     // inverted box
        "a: sphere 0 0 0 -1 from 0 for 1 at 1",     // negative radius
        "a: box 0 0 0 1 1 1 from x for 1 at 1",     // not a number
        "a: box 0 0 0 1 1 1 from 0 for 1 at 1 now", // trailing word
        "a: box 0 0 0 1 1 1 from 0 for 1 at 1; a: sphere 0 0 0 1 from 0 "
        "for 1 at 1"}) // duplicate name
    {
      INFO(text);
      CHECK_THROWS_WITH(parse_stimuli(text),
                        Catch::Contains("Electrophysiology / Stimuli") &&
                          Catch::Contains("Expected"));
    }
}

TEST_CASE("Stimulus regions contain what they should", "[ep][stimulus]")
{
  const auto  s   = parse_stimuli("b: box 0 0 0 1 2 3 from 0 for 1 at 1;"
                                  "s: sphere 1 1 1 0.5 from 0 for 1 at 1;"
                                  "f: surface x_min 0.25 from 0 for 1 at 1");
  const auto &box = s[0].region, &sphere = s[1].region, &layer = s[2].region;
  CHECK(box.contains(dealii::Point<3>(0, 0, 0))); // closed
  CHECK(box.contains(dealii::Point<3>(1, 2, 3)));
  CHECK_FALSE(box.contains(dealii::Point<3>(1.01, 1, 1)));
  CHECK(sphere.contains(dealii::Point<3>(1.5, 1, 1)));
  CHECK_FALSE(sphere.contains(dealii::Point<3>(1.4, 1.4, 1)));
  CHECK(layer.contains(dealii::Point<3>(7, 7, 7), 0.25));
  CHECK_FALSE(layer.contains(dealii::Point<3>(0, 0, 0), 0.26));
}

TEST_CASE("Stimuli switch on in their window, every period", "[ep][stimulus]")
{
  const auto s = parse_stimuli("a: box 0 0 0 1 1 1 from 10 for 2 at 1")[0];
  // Once (period 0): [10, 12).
  CHECK_FALSE(s.active(9.999, 0));
  CHECK(s.active(10, 0));
  CHECK(s.active(11.999, 0));
  CHECK_FALSE(s.active(12, 0));
  CHECK_FALSE(s.active(810, 0));
  // Every beat of 800 ms: [10 + 800 k, 12 + 800 k).
  CHECK(s.active(810.5, 800));
  CHECK(s.active(1611.9, 800));
  CHECK_FALSE(s.active(812.5, 800));
  CHECK_FALSE(s.active(5, 800)); // never before the first onset
}

TEST_CASE("Steps end at every stimulus switching time", "[ep][stimulus]")
{
  const auto s = parse_stimuli("a: box 0 0 0 1 1 1 from 10 for 2 at 1;"
                               "b: box 0 0 0 1 1 1 from 0 for 2 at 1");
  // Once: 0 (excluded: the interval is open), 2, 10, 12.
  CHECK(switching_times(s, 0, 0, 100) == std::vector<double>{2, 10, 12});
  CHECK(switching_times(s, 0, 5, 11) == std::vector<double>{10});
  // Every 400 ms, from 790 to 1210: 800, 802, 810, 812, 1200, 1202.
  CHECK(switching_times(s, 400, 790, 1210) ==
        std::vector<double>{800, 802, 810, 812, 1200, 1202});
  CHECK(switching_times(s, 400, 12, 400).empty());
}
