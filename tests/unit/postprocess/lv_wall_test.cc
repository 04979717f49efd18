#include <deal.II/grid/grid_generator.h>

#include "support/postprocess_fixture.h"

#include "postprocess/aha_segments.h"
#include "postprocess/lv_wall.h"
#include "postprocess/manager.h"
#include <catch2/catch.hpp>

#include <array>
#include <cctype>
#include <cmath>
#include <set>

using namespace systole;
using test_support::column_value;

namespace
{
  using Vector = dealii::Tensor<1, 3>;
  using Matrix = dealii::Tensor<2, 3>;
  using Setup  = test_support::PostprocessVentricle;

  /// Both ventricles (parts lv_endocardium 1, rv_endocardium 2, epicardium
  /// 3, base 4; the LV cavity and wall ellipsoids centred at the origin, the
  /// RV's at x = 25 mm, the base plane z = 25 mm).
  const std::string biv_mesh = SYSTOLE_SOURCE_DIR "/meshes/biv_hex_coarse.msh";

  /// @p text with every run of white space made one space (deal.II wraps
  /// its messages).
  std::string
  squeezed(const std::string &text)
  {
    std::string result;
    for (const char c : text)
      if (!std::isspace(static_cast<unsigned char>(c)))
        result += c;
      else if (!result.empty() && result.back() != ' ')
        result += ' ';
    return result;
  }

  /// The boundary parts of the faces of @p cell.
  std::set<dealii::types::boundary_id>
  parts(const dealii::Triangulation<3>::active_cell_iterator &cell)
  {
    std::set<dealii::types::boundary_id> ids;
    for (const auto &face : cell->face_iterators())
      if (face->at_boundary())
        ids.insert(face->boundary_id());
    return ids;
  }

  /// The reference positions of the vertices of the LV wall's cells.
  std::set<std::array<double, 3>>
  wall_vertices(const Setup &s)
  {
    std::set<std::array<double, 3>> result;
    for (const auto &cell : s.tria.active_cell_iterators())
      if (s.manager->wall().contains(cell))
        for (const unsigned int v : cell->vertex_indices())
          result.insert(std::array<double, 3>{
            {cell->vertex(v)[0], cell->vertex(v)[1], cell->vertex(v)[2]}});
    return result;
  }

  /// X turned by @p angle [rad] about the axis through @p A along -@p e
  /// (counter-clockwise seen from the apex).
  dealii::Point<3>
  turned(const dealii::Point<3> &X,
         const dealii::Point<3> &A,
         const Vector           &e,
         const double            angle)
  {
    const Vector r = X - A, k = -e;
    return A + r * std::cos(angle) +
           dealii::cross_product_3d(k, r) * std::sin(angle) +
           k * (k * r) * (1 - std::cos(angle));
  }
} // namespace

