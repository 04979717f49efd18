#include "mechanics/field_layout.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>

#include <map>

namespace systole::Mechanics
{
  FieldLayout::FieldLayout(const unsigned int        degree,
                           const Parameters         &params,
                           const Geometry::CellKind &cells)
    : degree(degree)
    , has_pressure(params.mixed())
    , params(params)
    , cells(cells)
  {
    // P2-P1disc is not inf-sup stable on tetrahedra (Boffi, Brezzi, Fortin
    // 2013, 8.6): only Taylor-Hood is offered there.
    AssertThrow(!has_pressure || !cells.simplex() ||
                  params.pressure_element == PressureElement::continuous,
                dealii::ExcMessage(
                  "Discretization / Pressure element = discontinuous is not "
                  "inf-sup stable on tetrahedra: set Pressure element = "
                  "continuous (Taylor-Hood P2-P1) for this mesh."));
    AssertThrow(!has_pressure ||
                  params.pressure_element == PressureElement::discontinuous ||
                  degree >= 2,
                dealii::ExcMessage(
                  "Discretization / Pressure element = continuous "
                  "(Taylor-Hood) needs Discretization / Polynomial degree = "
                  "2: Q1-Q1 is not inf-sup stable. Use Polynomial degree = 2, "
                  "or Pressure element = discontinuous (Q1-P0)."));
  }

  std::unique_ptr<dealii::FiniteElement<3, 3>>
  FieldLayout::make_fe() const
  {
    const auto u = cells.lagrange(degree);
    if (!has_pressure)
      return std::make_unique<dealii::FESystem<3>>(*u, 3);
    const auto p = params.pressure_element == PressureElement::continuous
                     ? cells.lagrange(degree - 1)
                     : cells.discontinuous(degree - 1);
    return std::make_unique<dealii::FESystem<3>>(*u, 3, *p, 1);
  }

  std::string
  FieldLayout::name() const
  {
    const std::string Q = cells.simplex() ? "P" : "Q";
    const std::string u = Q + std::to_string(degree);
    if (!has_pressure)
      return u + " (displacement, volumetric penalty)";
    const std::string p = params.pressure_element == PressureElement::continuous
                            ? Q + std::to_string(degree - 1)
                            : "P" + std::to_string(degree - 1) + "disc";
    return u + "-" + p + " (u-p, " +
           (params.incompressibility == Incompressibility::incompressible
              ? "incompressible"
              : "nearly incompressible") +
           ")";
  }

  void
  FieldLayout::renumber(dealii::DoFHandler<3, 3> &dof_handler)
  {
    const auto             &fe    = dof_handler.get_fe();
    const dealii::IndexSet &owned = dof_handler.locally_owned_dofs();
    const MPI_Comm          comm  = dof_handler.get_communicator();
    const auto              n     = owned.n_elements();
    AssertThrow(n == 0 || owned.is_contiguous(),
                dealii::ExcInternalError("owned DoFs not contiguous"));
    const dealii::types::global_dof_index first = n == 0 ? 0 : *owned.begin();

    // Component of every owned DoF (each lies on a locally owned cell).
    std::vector<int>                             component(n, -1);
    std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            if (owned.is_element(dofs[i]))
              component[dofs[i] - first] =
                fe.system_to_component_index(i).first;
        }
    std::size_t n_u = 0;
    for (const int c : component)
      {
        Assert(c >= 0, dealii::ExcInternalError());
        n_u += (c < 3) ? 1 : 0;
      }

    std::vector<dealii::types::global_dof_index> new_numbers(n);
    std::size_t                                  next_u = 0, next_p = 0;
    for (std::size_t i = 0; i < n; ++i)
      new_numbers[i] =
        component[i] < 3 ? first + next_u++ : first + n_u + next_p++;
    dof_handler.renumber_dofs(new_numbers);

    owned_u = dealii::IndexSet(dof_handler.n_dofs());
    owned_p = dealii::IndexSet(dof_handler.n_dofs());
    owned_u.add_range(first, first + n_u);
    owned_p.add_range(first + n_u, first + n);

    // Interleaving: the DoF of component c of a node is (DoF of component 0)
    // + c, and component 0 sits at a multiple of 3 from the range start.
    bool ok = n_u % 3 == 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (ok && cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          std::map<unsigned int, std::array<dealii::types::global_dof_index, 3>>
            node;
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              const auto [c, base_index] = fe.system_to_component_index(i);
              if (c < 3)
                node[base_index][c] = dofs[i];
            }
          for (const auto &[base_index, d] : node)
            if (owned_u.is_element(d[0]) || owned_u.is_element(d[1]) ||
                owned_u.is_element(d[2]))
              ok = ok && owned_u.is_element(d[0]) && (d[0] - first) % 3 == 0 &&
                   d[1] == d[0] + 1 && d[2] == d[0] + 2;
        }
    interleaved = dealii::Utilities::MPI::min(ok ? 1 : 0, comm) == 1;
  }
} // namespace systole::Mechanics
