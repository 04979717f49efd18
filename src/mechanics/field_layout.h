#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values_extractors.h>

#include "geometry/cell_kind.h"
#include "mechanics/parameters.h"

#include <memory>
#include <string>

namespace systole::Mechanics
{
  /// The one description of the fields of the mechanics and of their place
  /// in the DoF numbering (the block layout).
  ///
  /// Fields: the displacement u (components 0-2, Q_k) and, for the mixed
  /// formulations, the pressure p (component 3: P_{k-1} discontinuous or
  /// Q_{k-1}). Blocks: 0 = u, 1 = p. The numbering keeps PETSc's contiguous
  /// ownership: rank r owns the range [first, first + n_u + n_p), its
  /// displacement DoFs first (in deal.II's order, three components of a
  /// node next to each other), then its pressure DoFs. The cavity
  /// multipliers of the bordered systems are not a field: they stay a small
  /// Schur complement outside these blocks.
  class FieldLayout
  {
  public:
    static constexpr unsigned int n_blocks = 2;

    /// @param[in] degree displacement degree k (1 or 2)
    /// @param[in] params formulation and pressure element; throws naming the
    ///            entry when the combination is not available (Taylor-Hood
    ///            with k = 1)
    /// @param[in] cells the cell shape of the mesh (Q_k on hexahedra, P_k
    ///            on tetrahedra, where only Taylor-Hood is stable)
    FieldLayout(const unsigned int        degree,
                const Parameters         &params,
                const Geometry::CellKind &cells);

    /// The cell shape the fields live on.
    const Geometry::CellKind &
    cell_kind() const
    {
      return cells;
    }

    /// Whether there is a pressure field.
    bool
    mixed() const
    {
      return has_pressure;
    }

    /// The finite element of all fields (FESystem).
    std::unique_ptr<dealii::FiniteElement<3, 3>>
    make_fe() const;

    /// Number of vector components: 3, or 4 with the pressure.
    unsigned int
    n_components() const
    {
      return has_pressure ? 4 : 3;
    }

    /// Block (0 = u, 1 = p) of a vector component.
    static unsigned int
    block_of_component(const unsigned int component)
    {
      return component < 3 ? 0 : 1;
    }

    /// Short description, e.g. "Q2-P1disc (u-p, incompressible)".
    std::string
    name() const;

    /// Renumber @p dof_handler (distributed, DoFs of this layout) as the
    /// class documentation says and record the owned ranges.
    void
    renumber(dealii::DoFHandler<3, 3> &dof_handler);

    /// Locally owned DoFs of block @p b (contiguous).
    const dealii::IndexSet &
    owned(const unsigned int b) const
    {
      return b == 0 ? owned_u : owned_p;
    }

    /// Whether the locally owned displacement DoFs come as (x, y, z)
    /// triples of one node, so that block size 3 may be given to AMG.
    bool
    displacement_interleaved() const
    {
      return interleaved;
    }

    const dealii::FEValuesExtractors::Vector displacement{0};
    const dealii::FEValuesExtractors::Scalar pressure{3};

  private:
    unsigned int       degree;
    bool               has_pressure;
    Parameters         params;
    Geometry::CellKind cells;
    dealii::IndexSet   owned_u, owned_p;
    bool               interleaved = false;
  };
} // namespace systole::Mechanics
