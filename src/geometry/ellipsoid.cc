#include "geometry/ellipsoid.h"

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <string>

namespace systole::Geometry
{
  using dealii::Point;

  namespace
  {
    constexpr double half_pi = 0.5 * M_PI;

    void
    require(const bool condition, const std::string &message)
    {
      AssertThrow(condition, dealii::ExcMessage(message));
    }
  } // namespace

  double
  LVShape::short_radius(const double t) const
  {
    return endo_short_radius + t * (epi_short_radius - endo_short_radius);
  }

  double
  LVShape::long_radius(const double t) const
  {
    return endo_long_radius + t * (epi_long_radius - endo_long_radius);
  }

  LVShape
  LVShape::arostica()
  {
    LVShape shape;
    shape.endo_short_radius = 25.0;
    shape.endo_long_radius  = 90.0;
    shape.epi_short_radius  = 35.0;
    shape.epi_long_radius   = 97.0;
    // x = r_l cos(mu_b) with cos(mu_b) = 5/17 (endo) and 5/20 (epi).
    shape.base_height     = 90.0 * 5.0 / 17.0;
    shape.epi_base_height = 97.0 * 5.0 / 20.0;
    shape.long_axis_x     = true;
    return shape;
  }

  bool
  LVShape::ruled_base() const
  {
    return !std::isnan(epi_base_height) && epi_base_height != base_height;
  }

  double
  LVShape::epicardial_base_height() const
  {
    return ruled_base() ? epi_base_height : base_height;
  }

  namespace
  {
    /// Where the segment from the endocardial cut ring to the epicardial one
    /// (in a meridional plane: rho, z) meets the spheroid (rs, rl): the root
    /// s >= 0 of the quadratic A s^2 + B s + C = 0 in the segment parameter.
    /// C <= 0 (the endocardial ring lies inside every spheroid t >= 0) and
    /// A > 0, so it is unique; the form 2(-C)/(B + sqrt(B^2 - 4AC)) gives
    /// s = 0 exactly on the endocardium.
    std::array<double, 2>
    ruled_base_point(const LVShape &shape, const double rs, const double rl)
    {
      const double z_e = shape.base_height;
      const double z_p = shape.epi_base_height;
      const double rho_e =
        shape.endo_short_radius *
        std::sqrt(1.0 - std::pow(z_e / shape.endo_long_radius, 2));
      const double rho_p =
        shape.epi_short_radius *
        std::sqrt(1.0 - std::pow(z_p / shape.epi_long_radius, 2));
      const double d_rho = rho_p - rho_e, d_z = z_p - z_e;
      const double A = d_rho * d_rho / (rs * rs) + d_z * d_z / (rl * rl);
      const double B =
        2.0 * (rho_e * d_rho / (rs * rs) + z_e * d_z / (rl * rl));
      const double C =
        std::min(0.0, rho_e * rho_e / (rs * rs) + z_e * z_e / (rl * rl) - 1.0);
      const double s = 2.0 * (-C) / (B + std::sqrt(B * B - 4.0 * A * C));
      return {{rho_e + s * d_rho, z_e + s * d_z}};
    }
  } // namespace

  double
  LVShape::base_angle(const double t) const
  {
    if (!ruled_base())
      return std::acos(-base_height / long_radius(t));
    const double rs = short_radius(t), rl = long_radius(t);
    const auto   p = ruled_base_point(*this, rs, rl);
    return std::atan2(p[0] / rs, -p[1] / rl);
  }

  Point<3>
  LVShape::to_generator_frame(const Point<3> &wall) const
  {
    return long_axis_x ? Point<3>(wall[1], wall[2], wall[0]) : wall;
  }

  Point<3>
  LVShape::from_generator_frame(const Point<3> &generator) const
  {
    return long_axis_x ? Point<3>(generator[2], generator[0], generator[1])
                       : generator;
  }

  dealii::Tensor<1, 3>
  LVShape::from_generator_frame(const dealii::Tensor<1, 3> &generator) const
  {
    return long_axis_x
             ? dealii::Tensor<1, 3>({generator[2], generator[0], generator[1]})
             : generator;
  }