TEST_CASE("The LV wall of two ventricles: the LV free wall and the septum, "
          "without the RV free wall",
          "[postprocess][biv]")
{
  Setup       s({"AHA segments"}, Setup::random_basis(), biv_mesh);
  const auto &wall = s.manager->wall();
  REQUIRE(wall.biventricular());
  CHECK(wall.endocardium() == "lv_endocardium");
  CHECK(wall.outer_surface() ==
        std::vector<std::string>{"epicardium", "rv_endocardium"});
  const auto lv_endo = s.boundary_names.id("lv_endocardium"),
             rv_endo = s.boundary_names.id("rv_endocardium"),
             epi     = s.boundary_names.id("epicardium");
  const auto &aha    = s.manager->segments();
  // By the faces: every cell on the LV endocardium is in; a cell on both
  // the RV endocardium and the epicardium (the RV free wall is one cell
  // thick) is out; the septum (in, on the RV endocardium) lies about
  // 90 degrees from the reference direction (0, 1, 0).
  unsigned int n_lv_endo = 0, n_rv_free = 0, n_septum = 0, n_in = 0;
  double       wall_volume = 0, all_volume = 0, septal_angle = 0;
  for (const auto &cell : s.tria.active_cell_iterators())
    {
      const auto ids = parts(cell);
      const bool in  = wall.contains(cell);
      all_volume += cell->measure();
      if (in)
        {
          wall_volume += cell->measure();
          ++n_in;
        }
      if (ids.count(lv_endo) > 0)
        {
          CHECK(in);
          ++n_lv_endo;
        }
      if (ids.count(rv_endo) > 0 && ids.count(epi) > 0 &&
          ids.count(lv_endo) == 0)
        {
          INFO("RV free wall cell at " << cell->center());
          CHECK(!in);
          ++n_rv_free;
        }
      if (in && ids.count(rv_endo) > 0 && ids.count(epi) == 0)
        {
          ++n_septum;
          septal_angle += aha.angle(cell->center()) * 180 / M_PI;
        }
    }
  INFO(n_in << " of " << s.tria.n_active_cells() << " cells in the LV wall; "
            << n_lv_endo << " on the LV endocardium, " << n_rv_free
            << " in the RV free wall, " << n_septum << " septal");
  CHECK(n_lv_endo > 0);
  CHECK(n_rv_free > 0);
  CHECK(n_septum > 0);
  CHECK(std::abs(septal_angle / n_septum - 90) < 15);
  // The LV wall is the shell between the LV ellipsoids (cavity semi-axes
  // 20, 18, 32.5 mm, wall 5 mm) below the base plane z = 25 mm: the volume
  // of an ellipsoid (a, b, c) below it is pi a b (25 + c - (25^3 + c^3) /
  // (3 c^2)). The flat facets and the cells at the junctions make the
  // mesh's a few percent off; the whole mesh (with the RV free wall) is far
  // more.
  const auto below = [](const double a, const double b, const double c) {
    return M_PI * a * b * (25 + c - (25 * 25 * 25 + c * c * c) / (3 * c * c));
  };
  const double shell = below(25, 23, 37.5) - below(20, 18, 32.5);
  INFO("LV wall " << wall_volume << " mm^3, shell " << shell << " mm^3, mesh "
                  << all_volume << " mm^3");
  CHECK(std::abs(wall_volume / shell - 1) < 0.1);
  CHECK(all_volume > 1.3 * shell);

  // The 17 segments partition the LV wall.
  const auto volumes = s.manager->segment_volumes();
  double     total   = 0;
  for (unsigned int k = 0; k < 17; ++k)
    {
      INFO("segment " << k + 1);
      CHECK(volumes[k] > 0);
      total += volumes[k];
    }
  double points_volume = 0;
  {
    std::vector<std::vector<Mechanics::PointState>> states;
    s.problem->point_states(states);
    for (const auto &cell : s.tria.active_cell_iterators())
      if (wall.contains(cell))
        for (const auto &p : states[cell->active_cell_index()])
          points_volume += p.JxW;
  }
  CHECK(std::abs(total - points_volume) < 1e-10 * points_volume);
  CHECK(std::abs(points_volume - wall_volume) < 1e-8 * wall_volume);
  // The LV apex is that of the LV epicardium (the RV's lies higher).
  CHECK(std::abs(aha.axis().apex[2] + 37.5) < 0.5);
}

