#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/data_out.h>

#include "support/postprocess_fixture.h"
#include "support/random_tensors.h"

#include "postprocess/factory.h"
#include "postprocess/manager.h"
#include <catch2/catch.hpp>

#include <cctype>
#include <cmath>
#include <functional>
#include <sstream>

using namespace systole;

namespace
{
  using Setup = test_support::PostprocessVentricle;

  double
  value_of(const std::vector<IO::Column> &row, const std::string &name)
  {
    return test_support::column_value(row, name);
  }

  const std::vector<std::string> all_fields = {"fibre stretch",
                                               "strain",
                                               "volume ratio",
                                               "stress",
                                               "active tension"};
} // namespace

TEST_CASE("Homogeneous stretch along the fibres: every field is analytic at "
          "every point and node",
          "[postprocess][analytic]")
{
  const auto   basis  = test_support::random_fibre_basis(3);
  const double lambda = 1.15;
  Setup        setup(all_fields, basis);
  const auto   f = basis.f;
  setup.step([&](const dealii::Point<3> &X) {
    return dealii::Tensor<1, 3>((lambda - 1) * (f * X) * f);
  });
  const auto  &quantities = setup.manager->quantities();
  const auto  &frames     = setup.manager->frames();
  const double e          = 0.5 * (lambda * lambda - 1);
  unsigned int n_points   = 0;
  double       worst      = 0;
  for (unsigned int c = 0; c < quantities.size(); ++c)
    for (unsigned int q = 0; q < quantities[c].size(); ++q)
      {
        const auto &v  = quantities[c][q];
        const auto &fr = frames[c][q];
        // The frame is orthonormal.
        worst = std::max({worst,
                          std::abs(fr.circumferential.norm() - 1),
                          std::abs(fr.longitudinal.norm() - 1),
                          std::abs(fr.radial.norm() - 1),
                          std::abs(fr.circumferential * fr.radial),
                          std::abs(fr.longitudinal * fr.radial)});
        worst =
          std::max({worst,
                    std::abs(v.fibre_stretch - lambda),
                    std::abs(v.J - lambda),
                    std::abs(v.strain_circumferential -
                             e * std::pow(f * fr.circumferential, 2)),
                    std::abs(v.strain_longitudinal -
                             e * std::pow(f * fr.longitudinal, 2)),
                    std::abs(v.strain_radial - e * std::pow(f * fr.radial, 2)),
                    std::abs(v.active_tension)});
        ++n_points;
      }
  CHECK(n_points > 0);
  CHECK(worst < 1e-10);
  // The nodal fields of constant values are the constants.
  dealii::DataOut<3> data_out;
  setup.problem->attach_output(data_out);
  setup.manager->attach_output(data_out);
  double nodal = 0;
  for (const char *name : {"fibre_stretch", "J"})
    for (const double v : setup.manager->nodal_values(name))
      nodal = std::max(nodal, std::abs(v - lambda));
  CHECK(nodal < 1e-10);
  const auto names = setup.manager->field_names();
  CHECK(names == std::vector<std::string>{"fibre_stretch",
                                          "strain_circumferential",
                                          "strain_longitudinal",
                                          "strain_radial",
                                          "J",
                                          "first_principal_stress",
                                          "fibre_stress",
                                          "active_tension"});
}

TEST_CASE("Simple shear: the strains in the cardiac frame are analytic",
          "[postprocess][analytic]")
{
  Setup setup({"strain", "fibre stretch", "volume ratio"});
  // F = I + gamma a x b with a = e_x, b = e_z.
  const double               gamma = 0.2;
  const dealii::Tensor<1, 3> a({1, 0, 0}), b({0, 0, 1});
  setup.step([&](const dealii::Point<3> &X) {
    return dealii::Tensor<1, 3>(gamma * (b * X) * a);
  });
  const auto &quantities = setup.manager->quantities();
  const auto &frames     = setup.manager->frames();
  const auto  f          = test_support::random_fibre_basis(3).f;
  double      worst      = 0;
  const auto  strain     = [&](const dealii::Tensor<1, 3> &e) {
    // e . E e with E = (gamma (a x b + b x a) + gamma^2 b x b) / 2.
    return gamma * (a * e) * (b * e) + 0.5 * gamma * gamma * (b * e) * (b * e);
  };
  for (unsigned int c = 0; c < quantities.size(); ++c)
    for (unsigned int q = 0; q < quantities[c].size(); ++q)
      {
        const auto &v  = quantities[c][q];
        const auto &fr = frames[c][q];
        worst          = std::max(
          {worst,
                    std::abs(v.strain_circumferential - strain(fr.circumferential)),
                    std::abs(v.strain_longitudinal - strain(fr.longitudinal)),
                    std::abs(v.strain_radial - strain(fr.radial)),
                    std::abs(v.J - 1),
                    std::abs(v.fibre_stretch - std::sqrt(1 + 2 * strain(f)))});
      }
  CHECK(worst < 1e-10);
}

TEST_CASE("A uniform dilation: long-axis shortening 1 - lambda, wall "
          "thickening lambda - 1, no torsion",
          "[postprocess][analytic]")
{
  Setup                  setup({"ventricle function"});
  const double           lambda = 1.1;
  const dealii::Point<3> centre(0.3, -0.2, 1.0);
  setup.step([](const dealii::Point<3> &) { return dealii::Tensor<1, 3>(); });
  const auto row = setup.step([&](const dealii::Point<3> &X) {
    return dealii::Tensor<1, 3>((lambda - 1) * (X - centre));
  });
  CHECK(std::abs(value_of(row, "long_axis_shortening") - (1 - lambda)) < 1e-10);
  CHECK(std::abs(value_of(row, "wall_thickening") - (lambda - 1)) < 1e-10);
  CHECK(std::abs(value_of(row, "torsion")) < 1e-10);
}

