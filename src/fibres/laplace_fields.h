#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace systole::Fibres
{
  /// Wall-clock seconds since @p start (the timings of the fibre generators'
  /// reports).
  double
  seconds_since(const std::chrono::steady_clock::time_point start);

  /// One scalar problem -Laplace u = source on the mesh, with Dirichlet values
  /// on some boundary parts (and, optionally, at single mesh vertices) and
  /// zero flux on the others.
  struct LaplaceProblem
  {
    std::string                                  name; ///< for messages
    std::map<dealii::types::boundary_id, double> dirichlet;
    double                                       source = 0.0;
    /// Dirichlet values at mesh vertices (e.g. Bayer's psi = 0 at the apex):
    /// the vertex within 1e-10 of the mesh diameter of each point [mm]. A
    /// point condition is singular in 3D (the gradient near it is poorly
    /// resolved).
    std::vector<std::pair<dealii::Point<3>, double>> vertex_values = {};
  };

  /// The value and gradient of one field at one point.
  struct FieldValue
  {
    double               value = 0.0;
    dealii::Tensor<1, 3> gradient;
  };

  /// Several scalar Laplace/Poisson problems on one mesh, and their values
  /// and gradients at points of the locally owned cells: the coordinates of
  /// the rule-based fibre generators (rule_based.h, biventricular.h,
  /// arostica.h). The one Laplace solver of src/fibres/.
  ///
  /// Works on hexahedral and tetrahedral meshes alike: Geometry::CellKind
  /// picks the continuous Lagrange element of degree @p degree (Q_k or P_k),
  /// the Gauss rule with degree + 1 points per direction and the mapping of
  /// degree 2 (MappingQCache following the manifolds on hexahedra, affine on
  /// the flat-faceted tetrahedra). Each problem is solved with PETSc CG
  /// preconditioned by BoomerAMG, or by MUMPS if CG breaks down (an
  /// indefinite matrix: tangled cells). Keeps @p tria by reference: it must
  /// not outlive the mesh, and the mesh must not be refined meanwhile.
  /// Collective.
  class LaplaceFields
  {
  public:
    LaplaceFields(const dealii::Triangulation<3, 3> &tria,
                  const unsigned int                 degree,
                  const std::vector<LaplaceProblem> &problems);
    ~LaplaceFields();

    unsigned int
    n_fields() const;

    /// Replace field @p k by a u + b (owned and ghost values).
    void
    scale(const unsigned int k, const double a, const double b);

    /// The largest value of field @p k (over all ranks) and a point where
    /// it is attained (a support point). Collective.
    std::pair<double, dealii::Point<3>>
    maximum(const unsigned int k) const;

    /// Values and gradients of every field at the real points @p points of
    /// the locally owned (or ghost) cell @p cell: values[k][i] is field k at
    /// point i. Points a little outside the cell (another mapping) are
    /// projected onto the reference cell (hexahedra: each coordinate clamped
    /// to [0, 1]; tetrahedra: negative barycentric coordinates set to 0 and
    /// the others rescaled to sum 1); points the inverse mapping cannot
    /// place (in a tangled cell) take the nearest of a lattice of reference
    /// points (5 x 5 x 5 on a hexahedron, the 35 with i + j + k <= 4 on a
    /// tetrahedron). Throws if a point is farther than the cell's diameter
    /// from it.
    void
    evaluate(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
             const std::vector<dealii::Point<3>>                     &points,
             std::vector<std::vector<FieldValue>> &values) const;

    /// One result per point: @p out[i] = @p at(values, i) with the values
    /// of evaluate() at the points @p points of @p cell.
    template <class T, class At>
    void
    evaluate_each(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
                  const std::vector<dealii::Point<3>> &points,
                  std::vector<T>                      &out,
                  const At                            &at) const
    {
      std::vector<std::vector<FieldValue>> values;
      evaluate(cell, points, values);
      out.resize(points.size());
      for (unsigned int i = 0; i < points.size(); ++i)
        out[i] = at(values, i);
    }

    /// "Q2", "P1", ...: the element, for reports.
    std::string
    element_name() const;
    unsigned long long
    n_dofs() const;
    /// CG iterations of each solve (0 where MUMPS solved).
    const std::vector<unsigned int> &
    iterations() const;
    /// Whether each solve needed MUMPS (CG + AMG broke down).
    const std::vector<bool> &
    direct() const;
    /// Wall time of each solve (assembly, AMG set-up and solve) [s].
    const std::vector<double> &
    solve_seconds() const;
    /// Wall time of the DoF distribution and the tangled-cell count [s].
    double
    setup_seconds() const;
    /// Cells with a non-positive Jacobian at a Gauss point.
    unsigned int
    n_tangled_cells() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Fibres
