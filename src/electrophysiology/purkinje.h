#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "electrophysiology/stimulus.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

/// @file
/// A Purkinje network: a fractal tree grown on the endocardial surface
/// (PurkinjeTree), the conduction along it (purkinje_activation_times) and
/// its junctions with the muscle (purkinje_junctions).

namespace systole::Electrophysiology
{
  /// Subsection "Electrophysiology / Purkinje": the tree and its
  /// conduction. Lengths in mm, angles in degrees, times in ms. The
  /// defaults are those of declare(): a tree for the default LV.
  struct PurkinjeParameters
  {
    bool enabled = false; ///< grow the tree and activate through it
    /// Boundary part the tree grows on (the endocardium).
    std::string surface = "endocardium";
    /// Entry of the His bundle on the surface [mm] (projected onto it).
    dealii::Point<3> his_point{22.9, 0, -5};
    /// Direction of the His bundle (projected onto the surface's tangent
    /// plane at the His point) [-].
    dealii::Tensor<1, 3> initial_direction{{0, 0, -1}};
    double               his_length = 8; ///< the bundle's length [mm]
    std::vector<double>  fascicle_angles{-80, 0, 80}; ///< from the bundle [deg]
    std::vector<double>  fascicle_lengths{20, 20, 20}; ///< one per angle [mm]
    double               segment_length = 1;           ///< [mm]
    double               branch_length  = 5;           ///< mean [mm]
    double               branch_angle   = 30; ///< each side of a fork [deg]
    /// Relative spread of the branch lengths and angles: each drawn
    /// uniformly in (1 ± variation) times its mean [-].
    double       variation   = 0.3;
    unsigned int generations = 10; ///< forks after the fascicles
    /// A new node closer than this to a node of another branch stops its
    /// branch [mm].
    double minimum_distance = 0.9;
    /// The long axis: the endocardial apex and a point of the base plane
    /// [mm], for the Junction height limit.
    dealii::Point<3> apex{0, 0, -84};
    dealii::Point<3> base{0, 0, 5};
    /// Largest relative height (x − apex)·(base − apex)/|base − apex|² of a
    /// junction; the branches after the fascicles do not grow above it
    /// (junction_height()) [-]; 1: no limit below the base.
    double             junction_height_limit = 1;
    double             velocity       = 3;    ///< conduction velocity [mm/ms]
    double             junction_delay = 5;    ///< Purkinje-muscle delay [ms]
    std::uint_fast32_t seed           = 1234; ///< of the std::mt19937
    /// Model = monodomain: radius of the stimulus at each junction [mm].
    double junction_radius = 1.5;

    /// Subsection "Right bundle": a second tree, the right bundle branch,
    /// on its own surface (biventricular meshes), from its own His point
    /// (the His entry on the septum's right side: activated at the same
    /// time as the left one), with the branching settings above and the
    /// seed + 1.
    struct RightBundle
    {
      std::string          surface; ///< boundary part; empty: no right tree
      dealii::Point<3>     his_point;
      dealii::Tensor<1, 3> initial_direction{{0, 0, -1}};
      double               his_length = 8;       ///< [mm]
      std::vector<double>  fascicle_angles{0};   ///< [deg]
      std::vector<double>  fascicle_lengths{20}; ///< [mm]
    } right;

    /// The parameters of the right bundle's tree: these with the bundle,
    /// His point, direction and fascicles of #right, the seed + 1.
    PurkinjeParameters
    right_bundle() const;

    /// Declares subsection "Purkinje" (inside "Electrophysiology": call
    /// with the handler entered there).
    static void
    declare(dealii::ParameterHandler &prm);
    /// Reads "Electrophysiology / Purkinje" (@p prm entered nowhere) and
    /// validates it.
    static PurkinjeParameters
    parse(const dealii::ParameterHandler &prm);
  };

  /// A triangulated surface (the boundary faces of a boundary part, each
  /// quadrilateral cut into two triangles), the same on every rank, with
  /// closest-point queries.
  class TriangleSurface
  {
  public:
    /// The closest point of the surface to a point.
    struct Projection
    {
      dealii::Point<3>     point;
      dealii::Tensor<1, 3> normal;   ///< unit, of the triangle (outward)
      double               distance; ///< [mm]
    };

    /// From triangles (three vertices each, ordered so that the normal
    /// (b - a) x (c - a) points outward); sorted so that the result does
    /// not depend on the order given.
    explicit TriangleSurface(
      std::vector<std::array<dealii::Point<3>, 3>> triangles);
    TriangleSurface(TriangleSurface &&) noexcept;
    ~TriangleSurface();

    /// The faces with boundary id @p id of the locally owned cells of
    /// @p tria (its vertices: Q1/P1 geometry), gathered from all ranks.
    /// Collective.
    static TriangleSurface
    gather(const dealii::Triangulation<3, 3> &tria,
           const dealii::types::boundary_id   id,
           const MPI_Comm                     comm);

    /// Closest point of the surface to @p p (ties: the first triangle in
    /// the sorted order). Throws on an empty surface.
    Projection
    project(const dealii::Point<3> &p) const;

    unsigned int
    n_triangles() const
    {
      return triangles.size();
    }

  private:
    std::vector<std::array<dealii::Point<3>, 3>> triangles;
    /// An R-tree of the triangles' bounding boxes (purkinje.cc).
    struct Index;
    std::unique_ptr<Index> index;
  };

  /// The relative height of @p x along the long axis of @p params: 0 at
  /// the apex, 1 in the base plane.
  double
  junction_height(const PurkinjeParameters &params, const dealii::Point<3> &x);

  /// Closest point of the triangle @p t to @p p (Ericson 2005, Real-Time
  /// Collision Detection, 5.1.5).
  dealii::Point<3>
  closest_point_on_triangle(const dealii::Point<3>                &p,
                            const std::array<dealii::Point<3>, 3> &t);