TEST_CASE("A prescribed twist: the torsion is its angle",
          "[postprocess][analytic]")
{
  Setup       setup({"ventricle function"});
  const auto &aha  = setup.manager->segments();
  const auto &axis = aha.axis();
  const auto  e    = axis.direction;
  // The apical ring ends and the basal ring starts at these levels.
  const double c = axis.cap_level, top = c + (1 - c) / 3,
               bottom = c + 2 * (1 - c) / 3;
  for (const double degrees : {-12.0, 7.5, 25.0})
    {
      const double phi = degrees * M_PI / 180;
      setup.step(
        [](const dealii::Point<3> &) { return dealii::Tensor<1, 3>(); });
      // Rotate by alpha(l) about the axis (counter-clockwise seen from the
      // apex: right-handed about -e): alpha = phi up to the top of the apical
      // ring, 0 from the bottom of the basal ring, linear between.
      const auto row = setup.step([&](const dealii::Point<3> &X) {
        const double               l     = aha.level(X);
        const double               alpha = l <= top ? phi
                                           : l >= bottom
                                             ? 0.0
                                             : phi * (bottom - l) / (bottom - top);
        const dealii::Tensor<1, 3> r     = X - axis.apex;
        const dealii::Tensor<1, 3> k     = -e;
        const dealii::Tensor<1, 3> rot =
          r * std::cos(alpha) +
          dealii::cross_product_3d(k, r) * std::sin(alpha) +
          k * (k * r) * (1 - std::cos(alpha));
        return dealii::Tensor<1, 3>(rot - r);
      });
      INFO("twist " << degrees << " degrees");
      CHECK(std::abs(value_of(row, "torsion") - degrees) < 1e-10);
      CHECK(std::abs(value_of(row, "long_axis_shortening")) < 1e-10);
    }
}

TEST_CASE("The 17 AHA segments of the default ventricle partition its wall",
          "[postprocess][aha]")
{
  Setup      setup({"AHA segments"});
  const auto volumes = setup.manager->segment_volumes();
  const auto cells   = setup.manager->segment_cells();
  double     total   = 0;
  for (unsigned int s = 0; s < 17; ++s)
    {
      INFO("segment " << s + 1 << " (" << Postprocess::AhaSegments::name(s + 1)
                      << "): " << cells[s] << " cells, " << volumes[s]
                      << " mm^3");
      CHECK(cells[s] > 0);
      total += volumes[s];
    }
  const double wall =
    dealii::GridTools::volume(setup.tria, setup.problem->mapping());
  CHECK(std::abs(total - wall) < 1e-10 * wall);
  unsigned int n_cells = 0;
  for (const unsigned int n : cells)
    n_cells += n;
  // Segments are made of points: a cell may be cut by a segment boundary.
  CHECK(n_cells >= setup.tria.n_global_active_cells());
}

TEST_CASE("AHA segment numbering follows the bull's-eye", "[postprocess][aha]")
{
  Postprocess::AhaSegments::Axis axis;
  axis.apex      = dealii::Point<3>(0, 0, -10);
  axis.direction = dealii::Tensor<1, 3>({0, 0, 1});
  axis.length    = 10;
  axis.cap_level = 0.1;
  axis.reference = dealii::Tensor<1, 3>({1, 0, 0});
  const Postprocess::AhaSegments aha(axis);
  // Counter-clockwise seen from the apex (looking along +z) is clockwise
  // about +z: 90 degrees (the septum) lies at -y.
  const auto at = [&](const double level, const double degrees) {
    const double t = degrees * M_PI / 180;
    return dealii::Point<3>(std::cos(t), -std::sin(t), -10 + 10 * level);
  };
  CHECK(aha.angle(at(0.5, 90)) == Approx(M_PI / 2));
  CHECK(aha.segment(at(0.05, 0)) == 17);
  CHECK(aha.segment(at(0.2, 0)) == 13);
  CHECK(aha.segment(at(0.2, 90)) == 14);
  CHECK(aha.segment(at(0.2, 180)) == 15);
  CHECK(aha.segment(at(0.2, 270)) == 16);
  CHECK(aha.segment(at(0.2, 350)) == 13);
  for (unsigned int k = 0; k < 6; ++k)
    {
      CHECK(aha.segment(at(0.5, 60.0 * k + 20)) == 7 + k);
      CHECK(aha.segment(at(0.9, 60.0 * k - 20 + 360)) == 1 + k);
    }
  CHECK(Postprocess::AhaSegments::name(2) == "basal anteroseptal");
  CHECK(Postprocess::AhaSegments::name(14) == "apical septal");
}

TEST_CASE("An unknown postprocessor is an error naming the valid ones",
          "[postprocess]")
{
  bool thrown = false;
  try
    {
      systole::Postprocess::create_postprocessor("strains");
    }
  catch (const std::exception &e)
    {
      thrown = true;
      // deal.II wraps the message: compare with single spaces.
      std::string msg;
      for (const char c : std::string(e.what()))
        if (!std::isspace(static_cast<unsigned char>(c)))
          msg += c;
        else if (!msg.empty() && msg.back() != ' ')
          msg += ' ';
      INFO(msg);
      CHECK(msg.find("List of postprocessors = \"strains\" is unknown") !=
            std::string::npos);
      for (const auto &name : systole::Postprocess::postprocessor_names())
        CHECK(msg.find(name) != std::string::npos);
      CHECK(systole::Postprocess::postprocessor_names().size() == 8);
    }
  CHECK(thrown);
}
