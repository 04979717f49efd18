#include "mechanics/cavity_volume.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/petsc_vector.h>

#include "mechanics/surface_terms.h"

#include <array>
#include <map>

namespace systole::Mechanics
{
  namespace
  {
    using LineIterator = dealii::TriaIterator<dealii::TriaAccessor<1, 3, 3>>;

    /// Count each active (leaf) line of @p line once in @p uses: a face
    /// next to a refined neighbour shares its neighbours' child lines.
    void
    count_leaf_lines(const LineIterator                              &line,
                     std::map<unsigned int, unsigned int>            &uses,
                     std::map<unsigned int, std::array<unsigned, 2>> &ends)
    {
      if (line->has_children())
        {
          for (unsigned int i = 0; i < line->n_children(); ++i)
            count_leaf_lines(line->child(i), uses, ends);
          return;
        }
      ++uses[line->index()];
      ends[line->index()] = {{line->vertex_index(0), line->vertex_index(1)}};
    }

    /// Call @p f(X_v, dofs) once for every rim vertex this rank counts, with
    /// its position and the global indices of its 3 displacement DoFs, from a
    /// locally owned cell around it.
    template <class Function>
    void
    for_each_counted_rim_vertex(const dealii::DoFHandler<3, 3> &dof_handler,
                                const std::vector<bool>        &counted,
                                const Function                 &f)
    {
      const auto        &fe  = dof_handler.get_fe();
      const unsigned int dpv = fe.n_dofs_per_vertex();
      AssertThrow(counted.size() ==
                    dof_handler.get_triangulation().n_vertices(),
                  dealii::ExcMessage(
                    "CavityVolume: the mesh changed since the rim was found "
                    "(build the CavityVolume after refining)."));
      std::vector<bool> visited(counted.size(), false);
      std::array<dealii::types::global_dof_index, 3> dofs;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const unsigned int v : cell->vertex_indices())
            {
              const unsigned int index = cell->vertex_index(v);
              if (!counted[index] || visited[index])
                continue;
              visited[index]     = true;
              unsigned int found = 0;
              // Vertex DoFs come first in a cell's numbering, dpv per vertex.
              for (unsigned int j = 0; j < dpv; ++j)
                {
                  const unsigned int component =
                    fe.system_to_component_index(v * dpv + j).first;
                  if (component < 3)
                    {
                      dofs[component] = cell->vertex_dof_index(v, j);
                      ++found;
                    }
                }
              AssertThrow(found == 3,
                          dealii::ExcMessage(
                            "CavityVolume: the displacement element has no "
                            "DoFs at the vertices (the rim fan needs a "
                            "Lagrange element)."));
              f(cell->vertex(v), dofs);
            }
    }
  } // namespace

  CavityVolume::CavityVolume(const dealii::types::boundary_id endocardium,
                             const Geometry::Plane           &lid)
    : kind(Closure::plane)
    , endocardium(endocardium)
    , lid(lid)
  {}

  CavityVolume::CavityVolume(const dealii::Triangulation<3, 3> &tria,
                             const dealii::types::boundary_id   endocardium,
                             const dealii::types::boundary_id   base)
    : kind(Closure::rim_fan)
    , endocardium(endocardium)
    , counted_rim_vertex(tria.n_vertices(), false)
  {
    // On the owned and ghost cells: the faces of both parts and the lowest
    // subdomain id around each vertex. A rank that owns a cell around a
    // vertex sees all cells around it (the ghost layer), so there both the
    // rim test and that lowest id are complete.
    const bool         with_base = base != dealii::numbers::invalid_boundary_id;
    const unsigned int n_vertices = tria.n_vertices();
    std::vector<bool>  on_cavity(n_vertices, false), on_base(n_vertices, false);
    std::vector<dealii::types::subdomain_id> lowest(
      n_vertices,
      dealii::numbers::invalid_subdomain_id);
    std::map<unsigned int, unsigned int>            line_uses;
    std::map<unsigned int, std::array<unsigned, 2>> line_ends;
    for (const auto &cell : tria.active_cell_iterators())
      {
        if (cell->is_artificial())
          continue;
        for (const unsigned int v : cell->vertex_indices())
          lowest[cell->vertex_index(v)] =
            std::min(lowest[cell->vertex_index(v)], cell->subdomain_id());
        if (!cell->at_boundary())
          continue;
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() &&
              (face->boundary_id() == endocardium ||
               (with_base && face->boundary_id() == base)))
            {
              auto &mark =
                face->boundary_id() == endocardium ? on_cavity : on_base;
              for (const unsigned int v : face->vertex_indices())
                mark[face->vertex_index(v)] = true;
              if (!with_base && face->boundary_id() == endocardium)
                for (const unsigned int l : face->line_indices())
                  count_leaf_lines(face->line(l), line_uses, line_ends);
            }
      }
    std::vector<bool> rim(n_vertices, false);
    if (with_base)
      for (unsigned int v = 0; v < n_vertices; ++v)
        rim[v] = on_cavity[v] && on_base[v];
    else
      for (const auto &[line, uses] : line_uses)
        if (uses == 1)
          for (const unsigned int v : line_ends[line])
            rim[v] = true;

    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          {
            const unsigned int index = cell->vertex_index(v);
            if (rim[index] && cell->subdomain_id() == lowest[index] &&
                !counted_rim_vertex[index])
              {
                counted_rim_vertex[index] = true;
                ++n_rim;
              }
          }
    n_rim = dealii::Utilities::MPI::sum(n_rim, tria.get_communicator());
    AssertThrow(n_rim >= 3,
                dealii::ExcMessage(
                  "The cavity of boundary id " + std::to_string(endocardium) +
                  " has " + std::to_string(n_rim) + " rim vertices " +
                  (with_base ? "shared with the base (boundary id " +
                                 std::to_string(base) + ")"
                             : std::string("(boundary edges of the part)")) +
                  ": it needs at least 3 to be closed by a lid."));
  }

  void
  CavityVolume::for_each_rim_vertex(
    const dealii::DoFHandler<3, 3> &dof_handler,
    const std::function<
      void(const std::array<dealii::types::global_dof_index, 3> &)> &f) const
  {
    for_each_counted_rim_vertex(
      dof_handler,
      counted_rim_vertex,
      [&](const dealii::Point<3> &,
          const std::array<dealii::types::global_dof_index, 3> &dofs) {
        f(dofs);
      });
  }

  void
  CavityVolume::add_fan_face(
    const dealii::FEFaceValues<3, 3>        &fe_face,
    const std::vector<dealii::Tensor<1, 3>> &u_values,
    const std::vector<dealii::Tensor<2, 3>> &u_gradients,
    const dealii::Point<3>                  &c,
    const double                             scale,
    dealii::Vector<double>                  &vector,
    dealii::FullMatrix<double>              *matrix,
    dealii::Tensor<1, 3>                    &area_sum,
    std::array<dealii::Vector<double>, 3>   *alpha)
  {
    const auto                       &fe        = fe_face.get_fe();
    const unsigned int                n         = fe.n_dofs_per_cell();
    const std::vector<unsigned int>   component = shape_components(fe);
    std::vector<dealii::Tensor<1, 3>> grad(n), turn(n);
    for (const unsigned int q : fe_face.quadrature_point_indices())
      {
        const dealii::Tensor<2, 3> F =
          dealii::unit_symmetric_tensor<3>() + u_gradients[q];
        const dealii::Tensor<1, 3> &N    = fe_face.normal_vector(q);
        const dealii::Tensor<1, 3>  area = dealii::cofactor(F) * N;
        const dealii::Tensor<1, 3>  w =
          fe_face.quadrature_point(q) + u_values[q] - c;
        const double JxW = fe_face.JxW(q);
        area_sum += area * JxW;
        const double weight = -scale * JxW / 3.0;
        // da[e_k g] = dcof(F)[e_k (x) g] N, and w . da[e_k g] = ((F (N x g))
        // x w)_k (N = t1 x t2: dcof[G](t1 x t2) = G t1 x F t2 + F t1 x G t2).
        // A[i][j][K] = eps_ijk eps_JKL F_kL N_J: (da[e_j g])_i = A[i][j] . g.
        double A[3][3][3] = {};
        if (matrix != nullptr)
          area_derivative(F, N, A);
        for (unsigned int a = 0; a < n; ++a)
          {
            if (component[a] >= 3)
              continue;
            grad[a] = fe_face.shape_grad_component(a, q, component[a]);
            turn[a] =
              dealii::cross_product_3d(F * dealii::cross_product_3d(N, grad[a]),
                                       w);
          }
        for (unsigned int a = 0; a < n; ++a)
          {
            const unsigned int ca = component[a];
            if (ca >= 3)
              continue;
            const double phi_a = fe_face.shape_value(a, q);
            vector(a) += weight * (phi_a * area[ca] + turn[a][ca]);
            if (matrix == nullptr)
              continue;
            // alpha_k[phi_a] = int (da[phi_a])_k dA
            if (alpha != nullptr)
              for (unsigned int k = 0; k < 3; ++k)
                (*alpha)[k](a) +=
                  JxW * (A[k][ca][0] * grad[a][0] + A[k][ca][1] * grad[a][1] +
                         A[k][ca][2] * grad[a][2]);
            for (unsigned int b = 0; b < n; ++b)
              {
                const unsigned int cb = component[b];
                if (cb >= 3)
                  continue;
                const double phi_b = fe_face.shape_value(b, q);
                // phi_a . da[phi_b] + phi_b . da[phi_a]
                double value = phi_a * (A[ca][cb][0] * grad[b][0] +
                                        A[ca][cb][1] * grad[b][1] +
                                        A[ca][cb][2] * grad[b][2]) +
                               phi_b * (A[cb][ca][0] * grad[a][0] +
                                        A[cb][ca][1] * grad[a][1] +
                                        A[cb][ca][2] * grad[a][2]);
                // w . d2a: (w . (e_ca x e_cb)) (N . (g_a x g_b))
                if (ca != cb)
                  {
                    const unsigned int k    = 3 - ca - cb;
                    const double       sign = (cb == (ca + 1) % 3) ? 1.0 : -1.0;
                    value += sign * w[k] *
                             (N * dealii::cross_product_3d(grad[a], grad[b]));
                  }
                (*matrix)(a, b) += weight * value;
              }
          }
      }
  }

  dealii::Point<3>
  CavityVolume::rim_center(const dealii::DoFHandler<3, 3> &dof_handler,
                           const LA::MPI::Vector          &u) const
  {
    std::array<double, 4> sums{}; // sum of x_v (3), count
    for_each_counted_rim_vertex(
      dof_handler,
      counted_rim_vertex,
      [&](const dealii::Point<3>                               &X,
          const std::array<dealii::types::global_dof_index, 3> &dofs) {
        for (unsigned int k = 0; k < 3; ++k)
          sums[k] += X[k] + u(dofs[k]);
        sums[3] += 1;
      });
    dealii::Utilities::MPI::sum(dealii::ArrayView<const double>(sums),
                                dof_handler.get_communicator(),
                                dealii::ArrayView<double>(sums));
    AssertThrow(static_cast<unsigned int>(sums[3] + 0.5) == n_rim,
                dealii::ExcMessage("CavityVolume: " + std::to_string(sums[3]) +
                                   " of the " + std::to_string(n_rim) +
                                   " rim vertices found on the DoF handler's "
                                   "mesh: not the mesh of the constructor?"));
    return dealii::Point<3>(sums[0], sums[1], sums[2]) / sums[3];
  }

  namespace
  {
    /// The Gauss rule of @p n_points per direction on the faces of the
    /// element (CellKind's face rule, without its collective shape query).
    dealii::Quadrature<2>
    face_quadrature(const dealii::DoFHandler<3, 3> &dof_handler,
                    const unsigned int              n_points)
    {
      return dof_handler.get_fe()
        .reference_cell()
        .face_reference_cell(0)
        .get_gauss_type_quadrature<2>(n_points);
    }

    /// Calls @p f(cell) on every face of the locally owned cells in the
    /// boundary part @p part, with @p fe_face reinitialized on it.
    template <typename Function>
    void
    for_each_owned_face(const dealii::DoFHandler<3, 3>  &dof_handler,
                        const dealii::types::boundary_id part,
                        dealii::FEFaceValues<3>         &fe_face,
                        const Function                  &f)
    {
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && cell->at_boundary())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == part)
              {
                fe_face.reinit(cell, face);
                f(cell);
              }
    }
  } // namespace


  double
  CavityVolume::volume(const dealii::Mapping<3, 3>    &mapping,
                       const dealii::DoFHandler<3, 3> &dof_handler,
                       const LA::MPI::Vector          &u,
                       const unsigned int              n_points) const
  {
    const dealii::Quadrature<2> quadrature =
      face_quadrature(dof_handler, n_points);
    dealii::FEFaceValues<3>                  fe_face(mapping,
                                    dof_handler.get_fe(),
                                    quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_quadrature_points |
                                      dealii::update_normal_vectors |
                                      dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector displacement(0);
    std::vector<dealii::Tensor<1, 3>>        u_values(quadrature.size());
    std::vector<dealii::Tensor<2, 3>>        u_gradients(quadrature.size());

    const bool             fan = kind == Closure::rim_fan;
    const dealii::Point<3> c =
      fan ? rim_center(dof_handler, u) : dealii::Point<3>();
    const dealii::Tensor<1, 3> &e            = lid.normal;
    double                      local_volume = 0.0;
    for_each_owned_face(dof_handler, endocardium, fe_face, [&](const auto &) {
      fe_face[displacement].get_function_values(u, u_values);
      fe_face[displacement].get_function_gradients(u, u_gradients);
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        {
          const dealii::Tensor<2, 3> F =
            dealii::unit_symmetric_tensor<3>() + u_gradients[q];
          // cof(F) N dA = J F^{-T} N dA: the deformed vector area
          // element.
          const dealii::Tensor<1, 3> deformed_area =
            dealii::cofactor(F) * fe_face.normal_vector(q);
          const dealii::Tensor<1, 3> x =
            fe_face.quadrature_point(q) + u_values[q];
          if (fan)
            local_volume -= ((x - c) * deformed_area) * fe_face.JxW(q) / 3.0;
          else
            local_volume -=
              ((x - lid.point) * e) * (e * deformed_area) * fe_face.JxW(q);
        }
    });
    return dealii::Utilities::MPI::sum(local_volume,
                                       dof_handler.get_communicator());
  }

  void
  CavityVolume::derivative(const dealii::Mapping<3, 3>    &mapping,
                           const dealii::DoFHandler<3, 3> &dof_handler,
                           const LA::MPI::Vector          &u,
                           const unsigned int              n_points,
                           LA::MPI::Vector                &dV_du) const
  {
    const dealii::Quadrature<2> quadrature =
      face_quadrature(dof_handler, n_points);
    const bool              fan = kind == Closure::rim_fan;
    dealii::FEFaceValues<3> fe_face(
      mapping,
      dof_handler.get_fe(),
      quadrature,
      dealii::update_values | dealii::update_gradients |
        dealii::update_normal_vectors | dealii::update_JxW_values |
        (fan ? dealii::update_quadrature_points : dealii::update_default));
    const dealii::FEValuesExtractors::Vector     displacement(0);
    std::vector<dealii::Tensor<1, 3>>            u_values(quadrature.size());
    std::vector<dealii::Tensor<2, 3>>            u_gradients(quadrature.size());
    const auto                                  &fe = dof_handler.get_fe();
    const unsigned int                           n  = fe.n_dofs_per_cell();
    dealii::Vector<double>                       local(n);
    std::vector<dealii::types::global_dof_index> dofs(n);

    const dealii::Point<3> c =
      fan ? rim_center(dof_handler, u) : dealii::Point<3>();
    // Rim fan: the integral of cof(F) N dA over the endocardium (the wall's
    // deformed vector area), the weight of the lid's apex c.
    dealii::Tensor<1, 3> wall_area;

    dV_du = 0;
    for_each_owned_face(
      dof_handler,
      endocardium,
      fe_face,
      [&](const auto &cell) {
        fe_face[displacement].get_function_gradients(u, u_gradients);
        local = 0;
        if (!fan)
          add_volume_flux(fe_face, u_gradients, -1.0, local, nullptr);
        else
          {
            fe_face[displacement].get_function_values(u, u_values);
            add_fan_face(fe_face,
                         u_values,
                         u_gradients,
                         c,
                         1.0,
                         local,
                         nullptr,
                         wall_area);
          }
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < n; ++i)
          dV_du(dofs[i]) += local(i);
      });
    if (fan)
      {
        // The apex moves with the mean of the rim vertices: dV/dc = (1/3)
        // int cof(F) N dA, spread evenly over the rim vertices' DoFs.
        wall_area = dealii::Utilities::MPI::sum(wall_area,
                                                dof_handler.get_communicator());
        const dealii::Tensor<1, 3> share = wall_area / (3.0 * n_rim);
        for_each_counted_rim_vertex(
          dof_handler,
          counted_rim_vertex,
          [&](const dealii::Point<3> &,
              const std::array<dealii::types::global_dof_index, 3> &rim_dofs) {
            for (unsigned int k = 0; k < 3; ++k)
              dV_du(rim_dofs[k]) += share[k];
          });
      }
    dV_du.compress(dealii::VectorOperation::add);
  }
} // namespace systole::Mechanics
