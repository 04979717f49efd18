#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/tria.h>

#include <memory>
#include <string>

namespace systole::Geometry
{
  /// The cell shape of a mesh (all hexahedra or all tetrahedra) and the one
  /// place that picks the finite elements, quadratures and mappings that fit
  /// it, so that physics code never asks which cell type it has.
  ///
  /// | what                  | hexahedra              | tetrahedra |
  /// |-----------------------|------------------------|------------------------|
  /// | continuous degree k   | FE_Q(k)                | FE_SimplexP(k) | |
  /// discontinuous k       | FE_DGP(k)              | FE_SimplexDGP(k)       |
  /// | cell rule, n points   | QGauss(n) (n^3 points) | QGaussSimplex(n) | |
  /// face rule             | QGauss<2>(n)           | QGaussSimplex<2>(n)    |
  /// | mapping of degree m   | MappingQCache(m)       |
  /// MappingFE(FE_SimplexP(1 or 2)) |
  ///
  /// Both rules with n points per direction integrate polynomials of degree
  /// 2n - 1 exactly. Tetrahedral meshes read from a file of 4-node
  /// tetrahedra (or split from hexahedra) carry flat facets, so their
  /// mapping is affine whatever degree is asked for. A file of 10-node
  /// tetrahedra keeps its mid-edge nodes (Geometry::MidEdgeManifold), and a
  /// mapping degree >= 2 then gives the quadratic MappingFE(FE_SimplexP(2))
  /// through the corners and those nodes.
  class CellKind
  {
  public:
    /// The kind of @p tria (collective over its communicator for a parallel
    /// triangulation). Throws if the mesh mixes cell shapes.
    explicit CellKind(const dealii::Triangulation<3, 3> &tria);

    /// Tetrahedra (true) or hexahedra (false).
    bool
    simplex() const
    {
      return is_simplex;
    }

    /// "hexahedra" or "tetrahedra".
    std::string
    name() const;

    /// Continuous Lagrange element of degree @p degree (scalar).
    std::unique_ptr<dealii::FiniteElement<3, 3>>
    lagrange(const unsigned int degree) const;

    /// Discontinuous complete polynomials of degree @p degree (scalar).
    std::unique_ptr<dealii::FiniteElement<3, 3>>
    discontinuous(const unsigned int degree) const;

    /// Gauss rule on a cell, exact to degree 2 @p n_points_1d - 1.
    dealii::Quadrature<3>
    cell_quadrature(const unsigned int n_points_1d) const;

    /// Gauss rule on a face, exact to degree 2 @p n_points_1d - 1.
    dealii::Quadrature<2>
    face_quadrature(const unsigned int n_points_1d) const;

    /// The mapping of @p tria (hexahedra: a MappingQCache of degree
    /// @p degree that follows the manifolds, support points computed once;
    /// tetrahedra: MappingFE(FE_SimplexP(mapping_degree(@p degree))), affine
    /// unless the mesh has mid-edge nodes).
    std::unique_ptr<dealii::Mapping<3, 3>>
    mapping(const dealii::Triangulation<3, 3> &tria,
            const unsigned int                 degree) const;

    /// A rule whose points are the nodes of lagrange(@p degree), so that
    /// the mass matrix integrated with it is diagonal (the lumped mass):
    /// QGaussLobatto(degree + 1) on hexahedra; on tetrahedra the 4 vertices
    /// with weight 1/24 each (the reference volume over 4; for P1 exactly the
    /// row sums of the consistent mass, all positive). Throws for
    /// tetrahedra of degree 2 (their nodal rule has zero vertex weights).
    dealii::Quadrature<3>
    nodal_quadrature(const unsigned int degree) const;

    /// Sample points of a face (the weights mean nothing): its vertices,
    /// edge midpoints and centre (QGaussLobatto<2>(3) on quadrilaterals).
    dealii::Quadrature<2>
    face_sample_points() const;

    /// @p point (reference coordinates) moved into the reference cell: on
    /// hexahedra each coordinate clamped to [0, 1]; on tetrahedra the
    /// barycentric coordinates clamped to [0, 1] and renormalised to sum 1.
    /// Points inside stay where they are.
    dealii::Point<3>
    project_to_reference_cell(const dealii::Point<3> &point) const;

    /// Subdivisions of an output patch (DataOut::build_patches) for fields
    /// of degree @p degree: @p degree on hexahedra; 1 on tetrahedra (linear
    /// patches, the vertex values: the results file takes 4-node tetrahedra).
    unsigned int
    output_subdivisions(const unsigned int degree) const
    {
      return is_simplex ? 1 : degree;
    }

    /// The degree mapping() gives for @p degree: @p degree on hexahedra; on
    /// tetrahedra 2 if @p degree >= 2 and the mesh has mid-edge nodes
    /// (curved()), else 1.
    unsigned int
    mapping_degree(const unsigned int degree) const
    {
      if (!is_simplex)
        return degree;
      return curved && degree >= 2 ? 2 : 1;
    }

    /// Whether the mesh is tetrahedral with the mid-edge nodes of a
    /// second-order mesh file (Geometry::MidEdgeManifold).
    bool
    curved_tetrahedra() const
    {
      return curved;
    }

  private:
    bool is_simplex = false;
    bool curved     = false;
  };

  /// CellKind::project_to_reference_cell() for a cell that is a tetrahedron
  /// (@p simplex) or a hexahedron. Not collective.
  dealii::Point<3>
  project_to_reference_cell(const bool simplex, const dealii::Point<3> &point);
} // namespace systole::Geometry
