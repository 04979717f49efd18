// What the postprocessors read from the mechanics: the state at the
// quadrature points, the vertices and deformed boundary areas.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include "materials/active_stress.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem_impl.h"

#include <limits>
#include <set>

namespace systole::Mechanics
{
  void
  Problem::point_states(std::vector<std::vector<PointState>> &states) const
  {
    const Impl                       &m     = *impl;
    const bool                        mixed = m.discretization.layout.mixed();
    std::vector<dealii::Tensor<2, 3>> grad_u;
    std::vector<double>               p_values;
    states.assign(m.tria.n_active_cells(), {});
    m.discretization.for_each_owned_cell(
      m.discretization.n_q_1d,
      dealii::update_gradients | dealii::update_values |
        dealii::update_JxW_values,
      [&](const auto &cell, const auto &fe_values) {
        const unsigned int n_q = fe_values.n_quadrature_points;
        grad_u.resize(n_q);
        p_values.resize(n_q);
        fe_values[m.discretization.layout.displacement]
          .get_function_gradients(m.u, grad_u);
        if (mixed)
          fe_values[m.discretization.layout.pressure]
            .get_function_values(m.u, p_values);
        const auto data = m.points.point_data.get_data(cell);
        auto      &out  = states[cell->active_cell_index()];
        out.resize(n_q);
        for (unsigned int q = 0; q < n_q; ++q)
          {
            PointState &s = out[q];
            s.position    = data[q]->position;
            s.JxW         = fe_values.JxW(q);
            s.F           = dealii::unit_symmetric_tensor<3>() + grad_u[q];
            s.basis       = data[q]->basis;
            s.active_tension =
              m.points.last_active_tension + data[q]->tension +
              (m.points.tension_model != nullptr ? data[q]->model_tension
                                                 : 0.0);
            const double J = dealii::determinant(s.F);
            if (!(J > 0.0))
              {
                // An inverted point has no stress: NaN marks it.
                s.cauchy_stress = dealii::SymmetricTensor<2, 3>();
                for (unsigned int i = 0; i < 3; ++i)
                  for (unsigned int j = i; j < 3; ++j)
                    s.cauchy_stress[i][j] =
                      std::numeric_limits<double>::quiet_NaN();
                continue;
              }
            // The stress of the assembly (assembly.cc), without tangent.
            Materials::PassiveInput in;
            in.F            = s.F;
            in.basis        = s.basis;
            in.with_tangent = false;
            Materials::PassiveOutput law;
            m.material.passive_law.evaluate(in, law);
            if (mixed)
              Materials::add_volumetric_stress(in, -p_values[q], 0.0, law);
            else
              m.material.volumetric_law.add_to(s.F, law.S, law.dS_dE);
            if (s.active_tension != 0.0)
              Materials::add_active_stress(s.active_tension,
                                           m.params.active_cross_fibre,
                                           s.basis,
                                           law.S);
            const dealii::Tensor<2, 3> sigma =
              s.F * dealii::Tensor<2, 3>(law.S) * dealii::transpose(s.F) / J;
            s.cauchy_stress = dealii::symmetrize(sigma);
          }
      });
  }

  std::vector<VertexState>
  Problem::vertex_states() const
  {
    const Impl              &m = *impl;
    std::vector<VertexState> result;
    std::set<unsigned int>   seen;
    for (const auto &cell :
         m.discretization.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          {
            const auto first = cell->vertex_dof_index(v, 0);
            if (!m.discretization.owned.is_element(first) ||
                !seen.insert(cell->vertex_index(v)).second)
              continue;
            VertexState s;
            s.reference = cell->vertex(v);
            s.deformed  = s.reference;
            for (unsigned int c = 0; c < 3; ++c)
              s.deformed[c] += m.u(cell->vertex_dof_index(v, c));
            result.push_back(s);
          }
    return result;
  }

  double
  Problem::deformed_area(const std::string       &part,
                         const std::vector<bool> *cells) const
  {
    const Impl                       &m  = *impl;
    const dealii::types::boundary_id  id = m.boundaries.boundary_names.id(part);
    std::vector<dealii::Tensor<2, 3>> grad_u;
    double                            area = 0;
    m.discretization.for_each_owned_boundary_face(
      dealii::update_gradients | dealii::update_normal_vectors |
        dealii::update_JxW_values,
      [&](const dealii::types::boundary_id b) { return b == id; },
      [&](const auto &, const auto &fe_face) {
        if (cells && !(*cells)[fe_face.get_cell()->active_cell_index()])
          return;
        grad_u.resize(fe_face.n_quadrature_points);
        fe_face[m.discretization.layout.displacement]
          .get_function_gradients(m.u, grad_u);
        for (const unsigned int q : fe_face.quadrature_point_indices())
          {
            const dealii::Tensor<2, 3> F =
              dealii::unit_symmetric_tensor<3>() + grad_u[q];
            const dealii::Tensor<2, 3> cof =
              dealii::determinant(F) * dealii::transpose(dealii::invert(F));
            area += (cof * fe_face.normal_vector(q)).norm() * fe_face.JxW(q);
          }
      });
    return dealii::Utilities::MPI::sum(area, m.comm);
  }

  unsigned int
  Problem::n_quadrature_points_1d() const
  {
    return impl->discretization.n_q_1d;
  }

  const dealii::Triangulation<3, 3> &
  Problem::triangulation() const
  {
    return impl->tria;
  }

  const Geometry::CellKind &
  Problem::cell_kind() const
  {
    return impl->discretization.layout.cell_kind();
  }
} // namespace systole::Mechanics
