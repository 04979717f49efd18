#include "support/postprocess_fixture.h"
#include "support/random_tensors.h"

#include "postprocess/aha_regional.h"
#include "postprocess/clinical_kinematics.h"
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace systole;
using Postprocess::ClinicalKinematics;
using test_support::column_value;

namespace
{
  using Vector = dealii::Tensor<1, 3>;
  using Matrix = dealii::Tensor<2, 3>;
  using Map    = std::function<dealii::Point<3>(const dealii::Point<3> &)>;

  /// The rotation by @p degrees about the z axis, counter-clockwise seen
  /// from below (from the apex at z = 0 toward the base at z = 10), written
  /// out: (x, y) -> (x cos + y sin, -x sin + y cos).
  dealii::Point<3>
  turn(const dealii::Point<3> &X, const double degrees)
  {
    const double a = degrees * M_PI / 180;
    return {X[0] * std::cos(a) + X[1] * std::sin(a),
            -X[0] * std::sin(a) + X[1] * std::cos(a),
            X[2]};
  }

  /// A small synthetic ventricle without a mesh: the long axis z from the
  /// epicardial apex (0, 0, 0) to the base plane z = 10 (AHA cap level 0.1:
  /// apical ring 1 <= z < 4, basal ring z >= 7), vertices at the apex, on
  /// an apical ring (z = 2.5), a basal ring (z = 8) and the base (z = 10),
  /// and 12 points with their own cardiac frames, weights and transmural
  /// coordinates.
  struct Synthetic
  {
    Synthetic()
      : aha([] {
        Postprocess::AhaSegments::Axis a;
        a.apex      = dealii::Point<3>(0, 0, 0);
        a.direction = Vector({0, 0, 1});
        a.length    = 10;
        a.cap_level = 0.1;
        a.reference = Vector({1, 0, 0});
        return a;
      }())
    {
      reference.emplace_back(0, 0, 0);
      for (const auto &[z, radius] :
           std::vector<std::pair<double, double>>{{2.5, 3}, {8, 5}, {10, 5}})
        for (unsigned int k = 0; k < 8; ++k)
          reference.emplace_back(radius * std::cos(k * M_PI / 4),
                                 radius * std::sin(k * M_PI / 4),
                                 z);
      // Two "cells" of 6 points each, in different segments and layers.
      points.resize(2);
      frames.resize(2);
      segments.resize(2);
      for (unsigned int i = 0; i < 12; ++i)
        {
          const unsigned int    c = i / 6;
          Mechanics::PointState p;
          const double          angle = 0.7 * i;
          p.position                  = dealii::Point<3>(4 * std::cos(angle),
                                        4 * std::sin(angle),
                                        1.5 + 0.7 * i);
          p.JxW                       = 0.5 + 0.1 * i;
          p.F                         = dealii::unit_symmetric_tensor<3>();
          points[c].push_back(p);
          // (c, l, r) = (f, s, n) of a random right-handed frame: c = l x r.
          const auto                b = test_support::random_fibre_basis(i + 1);
          Postprocess::CardiacFrame frame;
          frame.circumferential = b.f;
          frame.longitudinal    = b.s;
          frame.radial          = b.n;
          frame.transmural      = (i % 3) / 3.0 + 0.1; // 0.1, 0.43, 0.77
          frames[c].push_back(frame);
          segments[c].push_back(aha.segment(p.position));
        }
    }

    /// Give every point the frame (c, l, r) = (y, z, x).
    void
    cartesian_frames()
    {
      for (auto &cell : frames)
        for (auto &f : cell)
          {
            f.circumferential = Vector({0, 1, 0});
            f.longitudinal    = Vector({0, 0, 1});
            f.radial          = Vector({1, 0, 0});
          }
    }