  /// A Purkinje tree on a surface: a fractal tree grown from the His entry
  /// (Ijiri et al. 2008, Sahli Costabal et al. 2016, J Biomech 49(12)). The
  /// His bundle runs from the His point along the initial direction; at its
  /// end the fascicles leave at their angles; each fascicle's end forks
  /// into two branches at ± the branch angle, and so on for the given
  /// generations. Every branch is a chain of segments: each new node is the
  /// last one moved by a segment length along the branch's direction (kept
  /// in the surface's tangent plane), projected onto the surface (closest
  /// point). A branch stops where a new node would come within the
  /// minimum distance of another branch's node (not checked for a
  /// branch's first segment, which starts next to its sibling), or where
  /// the surface ends (the step shrinks below half a segment), and a
  /// branch after the fascicles stops where a new node would lie above the
  /// Junction height limit (the network covers the apical part; the bundle
  /// and fascicles, insulated, may cross the base). Only branches that
  /// reached their full length fork. The junctions are the terminal nodes
  /// at or below the limit.
  /// Branch lengths and angles vary by a seeded std::mt19937 mapped to
  /// uniform numbers by hand (the same tree on every platform and rank).
  class PurkinjeTree
  {
  public:
    /// Grow the tree of @p params on @p surface. Throws if the His point
    /// lies more than two segment lengths from the surface.
    PurkinjeTree(const TriangleSurface    &surface,
                 const PurkinjeParameters &params);

    /// Node positions [mm]; node 0 is the His entry.
    const std::vector<dealii::Point<3>> &
    nodes() const
    {
      return node_positions;
    }

    /// Edges (parent, child), the parent always the earlier node.
    const std::vector<std::pair<unsigned int, unsigned int>> &
    edges() const
    {
      return edge_list;
    }

    /// The Purkinje-muscle junctions: the terminal nodes (one edge, not
    /// the His entry) at or below the Junction height limit, ascending.
    const std::vector<unsigned int> &
    junctions() const
    {
      return junction_nodes;
    }

    /// Sum of the edge lengths [mm].
    double
    total_length() const;

  private:
    const TriangleSurface            &surface;
    const PurkinjeParameters         &params;
    std::vector<dealii::Point<3>>     node_positions;
    std::vector<unsigned int>         node_branch; ///< the branch of each node
    std::vector<dealii::Tensor<1, 3>> node_normal;
    std::vector<std::pair<unsigned int, unsigned int>> edge_list;
    std::vector<unsigned int>                          junction_nodes;

    /// The end of a branch: its last node, the direction it arrived in,
    /// and whether it reached its full length.
    struct BranchEnd
    {
      unsigned int         node;
      dealii::Tensor<1, 3> direction;
      bool                 complete;
    };

    /// Grow branch number @p branch from node @p start along @p direction
    /// for @p length; if @p limited, not above the Junction height limit.
    BranchEnd
    grow_branch(const unsigned int          start,
                const dealii::Tensor<1, 3> &direction,
                const double                length,
                const unsigned int          branch,
                const bool                  limited);

    /// Whether @p p lies within the minimum distance of a node of another
    /// branch than @p branch.
    bool
    too_close(const dealii::Point<3> &p, const unsigned int branch) const;
  };

  /// Activation time of every node of @p tree [ms]: the shortest path from
  /// the His entry (time @p his_time) along the edges at @p velocity
  /// [mm/ms] (Dijkstra).
  std::vector<double>
  purkinje_activation_times(const PurkinjeTree &tree,
                            const double        velocity,
                            const double        his_time);

  /// The tree and its activation, as the myocardium sees it.
  struct PurkinjeNetwork
  {
    std::vector<dealii::Point<3>>                      nodes;
    std::vector<std::pair<unsigned int, unsigned int>> edges;
    std::vector<unsigned int>                          junctions;
    std::vector<double> times;              ///< activation of each node [ms]
    double              junction_delay = 0; ///< [ms]

    bool
    empty() const
    {
      return nodes.empty();
    }
  };

  /// Grow the tree of @p params on @p surface and activate it from the His
  /// entry at @p his_time [ms].
  PurkinjeNetwork
  build_purkinje_network(const TriangleSurface    &surface,
                         const PurkinjeParameters &params,
                         const double              his_time);

  /// @p a and @p b as one network (the nodes of @p b numbered after those
  /// of @p a).
  PurkinjeNetwork
  merge(const PurkinjeNetwork &a, const PurkinjeNetwork &b);

  /// The junctions of @p network as stimuli of the monodomain model: per
  /// junction a sphere around it of the radius of @p pulse's region [mm],
  /// widened to reach the nearest of the nodes at @p positions (the locally
  /// owned ones of each rank; nearest over all ranks), on from the
  /// junction's time plus the delay for @p pulse's duration [ms] at its
  /// amplitude [µA/mm³] (the rest of @p pulse unused). Collective.
  std::vector<Stimulus>
  junction_stimuli(const PurkinjeNetwork               &network,
                   const std::vector<dealii::Point<3>> &positions,
                   const Stimulus                      &pulse,
                   const MPI_Comm                       comm);

  /// The junctions of @p network as sources of the myocardial eikonal
  /// solve: the node nearest to each junction (of the nodes at
  /// @p positions, the locally owned ones of each rank; nearest over all
  /// ranks) gets the junction's time plus the junction delay, or keeps its
  /// time in @p initial if that is earlier. Collective.
  void
  add_junction_sources(const PurkinjeNetwork               &network,
                       const std::vector<dealii::Point<3>> &positions,
                       std::vector<double>                 &initial,
                       const MPI_Comm                       comm);
} // namespace systole::Electrophysiology
