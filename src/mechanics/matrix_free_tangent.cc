// The matrix-free tangent: MatrixFree cell loops around the point kernel of
// hyperelastic_kernel.h. Only this file includes the MatrixFree headers.
#include "mechanics/matrix_free_tangent.h"

#include <deal.II/base/aligned_vector.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe.h>
#include <deal.II/matrix_free/fe_evaluation.h>
#include <deal.II/matrix_free/matrix_free.h>

#include <array>

namespace systole::Mechanics
{
  namespace
  {
    constexpr unsigned int degree = 2;  // Q2
    constexpr unsigned int n_q_1d = 3;  // Gauss points per direction
    constexpr unsigned int n_sym  = 45; // upper triangle of the 9 x 9 tangent

    using VA    = dealii::VectorizedArray<double>;
    using Eval  = dealii::FEEvaluation<3, degree, n_q_1d, 3, double>;
    using Grad  = dealii::Tensor<2, 3, VA>;
    using Range = std::pair<unsigned int, unsigned int>;

    /// dP = A : H with A stored as the upper triangle of the symmetric
    /// 9 x 9 matrix A_(3i+J)(3k+L) = dP_iJ/dF_kL, row by row.
    Grad
    apply_symmetric(const VA *A, const Grad &H)
    {
      std::array<VA, 9> h, out;
      for (unsigned int a = 0; a < 9; ++a)
        {
          h[a]   = H[a / 3][a % 3];
          out[a] = 0.0;
        }
      unsigned int index = 0;
      for (unsigned int a = 0; a < 9; ++a)
        {
          out[a] += A[index++] * h[a];
          for (unsigned int b = a + 1; b < 9; ++b, ++index)
            {
              out[a] += A[index] * h[b];
              out[b] += A[index] * h[a];
            }
        }
      Grad dP;
      for (unsigned int a = 0; a < 9; ++a)
        dP[a / 3][a % 3] = out[a];
      return dP;
    }

    /// The upper triangle of dP/dF at @p F, column by column from the
    /// kernel's directional derivative (so it is the same linearization).
    void
    tangent_of(const NeoHookeanPenalty &law, const Grad &F, VA *A)
    {
      std::array<Grad, 9> columns;
      Grad                P;
      for (unsigned int b = 0; b < 9; ++b)
        {
          Grad H;
          H[b / 3][b % 3] = 1.0;
          law.evaluate(F, &H, P, &columns[b]);
        }
      unsigned int index = 0;
      for (unsigned int a = 0; a < 9; ++a)
        for (unsigned int b = a; b < 9; ++b, ++index)
          // Symmetric up to round-off; average the two halves.
          A[index] =
            0.5 * (columns[b][a / 3][a % 3] + columns[a][b / 3][b % 3]);
    }
  } // namespace


  struct MatrixFreeTangent::Impl
  {
    Impl(const dealii::Mapping<3>                &mapping,
         const dealii::DoFHandler<3>             &dof_handler,
         const dealii::AffineConstraints<double> &constraints,
         const NeoHookeanPenalty                 &law,
         const Variant                            variant)
      : law(law)
      , variant(variant)
    {
      const auto &fe = dof_handler.get_fe();
      AssertThrow(fe.n_components() == 3 && fe.degree == degree &&
                    fe.reference_cell() == dealii::ReferenceCells::Hexahedron,
                  dealii::ExcMessage(
                    "MatrixFreeTangent needs a Q2 displacement element on "
                    "hexahedra (3 components, degree 2); got " +
                    fe.get_name() +
                    ". Use FESystem(FE_Q(2), 3) on a hexahedral mesh."));
      typename dealii::MatrixFree<3, double>::AdditionalData data;
      data.tasks_parallel_scheme =
        dealii::MatrixFree<3, double>::AdditionalData::none;
      data.mapping_update_flags =
        dealii::update_gradients | dealii::update_JxW_values;
      matrix_free.reinit(mapping,
                         dof_handler,
                         constraints,
                         dealii::QGauss<1>(n_q_1d),
                         data);
      matrix_free.initialize_dof_vector(u);
    }

    /// The point storage of @p cell (a batch), point @p q.
    const VA *
    point(const unsigned int cell, const unsigned int q) const
    {
      const unsigned int per_point = variant == Variant::cached ? n_sym : 9;
      return &storage[(cell * Eval::static_n_q_points + q) * per_point];
    }

    void
    apply_cells(const dealii::MatrixFree<3, double> &,
                Vector       &dst,
                const Vector &src,
                const Range  &cells) const;

    void
    residual_cells(const dealii::MatrixFree<3, double> &,
                   Vector       &dst,
                   const Vector &src,
                   const Range  &cells) const;

    const NeoHookeanPenalty       law;
    const Variant                 variant;
    dealii::MatrixFree<3, double> matrix_free;
    Vector                        u; ///< ghosted
    dealii::AlignedVector<VA>     storage;
  };


  void
  MatrixFreeTangent::Impl::apply_cells(const dealii::MatrixFree<3, double> &,
                                       Vector       &dst,
                                       const Vector &src,
                                       const Range  &cells) const
  {
    Eval phi(matrix_free);
    for (unsigned int cell = cells.first; cell < cells.second; ++cell)
      {
        phi.reinit(cell);
        phi.gather_evaluate(src, dealii::EvaluationFlags::gradients);
        for (unsigned int q = 0; q < phi.n_q_points; ++q)
          {
            const Grad H = phi.get_gradient(q);
            const VA  *s = point(cell, q);
            if (variant == Variant::cached)
              phi.submit_gradient(apply_symmetric(s, H), q);
            else
              {
                Grad F, P, dP;
                for (unsigned int a = 0; a < 9; ++a)
                  F[a / 3][a % 3] = s[a];
                law.evaluate(F, &H, P, &dP);
                phi.submit_gradient(dP, q);
              }
          }
        phi.integrate_scatter(dealii::EvaluationFlags::gradients, dst);
      }
  }