  void
  LVShape::validate() const
  {
    const std::string where = "Geometry / Ellipsoid / ";
    require(endo_short_radius > 0 && endo_long_radius > 0,
            where + "the endocardial radii must be positive.");
    require(epi_short_radius > endo_short_radius,
            where + "Epicardium short radius (" +
              std::to_string(epi_short_radius) +
              " mm) must be larger than Endocardium short radius (" +
              std::to_string(endo_short_radius) + " mm).");
    require(epi_long_radius > endo_long_radius,
            where + "Epicardium long radius (" +
              std::to_string(epi_long_radius) +
              " mm) must be larger than Endocardium long radius (" +
              std::to_string(endo_long_radius) + " mm).");
    require(std::abs(base_height) < endo_long_radius,
            where + "|Base height| (" + std::to_string(base_height) +
              " mm) must be smaller than Endocardium long radius (" +
              std::to_string(endo_long_radius) +
              " mm), or the base plane misses the cavity.");
    if (ruled_base())
      {
        require(std::abs(epi_base_height) < epi_long_radius,
                "Geometry: the epicardial cut height (" +
                  std::to_string(epi_base_height) +
                  " mm) must be smaller than the epicardial long radius (" +
                  std::to_string(epi_long_radius) + " mm).");
        // The base segment must leave the endocardial ring outwards (into
        // the wall), or the cut rings do not bound a wall.
        const double z_e = base_height;
        const double rho_e =
          endo_short_radius *
          std::sqrt(1.0 - std::pow(z_e / endo_long_radius, 2));
        const double rho_p =
          epi_short_radius *
          std::sqrt(1.0 - std::pow(epi_base_height / epi_long_radius, 2));
        const double outward =
          rho_e * (rho_p - rho_e) / (endo_short_radius * endo_short_radius) +
          z_e * (epi_base_height - z_e) / (endo_long_radius * endo_long_radius);
        require(outward > 0.0,
                "Geometry: the base segment from the endocardial cut ring "
                "(height " +
                  std::to_string(base_height) + " mm) to the epicardial one (" +
                  std::to_string(epi_base_height) +
                  " mm) runs into the cavity; bring the cut heights closer.");
      }
  }

  EllipsoidalWallManifold::EllipsoidalWallManifold(const LVShape &shape)
    : shape(shape)
    , reference_manifold(Point<3>())
  {}

  std::unique_ptr<dealii::Manifold<3, 3>>
  EllipsoidalWallManifold::clone() const
  {
    return std::make_unique<EllipsoidalWallManifold>(shape);
  }

  Point<3>
  EllipsoidalWallManifold::push_forward(const Point<3> &reference) const
  {
    const double r         = reference.norm();
    const double t         = r - 1.0;
    const double rho_ref   = std::hypot(reference[0], reference[1]);
    const double theta_ref = std::atan2(rho_ref, -reference[2]);
    const double theta     = theta_ref * shape.base_angle(t) / half_pi;

    Point<3> wall;
    if (rho_ref > 0.0)
      {
        const double factor = shape.short_radius(t) * std::sin(theta) / rho_ref;
        wall[0]             = factor * reference[0];
        wall[1]             = factor * reference[1];
      }
    wall[2] = -shape.long_radius(t) * std::cos(theta);
    return shape.from_generator_frame(wall);
  }

  double
  EllipsoidalWallManifold::transmural_coordinate(const Point<3> &point) const
  {
    const Point<3> wall = shape.to_generator_frame(point);
    // Solve rho^2 / r_s(t)^2 + z^2 / r_l(t)^2 = 1; the left side decreases
    // monotonically in t.
    const double rho2 = wall[0] * wall[0] + wall[1] * wall[1];
    const double z2   = wall[2] * wall[2];
    const auto   g    = [&](const double t) {
      const double rs = shape.short_radius(t), rl = shape.long_radius(t);
      return rho2 / (rs * rs) + z2 / (rl * rl) - 1.0;
    };
    const double drs = shape.epi_short_radius - shape.endo_short_radius;
    const double drl = shape.epi_long_radius - shape.endo_long_radius;
    const auto   dg  = [&](const double t) {
      const double rs = shape.short_radius(t), rl = shape.long_radius(t);
      return -2.0 * rho2 * drs / (rs * rs * rs) -
             2.0 * z2 * drl / (rl * rl * rl);
    };

    // Bracket, then safeguarded Newton.
    double lo = -0.5, hi = 1.5;
    while (g(lo) < 0.0 && lo > -0.99 * shape.endo_short_radius / drs)
      lo -= 0.5;
    while (g(hi) > 0.0 && hi < 100.0)
      hi += 1.0;
    double t = 0.5;
    for (unsigned int it = 0; it < 100; ++it)
      {
        const double value = g(t);
        if (std::abs(value) < 1e-15)
          break;
        (value > 0.0 ? lo : hi) = t;
        double next             = t - value / dg(t);
        if (!(next > lo && next < hi))
          next = 0.5 * (lo + hi);
        if (std::abs(next - t) < 1e-15)
          {
            t = next;
            break;
          }
        t = next;
      }
    return t;
  }