TEST_CASE("Clinical kinematics on two ventricles: homogeneous deformations "
          "after an ED one give the exact strains of the LV wall",
          "[postprocess][analytic][biv]")
{
  Setup        s({"clinical kinematics"}, Setup::random_basis(), biv_mesh);
  const auto  &wall     = s.manager->wall();
  const auto  &axis     = s.manager->segments().axis();
  const Matrix identity = dealii::unit_symmetric_tensor<3>();
  const auto   linear   = [](const Matrix &F) {
    return [F](const dealii::Point<3> &X) {
      return Vector((F - dealii::unit_symmetric_tensor<3>()) * X);
    };
  };
  SECTION("a general F2 after F1: the means of |F2 e_k| - 1 over the LV wall")
  {
    const Matrix F1 =
      Matrix({{1.05, 0.03, 0.0}, {-0.02, 0.97, 0.04}, {0.01, 0.0, 1.08}});
    const Matrix F2 =
      Matrix({{0.92, 0.07, -0.03}, {0.05, 1.12, 0.04}, {-0.06, 0.02, 0.87}});
    s.step(linear(identity), 100e3);
    s.step(linear(F1), 120e3);
    const auto row = s.step(linear(F2 * F1), 60e3);
    // By hand, at every point: the ED frame e_c = F1 E_c / |.|, e_r =
    // F1^-T E_r / |.|, e_l = e_r x e_c; the means over the LV wall's points
    // and its inner third, and over every point (which must differ).
    const auto &frames = s.manager->frames();
    std::vector<std::vector<Mechanics::PointState>> states;
    s.problem->point_states(states);
    std::array<double, 3> wall_sum{}, endo_sum{}, all_sum{};
    double                w_wall = 0, w_endo = 0, w_all = 0;
    const Matrix          F1_inv_T = dealii::transpose(dealii::invert(F1));
    for (const auto &cell : s.tria.active_cell_iterators())
      {
        const auto c = cell->active_cell_index();
        for (unsigned int q = 0; q < states[c].size(); ++q)
          {
            const auto &f  = frames[c][q];
            Vector      ec = F1 * f.circumferential, er = F1_inv_T * f.radial;
            ec /= ec.norm();
            er /= er.norm();
            const Vector el   = dealii::cross_product_3d(er, ec);
            const double w    = states[c][q].JxW;
            const bool   in   = wall.contains(cell);
            const bool   endo = in && f.transmural < 1.0 / 3;
            const Vector e[3] = {ec, el, er};
            for (unsigned int k = 0; k < 3; ++k)
              {
                const double strain = (F2 * e[k]).norm() - 1;
                all_sum[k] += w * strain;
                wall_sum[k] += in ? w * strain : 0.0;
                endo_sum[k] += endo ? w * strain : 0.0;
              }
            w_all += w;
            w_wall += in ? w : 0.0;
            w_endo += endo ? w : 0.0;
          }
      }
    CHECK(w_endo > 0.2 * w_wall);
    CHECK(w_endo < 0.5 * w_wall);
    const char *names[3]   = {"circumferential", "longitudinal", "radial"};
    double      difference = 0;
    for (unsigned int k = 0; k < 3; ++k)
      {
        INFO(names[k]);
        const std::string suffix = std::string("_") + names[k] + "_strain";
        CHECK(std::abs(column_value(row, "global" + suffix) -
                       wall_sum[k] / w_wall) < 1e-12);
        CHECK(std::abs(column_value(row, "endocardial" + suffix) -
                       endo_sum[k] / w_endo) < 1e-12);
        difference =
          std::max(difference,
                   std::abs(wall_sum[k] / w_wall - all_sum[k] / w_all));
      }
    // The RV free wall (left out) would change the means.
    CHECK(difference > 1e-3);
  }
  SECTION("dilations by lambda1 (ED) and lambda1 lambda2 about c")
  {
    // The strains lambda2 - 1 everywhere, the thickness V / A_endo
    // lambda2 times its ED value, the apex moved by lambda1 (lambda2 -
    // 1)(A - c), the mean LV base vertex B by lambda1 (lambda2 - 1)(B - c)
    // (B: the mean of the LV wall's vertices on the base).
    const double           lambda1 = 1.08, lambda2 = 0.9;
    const dealii::Point<3> c        = axis.apex + Vector({3, -2, 5});
    const auto             dilation = [&](const double f) {
      return
        [=](const dealii::Point<3> &X) { return Vector((f - 1) * (X - c)); };
    };
    s.step(dilation(1.0), 100e3);
    s.step(dilation(lambda1), 120e3);
    const auto row = s.step(dilation(lambda1 * lambda2), 60e3);
    for (const char *name : {"global_longitudinal_strain",
                             "global_circumferential_strain",
                             "global_radial_strain",
                             "endocardial_radial_strain",
                             "wall_thickening_ed"})
      {
        INFO(name);
        CHECK(std::abs(column_value(row, name) - (lambda2 - 1)) < 1e-10);
      }
    Vector       B;
    unsigned int n = 0;
    for (const auto &v : wall_vertices(s))
      if (std::abs(v[2] - 25) < 1e-9)
        {
          B += Vector({v[0], v[1], v[2]});
          ++n;
        }
    B /= n;
    const Vector A  = axis.apex;
    const Vector BA = B - A;
    // The base moves toward the apex along the ED axis (B - A) by
    // lambda1 (1 - lambda2) |B - A| (the apex moves along too).
    CHECK(std::abs(column_value(row, "av_plane_displacement") -
                   lambda1 * (1 - lambda2) * ((B - Vector(c)) * BA) /
                     BA.norm()) < 1e-9);
    CHECK(std::abs(column_value(row, "apex_displacement") -
                   lambda1 * (1 - lambda2) * (A - Vector(c)).norm()) < 1e-9);
    CHECK(std::abs(column_value(row, "twist")) < 1e-10);
  }
}