  void
  MatrixFreeTangent::Impl::residual_cells(const dealii::MatrixFree<3, double> &,
                                          Vector       &dst,
                                          const Vector &src,
                                          const Range  &cells) const
  {
    Eval phi(matrix_free);
    for (unsigned int cell = cells.first; cell < cells.second; ++cell)
      {
        phi.reinit(cell);
        phi.read_dof_values_plain(src);
        phi.evaluate(dealii::EvaluationFlags::gradients);
        for (unsigned int q = 0; q < phi.n_q_points; ++q)
          {
            Grad F = phi.get_gradient(q), P;
            for (unsigned int d = 0; d < 3; ++d)
              F[d][d] += 1.0;
            law.evaluate<VA>(F, nullptr, P, nullptr);
            phi.submit_gradient(P, q);
          }
        phi.integrate_scatter(dealii::EvaluationFlags::gradients, dst);
      }
  }


  MatrixFreeTangent::MatrixFreeTangent(
    const dealii::Mapping<3>                &mapping,
    const dealii::DoFHandler<3>             &dof_handler,
    const dealii::AffineConstraints<double> &constraints,
    const NeoHookeanPenalty                 &law,
    const Variant                            variant)
    : impl(
        std::make_unique<Impl>(mapping, dof_handler, constraints, law, variant))
  {}


  MatrixFreeTangent::~MatrixFreeTangent() = default;


  void
  MatrixFreeTangent::initialize_dof_vector(Vector &v) const
  {
    impl->matrix_free.initialize_dof_vector(v);
  }


  void
  MatrixFreeTangent::update(const Vector &u)
  {
    impl->u.copy_locally_owned_data_from(u);
    impl->u.update_ghost_values();

    const auto        &mf        = impl->matrix_free;
    const bool         cached    = impl->variant == Variant::cached;
    const unsigned int per_point = cached ? n_sym : 9;
    impl->storage.resize(static_cast<std::size_t>(mf.n_cell_batches()) *
                         Eval::static_n_q_points * per_point);
    Eval   phi(mf);
    double min_J = 1.0;
    for (unsigned int cell = 0; cell < mf.n_cell_batches(); ++cell)
      {
        phi.reinit(cell);
        phi.read_dof_values_plain(impl->u);
        phi.evaluate(dealii::EvaluationFlags::gradients);
        for (unsigned int q = 0; q < phi.n_q_points; ++q)
          {
            Grad F = phi.get_gradient(q);
            for (unsigned int d = 0; d < 3; ++d)
              F[d][d] += 1.0;
            const VA J = determinant(F);
            for (unsigned int l = 0;
                 l < mf.n_active_entries_per_cell_batch(cell);
                 ++l)
              min_J = std::min(min_J, J[l]);
            VA *s = const_cast<VA *>(impl->point(cell, q));
            if (cached)
              tangent_of(impl->law, F, s);
            else
              for (unsigned int a = 0; a < 9; ++a)
                s[a] = F[a / 3][a % 3];
          }
      }
    min_J = dealii::Utilities::MPI::min(min_J, u.get_mpi_communicator());
    AssertThrow(min_J > 0.0,
                dealii::ExcMessage(
                  "MatrixFreeTangent::update(): det F = " +
                  std::to_string(min_J) +
                  " <= 0 at a quadrature point (an inverted element); "
                  "reduce the load step or refine the mesh."));
  }


  void
  MatrixFreeTangent::vmult(Vector &dst, const Vector &src) const
  {
    impl->matrix_free.cell_loop(&Impl::apply_cells, impl.get(), dst, src, true);
    for (const unsigned int i : impl->matrix_free.get_constrained_dofs())
      dst.local_element(i) = src.local_element(i);
  }


  void
  MatrixFreeTangent::residual(Vector &dst) const
  {
    impl->matrix_free.cell_loop(&Impl::residual_cells,
                                impl.get(),
                                dst,
                                impl->u,
                                true);
  }


  dealii::types::global_dof_index
  MatrixFreeTangent::m() const
  {
    return impl->u.size();
  }


  std::size_t
  MatrixFreeTangent::memory_consumption() const
  {
    return impl->matrix_free.memory_consumption() + point_storage_bytes() +
           impl->u.memory_consumption();
  }


  std::size_t
  MatrixFreeTangent::point_storage_bytes() const
  {
    return impl->storage.memory_consumption();
  }


  std::size_t
  MatrixFreeTangent::n_quadrature_points() const
  {
    std::size_t n = 0;
    for (unsigned int c = 0; c < impl->matrix_free.n_cell_batches(); ++c)
      n += impl->matrix_free.n_active_entries_per_cell_batch(c) *
           Eval::static_n_q_points;
    return n;
  }


  std::size_t
  MatrixFreeTangent::n_geometry_numbers() const
  {
    using dealii::internal::MatrixFreeFunctions::GeometryType;
    const auto &info = impl->matrix_free.get_mapping_info();
    std::size_t n    = 0;
    for (unsigned int c = 0; c < impl->matrix_free.n_cell_batches(); ++c)
      {
        const std::size_t lanes = VA::size();
        n += info.get_cell_type(c) == GeometryType::general
               ? lanes * Eval::static_n_q_points * 10
               : lanes * 10;
      }
    return n;
  }
} // namespace systole::Mechanics
