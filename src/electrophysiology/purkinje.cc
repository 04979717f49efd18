#include "electrophysiology/purkinje.h"

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <random>
#include <sstream>

namespace systole::Electrophysiology
{
  namespace
  {
    const std::vector<std::string> section = {"Electrophysiology", "Purkinje"};

    std::string
    entry_name(const std::string &entry)
    {
      return "Electrophysiology / Purkinje / " + entry;
    }

    std::vector<double>
    parse_numbers(const std::string &text, const std::string &entry)
    {
      std::vector<double> values;
      for (const auto &item : dealii::Utilities::split_string_list(text, ','))
        {
          try
            {
              values.push_back(dealii::Utilities::string_to_double(item));
            }
          catch (...)
            {
              AssertThrow(false,
                          dealii::ExcMessage(entry_name(entry) + ": '" + item +
                                             "' is not a number."));
            }
        }
      return values;
    }

    dealii::Tensor<1, 3>
    parse_vector(const std::string &text, const std::string &entry)
    {
      const auto values = parse_numbers(text, entry);
      AssertThrow(values.size() == 3,
                  dealii::ExcMessage(entry_name(entry) + ": '" + text +
                                     "' must be three numbers 'x, y, z'."));
      return dealii::Tensor<1, 3>({values[0], values[1], values[2]});
    }

    std::string
    to_text(const dealii::Point<3> &p)
    {
      std::ostringstream o;
      o << p[0] << ", " << p[1] << ", " << p[2];
      return o.str();
    }

    /// Subsection "Right bundle" (inside "Purkinje").
    void
    declare_right_bundle(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.enter_subsection("Right bundle");
      prm.declare_entry(
        "Surface",
        "",
        Anything(),
        "Boundary part of a second tree, the right bundle branch (e.g. "
        "rv_endocardium; then Purkinje / Surface is the LV's, e.g. "
        "lv_endocardium); empty: none. It grows from its own His point, "
        "activated with the left one, with the branching entries above (seed + "
        "1). Units: -.");
      prm.declare_entry(
        "His point",
        "0, 0, 0",
        Anything(),
        "Entry of the right bundle 'x, y, z' on its Surface (the "
        "septum's right side). Units: mm.");
      prm.declare_entry("Initial direction",
                        "0, 0, -1",
                        Anything(),
                        "Direction 'x, y, z' of the right bundle. Units: -.");
      prm.declare_entry("His bundle length",
                        "8",
                        Double(0.0),
                        "Length of the right bundle before its fascicles. "
                        "Units: mm.");
      prm.declare_entry("Fascicle angles",
                        "0",
                        Anything(),
                        "Angles of its fascicles from the bundle's direction, "
                        "separated by commas. Units: degrees.");
      prm.declare_entry("Fascicle lengths",
                        "20",
                        Anything(),
                        "Length of each fascicle, one per angle. Units: mm.");
      prm.leave_subsection();
    }

    /// The branches after the fascicles: their lengths, angles and forks.
    void
    declare_branches(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry(
        "Branch length",
        "5",
        Double(0.0),
        "Mean length of the branches after the fascicles (each drawn "
        "uniformly within Branch variation of it). Units: mm.");
      prm.declare_entry(
        "Branch angle",
        "30",
        Double(0.0, 90.0),
        "Mean angle of each branch of a fork from the direction of its parent "
        "(the two branches leave at -angle and +angle, each drawn uniformly "
        "within Branch variation of it). Units: degrees.");
      prm.declare_entry("Branch variation",
                        "0.3",
                        Double(0.0, 0.9),
                        "Relative spread of the branch lengths and angles: "
                        "uniform in (1 - v, 1 + v) times the mean. Units: -.");
      prm.declare_entry("Number of generations",
                        "10",
                        Integer(0, 30),
                        "Forks after the fascicles (a branch that stopped "
                        "early does not fork). Units: -.");
      prm.declare_entry(
        "Minimum node distance",
        "0.9",
        Double(0.0),
        "A branch stops where its next node would lie closer than this to a "
        "node of another branch (not checked on a branch's first segment); "
        "smaller than the Segment length. Units: mm.");
    }