  Point<3>
  EllipsoidalWallManifold::pull_back(const Point<3> &point) const
  {
    const double   t    = transmural_coordinate(point);
    const Point<3> wall = shape.to_generator_frame(point);
    const double   rho  = std::hypot(wall[0], wall[1]);
    const double   theta =
      std::atan2(rho / shape.short_radius(t), -wall[2] / shape.long_radius(t));
    const double theta_ref = theta * half_pi / shape.base_angle(t);
    const double r         = 1.0 + t;

    Point<3> reference;
    if (rho > 0.0)
      {
        const double factor = r * std::sin(theta_ref) / rho;
        reference[0]        = factor * wall[0];
        reference[1]        = factor * wall[1];
      }
    reference[2] = -r * std::cos(theta_ref);
    return reference;
  }

  Point<3>
  EllipsoidalWallManifold::get_new_point(
    const dealii::ArrayView<const Point<3>> &surrounding_points,
    const dealii::ArrayView<const double>   &weights) const
  {
    std::vector<Point<3>> reference(surrounding_points.size());
    for (unsigned int i = 0; i < surrounding_points.size(); ++i)
      reference[i] = pull_back(surrounding_points[i]);
    return push_forward(
      reference_manifold.get_new_point(dealii::make_array_view(reference),
                                       weights));
  }

  namespace
  {
    /// A cube face's (n_a + 1) x (n_b + 1) grid of directions.
    struct Patch
    {
      unsigned int                                        n_a, n_b;
      std::function<dealii::Tensor<1, 3>(double, double)> direction;
    };

    /// The coordinate on a cube face of the direction at @p s in [-1, 1]
    /// (equal angles).
    double
    cube_angle(const double s)
    {
      return std::tan(0.25 * M_PI * s);
    }

    dealii::Tensor<1, 3>
    normalized(const dealii::Tensor<1, 3> &d)
    {
      return d / d.norm();
    }

    /// Reference directions on the lower half of a cube, projected with
    /// equal angles: the apex cap (@p N x @p N cells) and the four sides
    /// (@p N x @p L cells each).
    std::vector<Patch>
    cube_patches(const unsigned int N, const unsigned int L)
    {
      std::vector<Patch> patches;
      // Bottom (apex cap): face z = -1. Its first direction runs along -x so
      // that (a, b, radius) is right-handed like on the sides: every cell
      // then has positive volume.
      patches.push_back(
        {N, N, [](const double a, const double b) {
           return normalized(dealii::Tensor<1, 3>(
             {cube_angle(1.0 - 2.0 * a), cube_angle(-1.0 + 2.0 * b), -1.0}));
         }});
      // Four sides, from the bottom edge (c = -1) to the equator (c = 0).
      // The side direction is rotated by k * 90 degrees about the z axis.
      for (unsigned int k = 0; k < 4; ++k)
        patches.push_back(
          {N, L, [k](const double a, const double b) {
             const double c  = -1.0 + b; // b in [0, 1]
             const double u  = cube_angle(-1.0 + 2.0 * a);
             const double cs = std::cos(0.5 * M_PI * k);
             const double sn = std::sin(0.5 * M_PI * k);
             // On face x = 1: (1, u, tan(c pi/4)); rotate
             // about z.
             return normalized(dealii::Tensor<1, 3>(
               {cs * 1.0 - sn * u, sn * 1.0 + cs * u, cube_angle(c)}));
           }});
      return patches;
    }