    /// The data of a step: vertices at phi(X), every point's F = @p F,
    /// fixed areas (the thickness then scales with the wall volume).
    const Postprocess::StepData &
    data(const Map         &phi,
         const Matrix      &F,
         const double       volume,
         const double       time       = 0,
         const unsigned int beat       = 0,
         const double       beat_start = 0)
    {
      vertices.clear();
      for (const auto &X : reference)
        vertices.push_back({X, phi(X)});
      for (auto &cell : points)
        for (auto &p : cell)
          p.F = F;
      step                  = Postprocess::StepData();
      step.time             = time;
      step.beat             = beat;
      step.beat_start       = beat_start;
      step.cavity_volume    = volume;
      step.points           = &points;
      step.frames           = &frames;
      step.segments         = &aha;
      step.point_segments   = &segments;
      step.vertices         = &vertices;
      step.endocardial_area = 100;
      step.epicardial_area  = 140;
      return step;
    }

    /// The data of a homogeneous deformation x = F X.
    const Postprocess::StepData &
    data(const Matrix      &F,
         const double       volume,
         const double       time       = 0,
         const unsigned int beat       = 0,
         const double       beat_start = 0)
    {
      return data(
        [&](const dealii::Point<3> &X) { return dealii::Point<3>(F * X); },
        F,
        volume,
        time,
        beat,
        beat_start);
    }

    Postprocess::AhaSegments                            aha;
    std::vector<dealii::Point<3>>                       reference;
    std::vector<std::vector<Mechanics::PointState>>     points;
    std::vector<std::vector<Postprocess::CardiacFrame>> frames;
    std::vector<std::vector<unsigned int>>              segments;
    std::vector<Mechanics::VertexState>                 vertices;
    Postprocess::StepData                               step;
  };

  std::vector<IO::Column>
  run(ClinicalKinematics &k, const Postprocess::StepData &data)
  {
    std::vector<IO::Column> row;
    k.step(data, row);
    return row;
  }

  const Matrix identity = dealii::unit_symmetric_tensor<3>();

  const std::array<const char *, 3> strain_columns = {
    {"circumferential", "longitudinal", "radial"}};

  /// A step of a beat with the circulation's phases: its time [ms], cavity
  /// volume [mL], uniform stretch and whether the ventricle fills, and the
  /// stretch at the ED it must be referred to.
  struct Phased
  {
    double time, volume, stretch;
    bool   filling;
    double ed_stretch;
  };

  /// Runs @p steps through @p k, checking each step's longitudinal strain
  /// against its ED stretch; @p at(i) is called after step i. Returns the
  /// beat's end_diastolic_time.
  double
  run_phases(Synthetic                               &s,
             ClinicalKinematics                      &k,
             const std::vector<Phased>               &steps,
             const std::function<void(unsigned int)> &at = {})
  {
    for (unsigned int i = 0; i < steps.size(); ++i)
      {
        s.data(steps[i].stretch * identity, steps[i].volume, steps[i].time);
        s.step.filling = steps[i].filling;
        const auto row = run(k, s.step);
        INFO("step " << i);
        CHECK(std::abs(column_value(row, "global_longitudinal_strain") -
                       (steps[i].stretch / steps[i].ed_stretch - 1)) < 1e-14);
        if (at)
          at(i);
      }
    std::vector<IO::Column> summary;
    k.end_beat(s.step, nullptr, summary);
    return column_value(summary, "end_diastolic_time");
  }
} // namespace