    /// The Purkinje-muscle junctions: where, when, and how they stimulate.
    void
    declare_junctions(dealii::ParameterHandler &prm)
    {
      using namespace dealii::Patterns;
      prm.declare_entry("Apex",
                        "0, 0, -84",
                        Anything(),
                        "The endocardial apex 'x, y, z' (of the left "
                        "ventricle): with Base, the long axis of the Junction "
                        "height limit. Units: mm. Default: the default LV's "
                        "(parameters/lv_heartbeat.prm).");
      prm.declare_entry("Base",
                        "0, 0, 5",
                        Anything(),
                        "A point 'x, y, z' of the base plane on the long axis. "
                        "Units: mm. Default: the default LV's.");
      prm.declare_entry(
        "Junction height limit",
        "1",
        Double(0.0, 1.0),
        "Purkinje-muscle junctions only up to this relative height h = (x - "
        "Apex).(Base - Apex)/|Base - Apex|^2 (0 at the apex, 1 at the base): "
        "the branches after the fascicles do not grow above it, and terminal "
        "nodes above it (of the bundle or a fascicle) are no junctions; the "
        "base above it is activated through the muscle. 1: no limit. The "
        "human network's junctions are sparse towards the base, which "
        "activates last (Durrer et al. 1970, Circulation 41); models keep the "
        "junctions in the apical two thirds (2/3). Units: -.");
      prm.declare_entry(
        "Conduction velocity",
        "3",
        Double(0.0),
        "Conduction velocity along the tree. Units: mm/ms (= m/s). Source: "
        "Purkinje fibres conduct at 2-4 m/s (Durrer et al. 1970, Circulation "
        "41; Sahli Costabal et al. 2016, J Biomech 49, use 3).");
      prm.declare_entry(
        "Junction delay",
        "5",
        Double(0.0),
        "Delay from a junction's activation to the muscle's: the "
        "Purkinje-muscle junction delay, 3-10 ms anterograde (Wiedmann et al. "
        "1996, Circ Res 79; Behradfar et al. 2014, PLoS ONE 9). Units: ms.");
      prm.declare_entry("Random seed",
                        "1234",
                        Integer(0),
                        "Seed of the std::mt19937 that draws the branch "
                        "lengths and angles: the same seed grows the same "
                        "tree. Units: -.");
      prm.declare_entry(
        "Junction stimulus radius",
        "1.5",
        Double(0.0),
        "Model = monodomain: each junction stimulates the nodes within this "
        "distance of it (at least its nearest node), from its time plus the "
        "Junction delay, with the first stimulus's duration and amplitude "
        "(which then start at the His activation, the first stimulus's start). "
        "Units: mm.");
    }

  } // namespace