TEST_CASE("Twist and AV-plane displacement of two ventricles: the LV's rings "
          "and base, whatever the RV free wall does",
          "[postprocess][analytic][biv]")
{
  Setup       s({"clinical kinematics", "ventricle function"},
          Setup::random_basis(),
          biv_mesh);
  const auto &aha  = s.manager->segments();
  const auto &axis = aha.axis();
  const auto  e    = axis.direction;
  const auto  A    = axis.apex;
  const auto  lv   = wall_vertices(s);
  // The vertices of the RV free wall alone: those of cells outside the LV
  // wall that no LV wall cell shares.
  std::set<std::array<double, 3>> rv_only;
  for (const auto &cell : s.tria.active_cell_iterators())
    if (!s.manager->wall().contains(cell))
      for (const unsigned int v : cell->vertex_indices())
        {
          const std::array<double, 3> x = {
            {cell->vertex(v)[0], cell->vertex(v)[1], cell->vertex(v)[2]}};
          if (lv.count(x) == 0)
            rv_only.insert(x);
        }
  REQUIRE(rv_only.size() > 10);
  // Everything but the RV free wall's own vertices: rotations by alpha(l)
  // about the LV axis (phi up to the top of the apical ring, 0 from the
  // bottom of the basal ring, linear between), the base moved by @p drop
  // toward the apex. The RV free wall's own vertices: -30 degrees, and on
  // the base 3 mm away from the apex (counted, they would change the twist
  // and the base). Only vertices are measured (the points' F do not
  // matter here).
  const double cap = axis.cap_level, top = cap + (1 - cap) / 3,
               bottom = cap + 2 * (1 - cap) / 3;
  const auto motion   = [&](const double degrees, const double drop) {
    const double phi = degrees * M_PI / 180;
    return [=, &aha, &rv_only](const dealii::Point<3> &X) {
      const bool base = std::abs(X[2] - 25) < 1e-9;
      if (rv_only.count({{X[0], X[1], X[2]}}) > 0)
        return Vector(turned(X, A, e, -30 * M_PI / 180) +
                      (base ? 3.0 : 0.0) * e - X);
      const double l     = aha.level(X);
      const double alpha = l <= top      ? phi
                             : l >= bottom ? 0.0
                                           : phi * (bottom - l) / (bottom - top);
      return Vector(turned(X, A, e, alpha) - (base ? drop : 0.0) * e - X);
    };
  };
  // ED is the first step (the volume then falls).
  s.step(motion(0, 0), 100e3);
  const auto r = s.step(motion(12, 4), 50e3);
  // B: the mean of the LV wall's base vertices; the ED long axis B - A.
  Vector       B;
  unsigned int n = 0;
  for (const auto &v : lv)
    if (std::abs(v[2] - 25) < 1e-9)
      {
        B += Vector({v[0], v[1], v[2]});
        ++n;
      }
  B /= n;
  const Vector BA = B - Vector(A);
  CHECK(std::abs(column_value(r, "twist") - 12) < 1e-10);
  CHECK(std::abs(column_value(r, "torsion") - 12) < 1e-10);
  CHECK(std::abs(column_value(r, "torsion_per_length") - 12 / BA.norm()) <
        1e-10);
  CHECK(std::abs(column_value(r, "av_plane_displacement") -
                 4 * (e * BA) / BA.norm()) < 1e-10);
  CHECK(std::abs(column_value(r, "apex_displacement")) < 1e-10);
  CHECK(std::abs(column_value(r, "long_axis_shortening") - 4 / (BA * e)) <
        1e-10);
}

