#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/la_parallel_vector.h>

#include "electrophysiology/parameters.h"
#include "fibres/fibre_field.h"
#include "geometry/boundary_names.h"

#include <mpi.h>

#include <string>
#include <vector>

namespace systole::Electrophysiology
{
  /// Counters of the last EikonalSolver::solve().
  struct EikonalStatistics
  {
    unsigned long local_updates = 0; ///< node updates tried, summed
    unsigned int  rounds        = 0; ///< ghost exchanges until no change
    double        seconds       = 0; ///< wall time of solve()
  };

  /// Activation times T at the nodes of a first-order Lagrange DoFHandler
  /// (Q1 on hexahedra, P1 on tetrahedra: the nodes are the vertices) from
  /// the anisotropic eikonal equation
  /// @f[ \sqrt{\nabla T\cdot V\,\nabla T} = 1,\qquad
  ///     V = v_f^2\, f\otimes f + v_s^2\, s\otimes s + v_n^2\, n\otimes n, @f]
  /// with the fibre frame (f, s, n) of each cell taken at its centre
  /// (constant per cell) and given start times at source nodes. Its
  /// viscosity solution is the first arrival time
  /// T(x) = min over sources y and paths of t(y) + the length of the path in
  /// the metric V^{-1}; from a point source in a homogeneous block the
  /// fronts are the ellipsoids (x - y)·V^{-1}(x - y) = (T - t(y))².
  ///
  /// Discretization: at every node i and each cell K around it,
  /// @f[ T_i = \min_{p \in F_i(K)} \; T_h(p) + \|x_i - p\|_{V_K^{-1}}, @f]
  /// the local solver of the fast iterative method on tetrahedra (Fu, Kirby
  /// and Whitaker 2013, SIAM J. Sci. Comput. 35(5)): T_h is the linear
  /// interpolant of the nodal times on the triangles of F_i(K), the part of
  /// the cell's boundary facing away from i: on a tetrahedron its opposite
  /// face; on a hexahedron its three far faces, each cut into the four
  /// triangles of its four vertices (both diagonals, so that neither
  /// diagonal is preferred). The minimum of this convex function over a
  /// triangle is found in closed form (its stationary point if inside, else
  /// the same on the edges, else the vertices). The scheme is exact for
  /// planar fronts and first order in h for curved ones (the analytic test:
  /// tests/unit/electrophysiology/eikonal_test.cc).
  ///
  /// Algorithm, and why: the fast iterative method (an active list of nodes
  /// that are updated until they stop changing, Jeong and Whitaker 2008; Fu
  /// et al. 2013), with the active list kept as a heap ordered by time, so
  /// that nodes are mostly updated in the order of arrival and are final
  /// after one or two updates, as in fast marching. Unlike fast marching it
  /// needs no causality of the local solver: strong anisotropy and obtuse
  /// or distorted cells only cause re-updates, not wrong times. And it
  /// parallelises as a global fixed-point iteration: each rank runs the
  /// list on its owned nodes (the ghost values fixed), then the owned
  /// values go to the other ranks' ghosts, and the ghosts that decreased
  /// re-open the list, until no value changes anywhere. The update is
  /// monotone (non-decreasing in every neighbour's time), so from T = +inf
  /// off the sources any order of updates converges to the same (the
  /// largest) fixed point of the discrete equations: the result does not
  /// depend on the partition or the number of ranks (to round-off; 1, 2 and
  /// 3 ranks agree to 1e-12 ms in tests/mpi/electrophysiology/eikonal_test.cc).
  /// Fast sweeping would need structured orderings, and fast marching a
  /// sequential global heap.
  class EikonalSolver
  {
  public:
    /// @param[in] dofs a Q1 (hexahedra) or P1 (tetrahedra) scalar
    ///            DoFHandler on a distributed mesh (kept by reference)
    /// @param[in] fibres the fibre frame, evaluated once at the centre of
    ///            every locally owned cell
    /// @param[in] names boundary parts (the fast endocardial layer)
    EikonalSolver(const dealii::DoFHandler<3>   &dofs,
                  const Fibres::FibreField      &fibres,
                  const Geometry::BoundaryNames &names,
                  const EikonalSettings         &settings);

    /// Solve from @p initial: per locally owned node (in the order of
    /// locally_owned_dofs()) its source time [ms], or +inf where it is not
    /// a source. Collective.
    void
    solve(const std::vector<double> &initial);

    /// The activation times of the locally owned nodes [ms] (+inf where no
    /// source reaches).
    const std::vector<double> &
    owned_times() const
    {
      return owned;
    }

    /// Positions of the locally owned nodes [mm].
    const std::vector<dealii::Point<3>> &
    owned_positions() const
    {
      return owned_position;
    }

    const EikonalStatistics &
    statistics() const
    {
      return stats;
    }

  private:
    const dealii::DoFHandler<3> &dofs;
    MPI_Comm                     comm;
    dealii::IndexSet             locally_owned, locally_relevant;
    unsigned int                 n_owned;
    /// Owned nodes first, then the ghosts (the vector's local numbering).
    dealii::LinearAlgebra::distributed::Vector<double> times;
    std::vector<dealii::Point<3>>                      position; ///< local
    std::vector<dealii::Point<3>>                      owned_position;
    /// The owned and ghost cells: their nodes (local numbers) and metric
    /// V^{-1}.
    unsigned int                               nodes_per_cell;
    std::vector<unsigned int>                  cell_nodes;
    std::vector<dealii::SymmetricTensor<2, 3>> cell_metric;
    std::vector<unsigned int>                  node_cells_start;
    std::vector<unsigned int>                  node_cells;
    std::vector<double>                        owned;
    EikonalStatistics                          stats;

    /// The update of the node at local vertex @p vertex of cell @p c from
    /// the far triangles that hold local vertex @p changed (the others did
    /// not change since they were last used).
    double
    update(const unsigned int c,
           const unsigned int vertex,
           const unsigned int changed) const;
  };

  /// min over the simplex of the @p n points @p y (n = 1, 2, 3) of
  /// T_h(p) + sqrt((x - p)·A(x - p)), T_h the linear interpolant of @p T
  /// (finite) on it. Exposed for the tests.
  double
  eikonal_simplex_update(const dealii::SymmetricTensor<2, 3> &A,
                         const dealii::Point<3>              &x,
                         const dealii::Point<3>              *y[],
                         const double                        *T,
                         const unsigned int                   n);
} // namespace systole::Electrophysiology
