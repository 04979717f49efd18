#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace systole::Fibres
{
  /// One scalar problem -Laplace u = source on the mesh, with Dirichlet values
  /// on some boundary parts and zero flux on the others.
  struct LaplaceProblem
  {
    std::string                                  name; ///< for messages
    std::map<dealii::types::boundary_id, double> dirichlet;
    double                                       source = 0.0;
  };

  /// The value and gradient of one field at one point.
  struct FieldValue
  {
    double               value = 0.0;
    dealii::Tensor<1, 3> gradient;
  };

  /// Several scalar Laplace/Poisson problems on one mesh, solved with Q<degree>
  /// elements (MappingQ2, PETSc CG preconditioned by BoomerAMG, MUMPS if CG
  /// breaks down on a tangled mesh), and their values and gradients at points
  /// of the locally owned cells: the coordinates of the rule-based fibre
  /// generators (biventricular.h). Keeps @p tria by reference. Collective.
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
    /// the locally owned cell @p cell: values[k][i] is field k at point i.
    /// Points slightly outside the cell (another mapping) are projected onto
    /// it.
    void
    evaluate(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
             const std::vector<dealii::Point<3>>                     &points,
             std::vector<std::vector<FieldValue>> &values) const;

    unsigned long long
    n_dofs() const;
    /// CG iterations of each solve (0 where MUMPS solved).
    const std::vector<unsigned int> &
    iterations() const;
    /// Cells with a non-positive Jacobian at a Gauss point.
    unsigned int
    n_tangled_cells() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Fibres