TEST_CASE("Clinical kinematics: a deformation after a prestretch gives the "
          "strain of the deformation alone along the ED directions",
          "[postprocess][analytic]")
{
  SECTION("stretches along the frame: the numbers by hand")
  {
    // Frame (c, l, r) = (y, z, x); ED: F1 = diag(1.1, 0.9, 1.05), then
    // F2 = diag(1.3, 0.85, 0.8): the ED directions are the axes, the
    // strains 0.85 - 1 (c), 0.8 - 1 (l), 1.3 - 1 (r).
    Synthetic s;
    s.cartesian_frames();
    const Matrix       F1 = Matrix({{1.1, 0, 0}, {0, 0.9, 0}, {0, 0, 1.05}});
    const Matrix       F2 = Matrix({{1.3, 0, 0}, {0, 0.85, 0}, {0, 0, 0.8}});
    ClinicalKinematics k;
    run(k, s.data(identity, 100));
    run(k, s.data(F1, 120));
    const auto row = run(k, s.data(F2 * F1, 80));
    for (const char *layer : {"global", "endocardial"})
      {
        INFO(layer);
        const std::string p(layer);
        CHECK(std::abs(column_value(row, p + "_circumferential_strain") +
                       0.15) < 1e-14);
        CHECK(std::abs(column_value(row, p + "_longitudinal_strain") + 0.2) <
              1e-14);
        CHECK(std::abs(column_value(row, p + "_radial_strain") - 0.3) < 1e-14);
      }
    // Not the Green-Lagrange strain from the reference along z:
    // ((0.8 * 1.05)^2 - 1) / 2 = -0.1472.
    CHECK(std::abs(column_value(row, "global_longitudinal_strain") + 0.1472) >
          0.05);
    // The wall volume is 1.3 * 0.85 * 0.8 times its ED value (fixed areas).
    CHECK(std::abs(column_value(row, "wall_thickening_ed") -
                   (1.3 * 0.85 * 0.8 - 1)) < 1e-13);
  }

  SECTION("a transverse shear at ED keeps the wall normal")
  {
    // F1 = I + 0.4 y x x slides the layers x = const along y: the ED wall
    // normal is still x (the material line along x tilts), so a stretch
    // 1.25 along x gives the radial strain 0.25 (the tilted material line
    // would give sqrt(1.25^2 + 0.4^2) / sqrt(1 + 0.4^2) - 1 = 0.2186).
    Synthetic s;
    s.cartesian_frames();
    const Matrix       F1 = Matrix({{1, 0, 0}, {0.4, 1, 0}, {0, 0, 1}});
    const Matrix       F2 = Matrix({{1.25, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    ClinicalKinematics k;
    run(k, s.data(identity, 100));
    run(k, s.data(F1, 120));
    const auto row = run(k, s.data(F2 * F1, 80));
    CHECK(std::abs(column_value(row, "global_radial_strain") - 0.25) < 1e-14);
    CHECK(std::abs(column_value(row, "global_circumferential_strain")) < 1e-14);
    CHECK(std::abs(column_value(row, "global_longitudinal_strain")) < 1e-14);
  }

  SECTION("a rotated, dilated ED state and random frames: the weighted means")
  {
    // F1 = 1.1 Q (Q: 40 degrees about (1, 2, 2) / 3): the ED frame of a
    // reference frame E is Q E; F2 is a general deformation gradient.
    Synthetic    s;
    const Vector n({1.0 / 3, 2.0 / 3, 2.0 / 3});
    const double a = 40 * M_PI / 180;
    // Rodrigues: Q = cos a I + (1 - cos a) n x n + sin a [n]_x.
    const Matrix K =
      Matrix({{0, -n[2], n[1]}, {n[2], 0, -n[0]}, {-n[1], n[0], 0}});
    const Matrix Q = std::cos(a) * identity +
                     (1 - std::cos(a)) * dealii::outer_product(n, n) +
                     std::sin(a) * K;
    CHECK((Q * dealii::transpose(Q) - identity).norm() < 1e-14);
    CHECK(std::abs(dealii::determinant(Q) - 1) < 1e-14);
    const Matrix F1 = 1.1 * Q;
    const Matrix F2 =
      Matrix({{0.92, 0.07, -0.03}, {0.05, 1.12, 0.04}, {-0.06, 0.02, 0.97}});
    ClinicalKinematics k;
    run(k, s.data(identity, 100));
    run(k, s.data(F1, 120));
    const auto row = run(k, s.data(F2 * F1, 80));
    // By hand: the mean of |F2 Q E_k| - 1 over the points, weighted by JxW,
    // over all points and over those with transmural < 1/3.
    std::array<double, 3> wall{}, endo{};
    double                w_wall = 0, w_endo = 0;
    for (unsigned int c = 0; c < 2; ++c)
      for (unsigned int q = 0; q < 6; ++q)
        {
          const auto  &f    = s.frames[c][q];
          const double w    = s.points[c][q].JxW;
          const Vector E[3] = {f.circumferential, f.longitudinal, f.radial};
          for (unsigned int i = 0; i < 3; ++i)
            {
              const double e = (F2 * (Q * E[i])).norm() - 1;
              wall[i] += w * e;
              endo[i] += f.transmural < 1.0 / 3 ? w * e : 0.0;
            }
          w_wall += w;
          w_endo += f.transmural < 1.0 / 3 ? w : 0.0;
        }
    CHECK(w_endo > 0);
    CHECK(w_endo < w_wall);
    for (unsigned int i = 0; i < 3; ++i)
      {
        INFO(strain_columns[i]);
        const std::string name =
          std::string("_") + strain_columns[i] + "_strain";
        CHECK(std::abs(column_value(row, "global" + name) - wall[i] / w_wall) <
              1e-14);
        CHECK(std::abs(column_value(row, "endocardial" + name) -
                       endo[i] / w_endo) < 1e-14);
      }
  }
}

TEST_CASE("Clinical kinematics: a rotation of the apical ring relative to the "
          "basal ring since ED is the twist",
          "[postprocess][analytic]")
{
  // ED: the apical ring turned by 5 degrees, the basal ring and the base by
  // -3 degrees; then 17 and -7 degrees: twist (17 + 7) - (5 + 3) = 16
  // degrees. Everything also translated (the rings turn about their
  // centroids).
  Synthetic    s;
  const Vector shift({1, 2, 0.5});
  const auto   twisted = [&](const double apical, const double basal) {
    return [=](const dealii::Point<3> &X) {
      const double z = X[2];
      return turn(X, z > 1 && z < 4 ? apical : (z >= 7 ? basal : 0.0)) + shift;
    };
  };
  ClinicalKinematics k;
  run(k, s.data([](const auto &X) { return X; }, identity, 100));
  run(k, s.data(twisted(5, -3), identity, 120));
  const auto row = run(k, s.data(twisted(17, -7), identity, 80));
  CHECK(std::abs(column_value(row, "twist") - 16) < 1e-12);
  // The ED apex-to-base distance is 10 mm.
  CHECK(std::abs(column_value(row, "torsion_per_length") - 1.6) < 1e-13);
  CHECK(std::abs(column_value(row, "av_plane_displacement")) < 1e-13);
  CHECK(std::abs(column_value(row, "apex_displacement")) < 1e-13);
}

TEST_CASE("Clinical kinematics: a translation gives the AV-plane and apex "
          "displacements and no strain",
          "[postprocess][analytic]")
{
  // ED: x = F1 X with F1 = I + 0.3 x x z + 0.2 z x z: the apex stays at 0,
  // the mean base vertex goes to (3, 0, 12), so the ED long axis is
  // e = (3, 0, 12) / sqrt(153), tilted from the reference axis z.
  Synthetic          s;
  const Matrix       F1 = Matrix({{1, 0, 0.3}, {0, 1, 0}, {0, 0, 1.2}});
  const Vector       e  = Vector({3, 0, 12}) / std::sqrt(153.0);
  ClinicalKinematics k;
  run(k, s.data(identity, 100));
  run(k, s.data(F1, 120));
  SECTION("the whole ventricle moves by d = (1, 2, -3)")
  {
    // Toward the apex along e: -(d . e) = (36 - 3) / sqrt(153).
    const Vector d({1, 2, -3});
    const auto   row =
      run(k,
          s.data([&](const auto &X) { return dealii::Point<3>(F1 * X + d); },
                 F1,
                 80));
    CHECK(std::abs(column_value(row, "av_plane_displacement") -
                   33 / std::sqrt(153.0)) < 1e-13);
    CHECK(std::abs(column_value(row, "apex_displacement") - std::sqrt(14.0)) <
          1e-13);
    for (const char *name : {"global_longitudinal_strain",
                             "global_circumferential_strain",
                             "global_radial_strain",
                             "twist",
                             "wall_thickening_ed"})
      CHECK(std::abs(column_value(row, name)) < 1e-13);
  }
  SECTION("only the base moves, 8 mm toward the apex along the ED axis")
  {
    const auto row =
      run(k,
          s.data(
            [&](const auto &X) {
              return dealii::Point<3>(F1 * X - (X[2] == 10 ? 8.0 : 0.0) * e);
            },
            F1,
            80));
    CHECK(std::abs(column_value(row, "av_plane_displacement") - 8) < 1e-13);
    CHECK(std::abs(column_value(row, "apex_displacement")) < 1e-13);
  }
}

TEST_CASE("Clinical kinematics: end-diastole is the largest volume before "
          "ejection, and the peaks start there",
          "[postprocess]")
{
  // A dilation s at every step: the strain from ED is s / s_ED - 1.
  Synthetic          s;
  ClinicalKinematics k;
  struct Step
  {
    double time, volume, stretch;
  };
  const std::vector<Step> steps = {
    {0, 100, 1.00},               // the first step: ED
    {10, 110, 1.02},              // rises: ED
    {20, 110 * (1 + 1e-9), 1.03}, // noise of the isovolumic phase: not ED
    {30, 120, 1.05},              // ED
    {40, 119, 1.04},              // falls by less than 1 %
    {50, 121, 1.06},              // rises again: ED
    {60, 100, 0.90},              // ejection: ED is fixed
    {70, 130, 0.95}};             // filling again: still the same ED
  const std::vector<double> ed =
    {1.00, 1.02, 1.02, 1.05, 1.05, 1.06, 1.06, 1.06};
  for (unsigned int i = 0; i < steps.size(); ++i)
    {
      const auto row = run(k,
                           s.data(steps[i].stretch * identity,
                                  steps[i].volume,
                                  steps[i].time));
      INFO("step " << i);
      CHECK(std::abs(column_value(row, "global_longitudinal_strain") -
                     (steps[i].stretch / ed[i] - 1)) < 1e-14);
    }
  std::vector<IO::Column> summary;
  k.end_beat(s.step, nullptr, summary);
  CHECK(column_value(summary, "end_diastolic_time") == 50);
  CHECK(std::abs(column_value(summary, "peak_global_radial_strain") -
                 (0.90 / 1.06 - 1)) < 1e-14);
  // Every segment with points has the same strains.
  const std::string segment =
    Postprocess::AhaRegional::column_prefix(s.segments[0][4]);
  CHECK(
    std::abs(column_value(summary, segment + "peak_ed_strain_longitudinal") -
             (0.90 / 1.06 - 1)) < 1e-14);
  CHECK(summary.size() == 11 + 1 + 17 * 3);
  CHECK(summary[0].name == "peak_global_longitudinal_strain");
  CHECK(summary.back().name == "aha_17_peak_ed_strain_radial");
  // Segment 17 (the cap, z < 1) has no point: NaN.
  CHECK(std::isnan(column_value(summary, "aha_17_peak_ed_strain_radial")));

  // The next beat (starting at 800 ms): its first step is ED.
  auto row = run(k, s.data(0.97 * identity, 90, 805, 1, 800));
  CHECK(std::abs(column_value(row, "global_longitudinal_strain")) < 1e-14);
  summary.clear();
  k.end_beat(s.step, nullptr, summary);
  CHECK(column_value(summary, "end_diastolic_time") == 5);

  SECTION("with the circulation's phases: the closure of the mitral valve, "
          "not a later creep of the volume")
  {
    // The volume still rises in isovolumetric contraction (the closed
    // valves leak), by more than the 1e-6 of the volume rule.
    ClinicalKinematics phases;
    CHECK(run_phases(s,
                     phases,
                     {{0, 100, 1.00, true, 1.00},   // the first step: ED
                      {10, 99.5, 0.99, true, 0.99}, // filling, smaller: ED
                      {20, 110, 1.02, false, 1.02}, // closes the mitral valve
                      {30, 110 * (1 + 1e-5), 1.03, false, 1.02}, // the creep
                      {40, 90, 0.95, false, 1.02},               // ejection
                      {50, 120, 1.04, true, 1.02}}) == 20); // filling again
  }

  SECTION("with the circulation's phases: a valve that reopens before the "
          "ejection moves ED to its last closure")
  {
    ClinicalKinematics phases;
    const auto         held = [&](const unsigned int i) {
      if (i != 2)
        return;
      // A checkpoint while ED is held keeps it held (the fifth number of the
      // state: 0 moving, 0.5 held, 1 fixed).
      ClinicalKinematics resumed;
      resumed.set_state(phases.state());
      CHECK(phases.state()[4] == 0.5);
      CHECK(resumed.state()[4] == 0.5);
    };
    CHECK(run_phases(s,
                     phases,
                     {{0, 100, 1.00, true, 1.00},    // the first step: ED
                      {10, 110, 1.02, false, 1.02},  // closes the valve: ED
                      {15, 110, 1.021, false, 1.02}, // held
                      {20, 112, 1.03, true, 1.03},   // reopens: ED again
                      {25, 113, 1.04, false, 1.04},  // closes again: ED
                      {30, 113, 1.05, false, 1.04},  // held
                      {40, 90, 0.95, false, 1.04},   // ejection: fixed
                      {50, 120, 1.06, true, 1.04},   // filling after it
                      {60, 121, 1.07, false, 1.04}}, // and its closure
                     held) == 25);
  }

  SECTION("without a cavity, the first step of each beat")
  {
    ClinicalKinematics other;
    const double       nan = std::numeric_limits<double>::quiet_NaN();
    run(other, s.data(1.1 * identity, nan, 0));
    row = run(other, s.data(1.2 * identity, nan, 10));
    CHECK(std::abs(column_value(row, "global_radial_strain") -
                   (1.2 / 1.1 - 1)) < 1e-14);
    row = run(other, s.data(1.3 * identity, nan, 20, 1, 15));
    CHECK(std::abs(column_value(row, "global_radial_strain")) < 1e-14);
  }
}

TEST_CASE("Clinical kinematics: a checkpoint's state continues the beat",
          "[postprocess]")
{
  Synthetic          s;
  ClinicalKinematics k;
  const Matrix       F1 = Matrix({{1.1, 0.1, 0}, {0, 0.9, 0.05}, {0, 0, 1.05}});
  const Matrix F2 = Matrix({{0.95, 0, 0.1}, {0.02, 1.1, 0}, {0, 0, 0.85}});
  run(k, s.data(identity, 100));
  run(k, s.data(F1, 120, 10));
  run(k, s.data(F2 * F1, 90, 20));
  const std::vector<double> state = k.state();
  SECTION("restored where the points are: the same numbers")
  {
    ClinicalKinematics resumed;
    resumed.set_state(state);
    const auto again = resumed.state();
    REQUIRE(again.size() == state.size());
    for (unsigned int i = 0; i < state.size(); ++i)
      CHECK((again[i] == state[i] ||
             (std::isnan(again[i]) && std::isnan(state[i]))));
    const Matrix F3  = 0.98 * F2 * F1;
    const auto   one = run(k, s.data(F3, 85, 30));
    const auto   two = run(resumed, s.data(F3, 85, 30));
    REQUIRE(one.size() == two.size());
    for (unsigned int i = 0; i < one.size(); ++i)
      CHECK(one[i].value == two[i].value);
    CHECK(std::abs(column_value(two, "global_radial_strain")) > 0.01);
    std::vector<IO::Column> a, b;
    k.end_beat(s.step, nullptr, a);
    resumed.end_beat(s.step, nullptr, b);
    for (unsigned int i = 0; i < a.size(); ++i)
      CHECK((a[i].value == b[i].value ||
             (std::isnan(a[i].value) && std::isnan(b[i].value))));
  }
  SECTION("points it does not know: that step becomes ED")
  {
    ClinicalKinematics resumed;
    resumed.set_state(state);
    for (auto &cell : s.points)
      for (auto &p : cell)
        p.position[0] += 1e-3;
    const auto row = run(resumed, s.data(F2, 85, 30));
    CHECK(std::abs(column_value(row, "global_radial_strain")) < 1e-14);
    CHECK(std::abs(column_value(row, "twist")) < 1e-14);
  }
  SECTION("a state of the wrong size is refused")
  {
    ClinicalKinematics resumed;
    CHECK_THROWS(
      resumed.set_state(std::vector<double>(state.begin(), state.end() - 1)));
  }
}

TEST_CASE("Clinical kinematics on the default ventricle: a dilation after an "
          "ED dilation, and a twist after an ED twist",
          "[postprocess][analytic]")
{
  test_support::PostprocessVentricle setup({"clinical kinematics"});
  const auto                        &axis = setup.manager->segments().axis();
  const dealii::Point<3>             A    = axis.apex;
  const Vector                       e    = axis.direction;
  const double                       L    = axis.length;
  SECTION("dilations by lambda1 (ED) and lambda1 lambda2 about c")
  {
    // x = c + s (X - c): the strains lambda2 - 1 in every direction and
    // layer, the wall thickness lambda2 times its ED value; the apex moves
    // by lambda1 (lambda2 - 1)(A - c), the mean base vertex (on the axis,
    // at A + L e) by lambda1 (lambda2 - 1)(B - c).
    const double           lambda1 = 1.08, lambda2 = 0.9;
    const dealii::Point<3> c        = A + Vector({3, -2, 5});
    const auto             dilation = [&](const double s) {
      return
        [=](const dealii::Point<3> &X) { return Vector((s - 1) * (X - c)); };
    };
    setup.step(dilation(1.0), 100e3);
    setup.step(dilation(lambda1), 120e3);
    const auto row = setup.step(dilation(lambda1 * lambda2), 60e3);
    for (const char *layer : {"global", "endocardial"})
      for (const char *component : strain_columns)
        {
          const std::string name =
            std::string(layer) + "_" + component + "_strain";
          INFO(name);
          CHECK(std::abs(column_value(row, name) - (lambda2 - 1)) < 1e-10);
        }
    CHECK(std::abs(column_value(row, "wall_thickening_ed") - (lambda2 - 1)) <
          1e-10);
    CHECK(std::abs(column_value(row, "apex_displacement") -
                   lambda1 * (1 - lambda2) * (A - c).norm()) < 1e-9);
    CHECK(std::abs(column_value(row, "av_plane_displacement") -
                   lambda1 * (1 - lambda2) * (L - (c - A) * e)) < 1e-9);
    CHECK(std::abs(column_value(row, "twist")) < 1e-10);
  }
  SECTION("twists by 10 degrees (ED) and 25 degrees")
  {
    // Rotations about the long axis by alpha(l): phi up to the top of the
    // apical ring, 0 from the bottom of the basal ring (as in the test of
    // "ventricle function"): twist 25 - 10 degrees from ED.
    const auto  &aha = setup.manager->segments();
    const double cap = axis.cap_level, top = cap + (1 - cap) / 3,
                 bottom = cap + 2 * (1 - cap) / 3;
    const auto twist    = [&](const double degrees) {
      const double phi = degrees * M_PI / 180;
      return [=, &aha](const dealii::Point<3> &X) {
        const double l     = aha.level(X);
        const double alpha = l <= top ? phi
                                : l >= bottom
                                  ? 0.0
                                  : phi * (bottom - l) / (bottom - top);
        const Vector r     = X - A;
        const Vector k     = -e;
        return Vector(r * std::cos(alpha) +
                      dealii::cross_product_3d(k, r) * std::sin(alpha) +
                      k * (k * r) * (1 - std::cos(alpha)) - r);
      };
    };
    setup.step(twist(0), 100e3);
    setup.step(twist(10), 120e3);
    const auto row = setup.step(twist(25), 60e3);
    CHECK(std::abs(column_value(row, "twist") - 15) < 1e-10);
    CHECK(std::abs(column_value(row, "torsion_per_length") - 15 / L) < 1e-10);
    CHECK(std::abs(column_value(row, "av_plane_displacement")) < 1e-10);
    CHECK(std::abs(column_value(row, "apex_displacement")) < 1e-10);
  }
}