    /// The cells of the wall, @p M across it, over the @p patches, with
    /// their vertices pushed forward by @p manifold (merged by rounded
    /// reference coordinates).
    void
    wall_cells(const std::vector<Patch>         &patches,
               const unsigned int                M,
               const EllipsoidalWallManifold    &manifold,
               std::vector<Point<3>>            &vertices,
               std::vector<dealii::CellData<3>> &cells)
    {
      std::map<std::array<long, 3>, unsigned int> index_of;
      const auto vertex_index = [&](const Point<3> &reference) {
        const std::array<long, 3> key = {{std::lround(reference[0] * 1e9),
                                          std::lround(reference[1] * 1e9),
                                          std::lround(reference[2] * 1e9)}};
        const auto                it  = index_of.find(key);
        if (it != index_of.end())
          return it->second;
        vertices.push_back(manifold.push_forward(reference));
        index_of[key] = vertices.size() - 1;
        return static_cast<unsigned int>(vertices.size() - 1);
      };

      for (const Patch &patch : patches)
        for (unsigned int m = 0; m < M; ++m)
          for (unsigned int j = 0; j < patch.n_b; ++j)
            for (unsigned int i = 0; i < patch.n_a; ++i)
              {
                dealii::CellData<3> cell;
                for (unsigned int v = 0; v < 8; ++v)
                  {
                    const unsigned int di = v % 2, dj = (v / 2) % 2, dm = v / 4;
                    const double r = 1.0 + static_cast<double>(m + dm) / M;
                    const auto   d =
                      patch.direction(static_cast<double>(i + di) / patch.n_a,
                                      static_cast<double>(j + dj) / patch.n_b);
                    cell.vertices[v] = vertex_index(Point<3>(r * d));
                  }
                cells.push_back(cell);
              }
    }

    /// Boundary ids endocardium 0, epicardium 1, base 2 from the reference
    /// position of the face vertices.
    void
    set_wall_boundary_ids(dealii::Triangulation<3, 3>   &tria,
                          const EllipsoidalWallManifold &manifold,
                          BoundaryNames                 &names)
    {
      const dealii::types::boundary_id endo = 0, epi = 1, base = 2;
      for (const auto &cell : tria.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              bool all_endo = true, all_epi = true, all_base = true;
              for (const unsigned int v : face->vertex_indices())
                {
                  const Point<3> ref = manifold.pull_back(face->vertex(v));
                  const double   r   = ref.norm();
                  all_endo           = all_endo && std::abs(r - 1.0) < 1e-8;
                  all_epi            = all_epi && std::abs(r - 2.0) < 1e-8;
                  all_base           = all_base && std::abs(ref[2]) < 1e-8 * r;
                }
              Assert(all_endo + all_epi + all_base == 1,
                     dealii::ExcInternalError());
              face->set_boundary_id(all_endo ? endo : (all_epi ? epi : base));
            }
      names.add("endocardium", endo);
      names.add("epicardium", epi);
      names.add("base", base);
    }
  } // namespace

  void
  create_lv_mesh(dealii::Triangulation<3, 3> &tria,
                 const LVShape               &shape,
                 const LVMeshCells           &counts,
                 BoundaryNames               &names)
  {
    shape.validate();
    const std::string where = "Geometry / Ellipsoid / ";
    require(
      counts.circumferential >= 8 && counts.circumferential % 8 == 0,
      where + "Cells around circumference (" +
        std::to_string(counts.circumferential) +
        ") must be a multiple of 8 (the apex cap is a cubed-sphere face).");
    const unsigned int N =
      counts.circumferential / 4; // cells along a cube-face edge
    require(counts.longitudinal > N / 2,
            where + "Cells from apex to base (" +
              std::to_string(counts.longitudinal) +
              ") must be larger than Cells around circumference / 8 (" +
              std::to_string(N / 2) + "): the apex cap alone takes that many.");
    require(counts.transmural >= 1,
            where + "Cells through wall must be at least 1.");
    const unsigned int L =
      counts.longitudinal - N / 2; // rows on each side face
    const unsigned int M = counts.transmural;

    const EllipsoidalWallManifold    manifold(shape);
    std::vector<Point<3>>            vertices;
    std::vector<dealii::CellData<3>> cells;
    wall_cells(cube_patches(N, L), M, manifold, vertices, cells);
    dealii::GridTools::consistently_order_cells(cells);
    tria.create_triangulation(vertices, cells, dealii::SubCellData());
    set_wall_boundary_ids(tria, manifold, names);

    tria.set_all_manifold_ids(0);
    tria.set_manifold(0, manifold);
  }
} // namespace systole::Geometry