  void
  PurkinjeParameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Purkinje");
    prm.declare_entry(
      "Enable",
      "false",
      Bool(),
      "Grow a Purkinje network on the endocardium and activate the "
      "myocardium through it (Model = eikonal or reaction-eikonal; for "
      "monodomain see Junction stimulus radius): the His "
      "entry activates when the first stimulus has brought a cell to the "
      "threshold (its start plus the cell's latency), the activation runs "
      "along the tree at the Conduction velocity, and each terminal node (a "
      "Purkinje-muscle junction) activates the mesh node nearest to it "
      "after the Junction delay. The stimuli are then not sources of the "
      "eikonal solve (their amplitude and duration still excite the cells "
      "of the reaction-eikonal model). Units: -.");
    prm.declare_entry("Surface",
                      "endocardium",
                      Anything(),
                      "Boundary part the tree grows on. Units: -.");
    prm.declare_entry(
      "His point",
      "22.9, 0, -5",
      Anything(),
      "Entry of the His bundle 'x, y, z', projected onto the Surface; it "
      "must lie within two Segment lengths of it. Units: mm. Default: the "
      "septal side of the base of the default LV (parameters/"
      "lv_heartbeat.prm; the right ventricle lies towards +x).");
    prm.declare_entry(
      "Initial direction",
      "0, 0, -1",
      Anything(),
      "Direction 'x, y, z' of the His bundle (the left bundle branch) from "
      "the His point, projected onto the surface's tangent plane there. "
      "Units: -. Default: towards the apex of the default LV.");
    prm.declare_entry("His bundle length",
                      "8",
                      Double(0.0),
                      "Length of the bundle from the His point to the "
                      "fascicles. Units: mm.");
    prm.declare_entry(
      "Fascicle angles",
      "-80, 0, 80",
      Anything(),
      "Angles of the fascicles from the bundle's direction, about the "
      "outward surface normal (positive: counter-clockwise seen from the "
      "cavity's outside), separated by commas; one fascicle per angle. "
      "Units: degrees. Default: the left anterior, septal and posterior "
      "fascicles (docs/verification.md, Purkinje network, has the choice).");
    prm.declare_entry("Fascicle lengths",
                      "20, 20, 20",
                      Anything(),
                      "Length of each fascicle, one per angle. Units: mm.");
    prm.declare_entry("Segment length",
                      "1",
                      Double(0.0),
                      "Length of the segments the branches are made of "
                      "(each node is projected onto the surface). Units: "
                      "mm.");
    declare_branches(prm);
    declare_junctions(prm);
    declare_right_bundle(prm);
    prm.leave_subsection();
  }


  PurkinjeParameters
  PurkinjeParameters::right_bundle() const
  {
    PurkinjeParameters p = *this;
    p.surface            = right.surface;
    p.his_point          = right.his_point;
    p.initial_direction  = right.initial_direction;
    p.his_length         = right.his_length;
    p.fascicle_angles    = right.fascicle_angles;
    p.fascicle_lengths   = right.fascicle_lengths;
    p.seed               = seed + 1;
    p.right.surface.clear();
    return p;
  }


  PurkinjeParameters
  PurkinjeParameters::parse(const dealii::ParameterHandler &prm)
  {
    const auto        &s = section;
    PurkinjeParameters p;
    p.enabled = prm.get_bool(s, "Enable");
    p.surface = dealii::Utilities::trim(prm.get(s, "Surface"));
    p.his_point =
      dealii::Point<3>(parse_vector(prm.get(s, "His point"), "His point"));
    p.initial_direction =
      parse_vector(prm.get(s, "Initial direction"), "Initial direction");
    p.his_length = prm.get_double(s, "His bundle length");
    p.fascicle_angles =
      parse_numbers(prm.get(s, "Fascicle angles"), "Fascicle angles");
    p.fascicle_lengths =
      parse_numbers(prm.get(s, "Fascicle lengths"), "Fascicle lengths");
    p.segment_length   = prm.get_double(s, "Segment length");
    p.branch_length    = prm.get_double(s, "Branch length");
    p.branch_angle     = prm.get_double(s, "Branch angle");
    p.variation        = prm.get_double(s, "Branch variation");
    p.generations      = prm.get_integer(s, "Number of generations");
    p.minimum_distance = prm.get_double(s, "Minimum node distance");
    p.apex = dealii::Point<3>(parse_vector(prm.get(s, "Apex"), "Apex"));
    p.base = dealii::Point<3>(parse_vector(prm.get(s, "Base"), "Base"));
    p.junction_height_limit = prm.get_double(s, "Junction height limit");
    p.velocity              = prm.get_double(s, "Conduction velocity");
    p.junction_delay        = prm.get_double(s, "Junction delay");
    p.seed                  = prm.get_integer(s, "Random seed");
    p.junction_radius       = prm.get_double(s, "Junction stimulus radius");
    {
      std::vector<std::string> r = section;
      r.push_back("Right bundle");
      p.right.surface = dealii::Utilities::trim(prm.get(r, "Surface"));
      p.right.his_point =
        dealii::Point<3>(parse_vector(prm.get(r, "His point"), "His point"));
      p.right.initial_direction =
        parse_vector(prm.get(r, "Initial direction"), "Initial direction");
      p.right.his_length = prm.get_double(r, "His bundle length");
      p.right.fascicle_angles =
        parse_numbers(prm.get(r, "Fascicle angles"), "Fascicle angles");
      p.right.fascicle_lengths =
        parse_numbers(prm.get(r, "Fascicle lengths"), "Fascicle lengths");
    }
    if (!p.enabled)
      return p;
    AssertThrow(p.initial_direction.norm() > 0,
                dealii::ExcMessage(entry_name("Initial direction") +
                                   " must not be zero."));
    const auto check_fascicles = [](const std::vector<double> &angles,
                                    const std::vector<double> &lengths,
                                    const std::string         &where) {
      AssertThrow(angles.size() == lengths.size(),
                  dealii::ExcMessage(
                    entry_name(where + "Fascicle lengths") +
                    " needs one length per entry of Fascicle angles (" +
                    std::to_string(angles.size()) + ")."));
      for (const double l : lengths)
        AssertThrow(l >= 0,
                    dealii::ExcMessage(entry_name(where + "Fascicle lengths") +
                                       " must not be negative."));
    };
    check_fascicles(p.fascicle_angles, p.fascicle_lengths, "");
    if (!p.right.surface.empty())
      {
        check_fascicles(p.right.fascicle_angles,
                        p.right.fascicle_lengths,
                        "Right bundle / ");
        AssertThrow(p.right.initial_direction.norm() > 0,
                    dealii::ExcMessage(
                      entry_name("Right bundle / Initial direction") +
                      " must not be zero."));
      }
    const auto positive = [](const double value, const std::string &entry) {
      AssertThrow(value > 0,
                  dealii::ExcMessage(entry_name(entry) + " must be > 0."));
    };
    AssertThrow(p.base.distance(p.apex) > 0,
                dealii::ExcMessage(entry_name("Base") +
                                   " must differ from the Apex (they give "
                                   "the long axis)."));
    positive(p.segment_length, "Segment length");
    positive(p.velocity, "Conduction velocity");
    positive(p.branch_length, "Branch length");
    AssertThrow(p.minimum_distance < p.segment_length,
                dealii::ExcMessage(
                  entry_name("Minimum node distance") + " (" +
                  std::to_string(p.minimum_distance) +
                  " mm) must be smaller than the Segment length (" +
                  std::to_string(p.segment_length) +
                  " mm): a branch's second node lies about one segment from "
                  "its parent's last nodes and would stop every branch."));
    AssertThrow(p.surface != "",
                dealii::ExcMessage(entry_name("Surface") +
                                   " must name a boundary part."));
    return p;
  }


  // --- TriangleSurface ---

  struct TriangleSurface::Index
  {
    using Box = std::pair<dealii::BoundingBox<3>, unsigned int>;
    dealii::RTree<Box> tree;
  };


  TriangleSurface::TriangleSurface(
    std::vector<std::array<dealii::Point<3>, 3>> all)
    : triangles(std::move(all))
  {
    // A canonical order, so that every rank and every partition sees the
    // same list (ties in project() then go the same way).
    const auto less = [](const std::array<dealii::Point<3>, 3> &a,
                         const std::array<dealii::Point<3>, 3> &b) {
      for (unsigned int v = 0; v < 3; ++v)
        for (unsigned int d = 0; d < 3; ++d)
          if (a[v][d] != b[v][d])
            return a[v][d] < b[v][d];
      return false;
    };
    std::sort(triangles.begin(), triangles.end(), less);
    std::vector<Index::Box> boxes;
    boxes.reserve(triangles.size());
    for (unsigned int t = 0; t < triangles.size(); ++t)
      boxes.emplace_back(dealii::BoundingBox<3>(
                           std::vector<dealii::Point<3>>(triangles[t].begin(),
                                                         triangles[t].end())),
                         t);
    index       = std::make_unique<Index>();
    index->tree = dealii::pack_rtree(boxes);
  }


  TriangleSurface::TriangleSurface(TriangleSurface &&) noexcept = default;
  TriangleSurface::~TriangleSurface()                           = default;


  TriangleSurface
  TriangleSurface::gather(const dealii::Triangulation<3, 3> &tria,
                          const dealii::types::boundary_id   id,
                          const MPI_Comm                     comm)
  {
    std::vector<double> local; // 9 coordinates per triangle
    const auto          add = [&](const dealii::Point<3>     &a,
                         dealii::Point<3>            b,
                         dealii::Point<3>            c,
                         const dealii::Tensor<1, 3> &outward) {
      if (dealii::cross_product_3d(b - a, c - a) * outward < 0)
        std::swap(b, c);
      for (const dealii::Point<3> *p :
           std::array<const dealii::Point<3> *, 3>{{&a, &b, &c}})
        for (unsigned int d = 0; d < 3; ++d)
          local.push_back((*p)[d]);
    };
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == id)
            {
              const auto face    = cell->face(f);
              const auto outward = face->center() - cell->center();
              if (face->n_vertices() == 3)
                add(face->vertex(0), face->vertex(1), face->vertex(2), outward);
              else
                {
                  // deal.II numbers a quadrilateral's vertices
                  // lexicographically: the cycle is 0, 1, 3, 2.
                  add(face->vertex(0),
                      face->vertex(1),
                      face->vertex(3),
                      outward);
                  add(face->vertex(0),
                      face->vertex(3),
                      face->vertex(2),
                      outward);
                }
            }
    std::vector<std::array<dealii::Point<3>, 3>> triangles;
    for (const auto &from_rank :
         dealii::Utilities::MPI::all_gather(comm, local))
      for (unsigned int i = 0; i + 9 <= from_rank.size(); i += 9)
        triangles.push_back(
          {{dealii::Point<3>(from_rank[i], from_rank[i + 1], from_rank[i + 2]),
            dealii::Point<3>(from_rank[i + 3],
                             from_rank[i + 4],
                             from_rank[i + 5]),
            dealii::Point<3>(from_rank[i + 6],
                             from_rank[i + 7],
                             from_rank[i + 8])}});
    return TriangleSurface(std::move(triangles));
  }


  dealii::Point<3>
  closest_point_on_triangle(const dealii::Point<3>                &p,
                            const std::array<dealii::Point<3>, 3> &t)
  {
    const auto  &a = t[0], &b = t[1], &c = t[2];
    const auto   ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab * ap, d2 = ac * ap;
    if (d1 <= 0 && d2 <= 0)
      return a;
    const auto   bp = p - b;
    const double d3 = ab * bp, d4 = ac * bp;
    if (d3 >= 0 && d4 <= d3)
      return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
      return a + d1 / (d1 - d3) * ab;
    const auto   cp = p - c;
    const double d5 = ab * cp, d6 = ac * cp;
    if (d6 >= 0 && d5 <= d6)
      return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
      return a + d2 / (d2 - d6) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
      return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
    const double denominator = 1 / (va + vb + vc);
    return a + vb * denominator * ab + vc * denominator * ac;
  }


  TriangleSurface::Projection
  TriangleSurface::project(const dealii::Point<3> &p) const
  {
    AssertThrow(!triangles.empty(),
                dealii::ExcMessage("Purkinje: the surface has no faces."));
    namespace bgi           = boost::geometry::index;
    const auto box_distance = [&](const dealii::BoundingBox<3> &box) {
      double d2 = 0;
      for (unsigned int d = 0; d < 3; ++d)
        {
          const double below = box.get_boundary_points().first[d] - p[d];
          const double above = p[d] - box.get_boundary_points().second[d];
          const double gap   = std::max({below, above, 0.0});
          d2 += gap * gap;
        }
      return std::sqrt(d2);
    };
    // The k nearest boxes, k doubled until the best triangle found is
    // nearer than the farthest of them (the boxes not returned are no
    // nearer than that one, and a triangle is never nearer than its box).
    const unsigned int      n    = triangles.size();
    double                  best = std::numeric_limits<double>::infinity();
    unsigned int            best_triangle = 0;
    dealii::Point<3>        best_point;
    std::vector<Index::Box> found;
    for (unsigned int k = std::min(8u, n);; k = std::min(2 * k, n))
      {
        found.clear();
        index->tree.query(bgi::nearest(p, k), std::back_inserter(found));
        double farthest = 0;
        for (const auto &[box, t] : found)
          {
            farthest       = std::max(farthest, box_distance(box));
            const auto   q = closest_point_on_triangle(p, triangles[t]);
            const double d = p.distance(q);
            if (d < best || (d == best && t < best_triangle))
              {
                best          = d;
                best_triangle = t;
                best_point    = q;
              }
          }
        if (k == n || best < farthest)
          break;
      }
    const auto &tri = triangles[best_triangle];
    auto normal = dealii::cross_product_3d(tri[1] - tri[0], tri[2] - tri[0]);
    normal /= normal.norm();
    return {best_point, normal, best};
  }


  // --- PurkinjeTree ---

  namespace
  {
    /// @p direction in the plane normal to the unit @p normal, turned by
    /// @p degrees about it, unit length (zero if @p direction is normal to
    /// the plane).
    dealii::Tensor<1, 3>
    turn(const dealii::Tensor<1, 3> &direction,
         const dealii::Tensor<1, 3> &normal,
         const double                degrees)
    {
      auto         t    = direction - (direction * normal) * normal;
      const double norm = t.norm();
      if (!(norm > 1e-12 * direction.norm()))
        return dealii::Tensor<1, 3>();
      t /= norm;
      const double angle = degrees * M_PI / 180;
      return std::cos(angle) * t +
             std::sin(angle) * dealii::cross_product_3d(normal, t);
    }

    /// Uniform numbers in (0, 1) from a std::mt19937, mapped by hand (the
    /// std distributions may differ between standard libraries; the
    /// engine's output is fixed by the standard).
    class Uniform
    {
    public:
      explicit Uniform(const std::uint_fast32_t seed)
        : engine(seed)
      {}

      double
      operator()()
      {
        return (static_cast<double>(engine() & 0xffffffffUL) + 0.5) /
               4294967296.0;
      }

      /// Uniform in (1 - v, 1 + v).
      double
      factor(const double v)
      {
        return 1 + v * (2 * (*this)() - 1);
      }

    private:
      std::mt19937 engine;
    };
  } // namespace


  double
  junction_height(const PurkinjeParameters &params, const dealii::Point<3> &x)
  {
    const dealii::Tensor<1, 3> axis = params.base - params.apex;
    return (x - params.apex) * axis / axis.norm_square();
  }


  PurkinjeTree::PurkinjeTree(const TriangleSurface    &surface,
                             const PurkinjeParameters &params)
    : surface(surface)
    , params(params)
  {
    const auto his = surface.project(params.his_point);
    AssertThrow(his.distance <= 2 * params.segment_length,
                dealii::ExcMessage(
                  entry_name("His point") + " (" + to_text(params.his_point) +
                  ") lies " + std::to_string(his.distance) +
                  " mm from the Surface '" + params.surface +
                  "' (its nearest point is " + to_text(his.point) +
                  "); it must lie within two Segment lengths (" +
                  std::to_string(2 * params.segment_length) +
                  " mm) of it: move it onto the endocardium."));
    node_positions.push_back(his.point);
    node_normal.push_back(his.normal);
    node_branch.push_back(0);

    unsigned int           n_branches = 0;
    const auto             bundle     = grow_branch(0,
                                    params.initial_direction,
                                    params.his_length,
                                    n_branches++,
                                    false);
    std::vector<BranchEnd> front;
    for (unsigned int f = 0; f < params.fascicle_angles.size(); ++f)
      {
        const auto direction = turn(bundle.direction,
                                    node_normal[bundle.node],
                                    params.fascicle_angles[f]);
        const auto end       = grow_branch(bundle.node,
                                     direction,
                                     params.fascicle_lengths[f],
                                     n_branches++,
                                     false);
        if (end.complete)
          front.push_back(end);
      }
    Uniform uniform(params.seed);
    for (unsigned int g = 0; g < params.generations; ++g)
      {
        std::vector<BranchEnd> next;
        for (const auto &end : front)
          for (const double side : {-1.0, 1.0})
            {
              const double angle =
                side * params.branch_angle * uniform.factor(params.variation);
              const double length =
                params.branch_length * uniform.factor(params.variation);
              const auto branch =
                grow_branch(end.node,
                            turn(end.direction, node_normal[end.node], angle),
                            length,
                            n_branches++,
                            true);
              if (branch.complete)
                next.push_back(branch);
            }
        front = std::move(next);
      }

    std::vector<unsigned int> degree(node_positions.size(), 0);
    for (const auto &[a, b] : edge_list)
      {
        ++degree[a];
        ++degree[b];
      }
    for (unsigned int i = 1; i < degree.size(); ++i)
      if (degree[i] == 1 && junction_height(params, node_positions[i]) <=
                              params.junction_height_limit)
        junction_nodes.push_back(i);
  }


  PurkinjeTree::BranchEnd
  PurkinjeTree::grow_branch(const unsigned int          start,
                            const dealii::Tensor<1, 3> &direction,
                            const double                length,
                            const unsigned int          branch,
                            const bool                  limited)
  {
    const unsigned int n_segments =
      std::max<long>(1, std::lround(length / params.segment_length));
    const double         step_length = length / n_segments;
    unsigned int         current     = start;
    dealii::Tensor<1, 3> d           = direction;
    for (unsigned int s = 0; s < n_segments; ++s)
      {
        const auto t = turn(d, node_normal[current], 0);
        if (t.norm() == 0)
          return {current, d, false};
        const auto &x    = node_positions[current];
        const auto  next = surface.project(x + step_length * t);
        const auto  step = next.point - x;
        // The surface ends (or folds back): the branch ends.
        if (step.norm() < 0.5 * step_length)
          return {current, d, false};
        if (s > 0 && too_close(next.point, branch))
          return {current, d, false};
        if (limited &&
            junction_height(params, next.point) > params.junction_height_limit)
          return {current, d, false};
        node_positions.push_back(next.point);
        node_normal.push_back(next.normal);
        node_branch.push_back(branch);
        edge_list.emplace_back(current, node_positions.size() - 1);
        current = node_positions.size() - 1;
        d       = step / step.norm();
      }
    return {current, d, true};
  }


  bool
  PurkinjeTree::too_close(const dealii::Point<3> &p,
                          const unsigned int      branch) const
  {
    const double limit2 = params.minimum_distance * params.minimum_distance;
    for (unsigned int i = 0; i < node_positions.size(); ++i)
      if (node_branch[i] != branch &&
          (node_positions[i] - p).norm_square() < limit2)
        return true;
    return false;
  }


  double
  PurkinjeTree::total_length() const
  {
    double length = 0;
    for (const auto &[a, b] : edge_list)
      length += node_positions[a].distance(node_positions[b]);
    return length;
  }


  std::vector<double>
  purkinje_activation_times(const PurkinjeTree &tree,
                            const double        velocity,
                            const double        his_time)
  {
    const auto        &nodes = tree.nodes();
    const unsigned int n     = nodes.size();
    std::vector<std::vector<std::pair<unsigned int, double>>> neighbours(n);
    for (const auto &[a, b] : tree.edges())
      {
        const double dt = nodes[a].distance(nodes[b]) / velocity;
        neighbours[a].emplace_back(b, dt);
        neighbours[b].emplace_back(a, dt);
      }
    std::vector<double> times(n, std::numeric_limits<double>::infinity());
    using Entry = std::pair<double, unsigned int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    times[0] = his_time;
    heap.emplace(his_time, 0);
    while (!heap.empty())
      {
        const auto [t, i] = heap.top();
        heap.pop();
        if (t > times[i])
          continue;
        for (const auto &[j, dt] : neighbours[i])
          if (t + dt < times[j])
            {
              times[j] = t + dt;
              heap.emplace(times[j], j);
            }
      }
    return times;
  }


  PurkinjeNetwork
  build_purkinje_network(const TriangleSurface    &surface,
                         const PurkinjeParameters &params,
                         const double              his_time)
  {
    const PurkinjeTree tree(surface, params);
    PurkinjeNetwork    network;
    network.nodes     = tree.nodes();
    network.edges     = tree.edges();
    network.junctions = tree.junctions();
    network.times = purkinje_activation_times(tree, params.velocity, his_time);
    network.junction_delay = params.junction_delay;
    return network;
  }


  PurkinjeNetwork
  merge(const PurkinjeNetwork &a, const PurkinjeNetwork &b)
  {
    PurkinjeNetwork    merged = a;
    const unsigned int offset = a.nodes.size();
    merged.nodes.insert(merged.nodes.end(), b.nodes.begin(), b.nodes.end());
    merged.times.insert(merged.times.end(), b.times.begin(), b.times.end());
    for (const auto &[i, j] : b.edges)
      merged.edges.emplace_back(i + offset, j + offset);
    for (const unsigned int j : b.junctions)
      merged.junctions.push_back(j + offset);
    return merged;
  }


  namespace
  {
    /// Per junction of @p network: the distance to the nearest of the
    /// nodes at @p positions over all ranks, and on this rank the nearest
    /// local node if it is that one (else an invalid index).
    std::pair<std::vector<double>, std::vector<unsigned int>>
    nearest_nodes(const PurkinjeNetwork               &network,
                  const std::vector<dealii::Point<3>> &positions,
                  const MPI_Comm                       comm)
    {
      namespace bgi = boost::geometry::index;
      std::vector<std::pair<dealii::Point<3>, unsigned int>> indexed;
      for (unsigned int i = 0; i < positions.size(); ++i)
        indexed.emplace_back(positions[i], i);
      const auto                tree        = dealii::pack_rtree(indexed);
      const unsigned int        n_junctions = network.junctions.size();
      std::vector<double>       distance(n_junctions,
                                   std::numeric_limits<double>::infinity());
      std::vector<unsigned int> nearest(n_junctions,
                                        dealii::numbers::invalid_unsigned_int);
      for (unsigned int j = 0; j < n_junctions; ++j)
        {
          const auto &p = network.nodes[network.junctions[j]];
          std::vector<std::pair<dealii::Point<3>, unsigned int>> found;
          tree.query(bgi::nearest(p, 1), std::back_inserter(found));
          if (!found.empty())
            {
              distance[j] = p.distance(found.front().first);
              nearest[j]  = found.front().second;
            }
        }
      std::vector<double> global(n_junctions);
      MPI_Allreduce(distance.data(),
                    global.data(),
                    n_junctions,
                    MPI_DOUBLE,
                    MPI_MIN,
                    comm);
      for (unsigned int j = 0; j < n_junctions; ++j)
        if (!(distance[j] == global[j] && std::isfinite(distance[j])))
          nearest[j] = dealii::numbers::invalid_unsigned_int;
      return {global, nearest};
    }
  } // namespace


  void
  add_junction_sources(const PurkinjeNetwork               &network,
                       const std::vector<dealii::Point<3>> &positions,
                       std::vector<double>                 &initial,
                       const MPI_Comm                       comm)
  {
    // The rank(s) holding the nearest node set its time.
    const auto nearest = nearest_nodes(network, positions, comm).second;
    for (unsigned int j = 0; j < nearest.size(); ++j)
      if (nearest[j] != dealii::numbers::invalid_unsigned_int)
        initial[nearest[j]] = std::min(initial[nearest[j]],
                                       network.times[network.junctions[j]] +
                                         network.junction_delay);
  }


  std::vector<Stimulus>
  junction_stimuli(const PurkinjeNetwork               &network,
                   const std::vector<dealii::Point<3>> &positions,
                   const Stimulus                      &pulse,
                   const MPI_Comm                       comm)
  {
    const auto distance = nearest_nodes(network, positions, comm).first;
    std::vector<Stimulus> stimuli;
    for (unsigned int j = 0; j < network.junctions.size(); ++j)
      {
        Stimulus s;
        s.name          = "junction " + std::to_string(j);
        s.region.shape  = StimulusRegion::Shape::sphere;
        s.region.centre = network.nodes[network.junctions[j]];
        // A little over the nearest node's distance: it lies inside.
        s.region.radius =
          std::max(pulse.region.radius, distance[j] * (1 + 1e-9) + 1e-12);
        s.start = network.times[network.junctions[j]] + network.junction_delay;
        s.duration  = pulse.duration;
        s.amplitude = pulse.amplitude;
        stimuli.push_back(s);
      }
    return stimuli;
  }
} // namespace systole::Electrophysiology