TEST_CASE("A mesh with neither endocardium nor lv_endocardium: one clear "
          "error",
          "[postprocess]")
{
  dealii::Triangulation<3> tria;
  dealii::GridGenerator::hyper_cube(tria);
  Geometry::BoundaryNames names("the test cube");
  names.add("base", 0);
  CHECK_THROWS_WITH(Postprocess::LvWall(tria, names, false),
                    Catch::Contains("'endocardium' or 'lv_endocardium'"));
}

TEST_CASE("Two ventricles with the RV outside the septal segments: the error "
          "names a reference direction that puts it at 90 degrees",
          "[postprocess][biv]")
{
  Setup s({"ventricle function"}, Setup::random_basis(), biv_mesh);
  Postprocess::Parameters p;
  p.postprocessors      = {"AHA segments"};
  p.reference_direction = Vector({1, 0, 0});
  std::string message;
  try
    {
      Postprocess::Manager(p, *s.problem, s.boundary_names);
    }
  catch (const std::exception &error)
    {
      message = squeezed(error.what());
    }
  INFO(message);
  CHECK(message.find("outside the septal segments") != std::string::npos);
  CHECK(message.find("set it to 0.000, 1.000,") != std::string::npos);
}

TEST_CASE("Two ventricles: the LV wall's outer surface is its cells' faces on "
          "the epicardium and the septum's RV side, and its mean thickness "
          "is the shape's 5 mm",
          "[postprocess][biv]")
{
  Setup       s({"ventricle function"}, Setup::random_basis(), biv_mesh);
  const auto &wall  = s.manager->wall();
  const auto &cells = wall.cells();
  REQUIRE(wall.outer_surface() ==
          std::vector<std::string>{"epicardium", "rv_endocardium"});
  std::vector<bool> others(cells.size());
  for (unsigned int i = 0; i < cells.size(); ++i)
    others[i] = !cells[i];
  // Each part's area splits into the LV wall's faces and the others'.
  for (const std::string part :
       {"epicardium", "rv_endocardium", "lv_endocardium"})
    {
      INFO(part);
      const double whole = s.problem->deformed_area(part);
      CHECK(std::abs(s.problem->deformed_area(part, &cells) +
                     s.problem->deformed_area(part, &others) - whole) <
            1e-12 * whole);
    }
  // The septum's RV side is in the LV wall, the RV free wall's inside not.
  const double rv_wall_side =
    s.problem->deformed_area("rv_endocardium", &cells);
  CHECK(rv_wall_side > 0.2 * s.problem->deformed_area("rv_endocardium"));
  CHECK(rv_wall_side < 0.8 * s.problem->deformed_area("rv_endocardium"));
  // The mean thickness 2 V / (A_endo + A_outer) of the undeformed LV wall
  // against the shape's (scripts/make_biv_hex_mesh.py: LV wall 5 mm, the
  // septum included: 4.94 mm); V / A_endo alone gives 5.78 mm.
  double volume = 0;
  for (const auto &cell : s.problem->triangulation().active_cell_iterators())
    if (cell->is_locally_owned() && cells[cell->active_cell_index()])
      volume += cell->measure();
  const double endo = s.problem->deformed_area("lv_endocardium", &cells);
  const double outer =
    s.problem->deformed_area("epicardium", &cells) + rv_wall_side;
  const double thickness = 2 * volume / (endo + outer);
  INFO("thickness " << thickness << " mm, V / A_endo " << volume / endo);
  CHECK(std::abs(thickness - 5.0) < 0.25);
  CHECK(volume / endo > 5.5);
}
