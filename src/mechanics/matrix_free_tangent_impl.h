#pragma once

// Internal to MatrixFreeTangent: the operator as a template on deal.II's
// vectorization type. src/mechanics/matrix_free_tangent.cc instantiates it
// for internal::Lanes: the build machine's SIMD width (matrix_free_simd.h)
// or the installed deal.II's one lane; the
// benchmark also for 8 lanes (tests/bench/matrix_free_bench_simd.cc).
// Includes the MatrixFree headers: include it only in .cc files, and only
// in the units CMake compiles on the matrix-free width
// (cmake/SystoleSimd.cmake).

#include <deal.II/base/aligned_vector.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/subscriptor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/lac/diagonal_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/matrix_free/fe_evaluation.h>
#include <deal.II/matrix_free/matrix_free.h>
#include <deal.II/matrix_free/tools.h>

#include "mechanics/matrix_free_pressure_coupling.h"
#include "mechanics/matrix_free_tangent.h"

#ifndef SYSTOLE_MATRIX_FREE_LANES
#  error "SYSTOLE_MATRIX_FREE_LANES: set by the systole target (CMake)."
#endif
#if SYSTOLE_MATRIX_FREE_LANES > 1 && \
  DEAL_II_VECTORIZATION_WIDTH_IN_BITS < 64 * SYSTOLE_MATRIX_FREE_LANES
#  error \
    "Compile this unit with the matrix-free SIMD options (cmake/SystoleSimd.cmake)."
#endif

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <string>

namespace systole::Mechanics::internal
{
  /// The operator behind MatrixFreeTangent, on @p VA (a VectorizedArray of
  /// double): its functions are those of MatrixFreeTangent.
  template <typename VA>
  class TangentOperator : public dealii::Subscriptor
  {
  public:
    static constexpr unsigned int degree = 2;  ///< Q2
    static constexpr unsigned int n_q_1d = 3;  ///< Gauss points per direction
    static constexpr unsigned int n_sym  = 45; ///< upper triangle of 9 x 9

    using Vector = dealii::LinearAlgebra::distributed::Vector<double>;
    using MF     = dealii::MatrixFree<3, double, VA>;
    using Eval   = dealii::FEEvaluation<3, degree, n_q_1d, 3, double, VA>;
    /// The Q1 displacement of the coarse DoFHandler (DoF handler 1 of the
    /// MatrixFree, when given), at the same quadrature points.
    using Eval1    = dealii::FEEvaluation<3, 1, n_q_1d, 3, double, VA>;
    using FaceEval = dealii::FEFaceEvaluation<3, degree, n_q_1d, 3, double, VA>;
    using Grad     = dealii::Tensor<2, 3, VA>;
    using Range    = std::pair<unsigned int, unsigned int>;
    using Variant  = MatrixFreeTangent::Variant;
    /// The single-precision storage type of Variant::cached_single.
    using VAf = dealii::VectorizedArray<float, VA::size()>;

    TangentOperator(
      const dealii::Mapping<3>                &mapping,
      const dealii::DoFHandler<3>             &dof_handler,
      const dealii::AffineConstraints<double> &constraints,
      const NeoHookeanPenalty                 &law,
      const Variant                            variant,
      const unsigned int mg_level = dealii::numbers::invalid_unsigned_int,
      const MatrixFreeTangent::Options *options = nullptr)
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
      typename MF::AdditionalData data;
      data.tasks_parallel_scheme = MF::AdditionalData::none;
      data.mapping_update_flags =
        dealii::update_gradients | dealii::update_JxW_values;
      data.mg_level = mg_level;
      std::vector<const dealii::DoFHandler<3> *>             dofs{&dof_handler};
      std::vector<const dealii::AffineConstraints<double> *> all_constraints{
        &constraints};
      if (options != nullptr && options->boundary_faces)
        data.mapping_update_flags_boundary_faces =
          dealii::update_values | dealii::update_gradients |
          dealii::update_JxW_values | dealii::update_normal_vectors;
      if (options != nullptr && options->q1 != nullptr)
        {
          AssertThrow(options->q1->get_fe().degree == 1 &&
                        options->q1->get_fe().n_components() == 3 &&
                        options->q1_constraints != nullptr,
                      dealii::ExcMessage("MatrixFreeTangent: the coarse "
                                         "level is Q1^3 with constraints."));
          dofs.push_back(options->q1);
          all_constraints.push_back(options->q1_constraints);
          coarse_constraints = options->q1_constraints;
        }
      matrix_free.reinit(mapping,
                         dofs,
                         all_constraints,
                         dealii::QGauss<1>(n_q_1d),
                         data);
      matrix_free.initialize_dof_vector(u);
      with_faces = options != nullptr && options->boundary_faces;
      for (const auto &line : constraints.get_lines())
        coupled_constraints = coupled_constraints || !line.entries.empty();
    }

    void
    update(const Vector &u_in);

    /// MatrixFreeTangent::update(const CellTangents &): the point storage
    /// from the caller's dP/dF (a cached variant).
    void
    update_from(const MatrixFreeTangent::CellTangents &tangents);

    /// MatrixFreeTangent::update(const MixedCellTangents &, ...): the point
    /// storage and the pressure coupling.
    void
    update_from(const MatrixFreeTangent::MixedCellTangents &tangents,
                const MatrixFreeTangent::MixedConstants    &constants);

    void
    vmult(Vector &dst, const Vector &src) const
    {
      apply(dst, src, /*add=*/false);
    }

    /// dst += K src.
    void
    vmult_add(Vector &dst, const Vector &src) const
    {
      apply(dst, src, /*add=*/true);
    }

    /// K is symmetric (a Hessian).
    void
    Tvmult(Vector &dst, const Vector &src) const
    {
      vmult(dst, src);
    }
    void
    Tvmult_add(Vector &dst, const Vector &src) const
    {
      vmult_add(dst, src);
    }

    dealii::types::global_dof_index
    m() const
    {
      return u.size();
    }

    /// Not available (the interface of deal.II's PreconditionChebyshev
    /// asks for it; the diagonal comes from compute_inverse_diagonal()).
    double
    el(const unsigned int, const unsigned int) const
    {
      AssertThrow(false, dealii::ExcNotImplemented());
      return 0.0;
    }

    void
    initialize_dof_vector(Vector &v) const
    {
      matrix_free.initialize_dof_vector(v);
    }

    /// The inverse of K's diagonal (cached variant; 1 on constrained rows).
    void
    compute_inverse_diagonal(Vector &inverse) const;

    /// Add the cell terms' diagonal to @p diagonal from the stored points
    /// (without constraints that couple DoFs).
    void
    add_point_diagonal(Vector &diagonal) const;

    void
    residual(Vector &dst) const
    {
      matrix_free.cell_loop(
        &TangentOperator::loop_cells<&TangentOperator::residual_batch>,
        this,
        dst,
        u,
        true);
    }

    std::size_t
    n_quadrature_points() const
    {
      std::size_t n = 0;
      for (unsigned int c = 0; c < matrix_free.n_cell_batches(); ++c)
        n += matrix_free.n_active_entries_per_cell_batch(c) *
             Eval::static_n_q_points;
      return n;
    }

    /// The geometry vmult() reads: none (cached: folded into the stored
    /// tangent), or 10 numbers per point of a general cell and 10 per
    /// affine cell batch (recompute).
    std::size_t
    n_geometry_numbers() const
    {
      if (cached())
        return 0;
      using dealii::internal::MatrixFreeFunctions::GeometryType;
      const auto &info = matrix_free.get_mapping_info();
      std::size_t n    = 0;
      for (unsigned int c = 0; c < matrix_free.n_cell_batches(); ++c)
        n += info.get_cell_type(c) == GeometryType::general
               ? VA::size() * Eval::static_n_q_points * 10
               : VA::size() * 10;
      return n;
    }

    const NeoHookeanPenalty law;
    const Variant           variant;
    MF                      matrix_free;
    Vector                  u; ///< ghosted
    /// Whether the MatrixFree has its boundary faces (follower pressure).
    bool with_faces = false;
    /// Whether a constraint couples DoFs (hanging nodes, sliding
    /// boundaries), not only zeros them.
    bool coupled_constraints = false;
    /// The constraints of the Q1 level (DoF handler 1), if any.
    const dealii::AffineConstraints<double> *coarse_constraints = nullptr;
    /// The follower pressure [kPa] per boundary id (set_follower_pressure();
    /// at the displacement u).
    std::map<dealii::types::boundary_id, double> face_pressures;

    /// MatrixFreeTangent::set_follower_pressure().
    void
    set_follower_pressure(
      const Vector                                       &u_in,
      const std::map<dealii::types::boundary_id, double> &pressures)
    {
      face_pressures.clear();
      for (const auto &[id, p] : pressures)
        if (p != 0.0)
          face_pressures[id] = p;
      AssertThrow(face_pressures.empty() || with_faces,
                  dealii::ExcMessage(
                    "MatrixFreeTangent: this tangent was built without its "
                    "boundary faces (no follower pressure)."));
      u.copy_locally_owned_data_from(u_in);
      u.update_ghost_values();
    }

    /// The Q1 stiffness of the stored tangent (the same points, the Q1
    /// shape functions of DoF handler 1): the Galerkin projection of the
    /// bulk term onto Q1, added to @p matrix (a PETSc matrix in the
    /// numbering of the coarse DoFHandler; constrained rows as
    /// AffineConstraints leaves them: the caller adds their diagonal).
    template <typename Matrix>
    void
    add_coarse_matrix(Matrix &matrix) const;
    /// The pressure rows of a mixed formulation (update_from() with the
    /// pressure coupling; inactive otherwise): apply_cached() adds the
    /// augmented Lagrangian's B^T gamma W^-1 B.
    PressureCoupling<VA, Eval::static_n_q_points> pressure;
    /// Per cell batch and point: the 45 tangent entries (cached) or the
    /// law's state (recompute).
    dealii::AlignedVector<VA> storage;
    /// The 45 tangent entries of Variant::cached_single.
    dealii::AlignedVector<VAf> storage_single;

    /// Whether the tangent is stored (in double or single precision).
    bool
    cached() const
    {
      return variant != Variant::recompute;
    }

  private:
    using State = NeoHookeanPenalty::State<VA>;

    /// Numbers stored per point.
    unsigned int
    per_point() const
    {
      return cached() ? n_sym : State::n_numbers;
    }

    const VA *
    point(const unsigned int cell, const unsigned int q) const
    {
      return &storage[(cell * Eval::static_n_q_points + q) * per_point()];
    }
    VA *
    point(const unsigned int cell, const unsigned int q)
    {
      return &storage[(cell * Eval::static_n_q_points + q) * per_point()];
    }
    const VAf *
    point_single(const unsigned int cell, const unsigned int q) const
    {
      return &storage_single[(cell * Eval::static_n_q_points + q) * n_sym];
    }

    /// The lanes of @p x in double precision.
    static VA
    to_double(const VAf &x)
    {
      VA result;
#if defined(__AVX512F__)
      // One conversion instruction for the 8-lane build.
      if constexpr (VA::size() == 8)
        {
          result.data = _mm512_cvtps_pd(x.data);
          return result;
        }
#endif
      for (unsigned int l = 0; l < VA::size(); ++l)
        result[l] = x[l];
      return result;
    }
    static const VA &
    to_double(const VA &x)
    {
      return x;
    }

    /// The state of the law at a point to and from its storage.
    static void
    store(const State &state, VA *s)
    {
      for (unsigned int a = 0; a < 9; ++a)
        {
          s[a]     = state.F[a / 3][a % 3];
          s[9 + a] = state.FinvT[a / 3][a % 3];
        }
      s[18] = state.a;
      s[19] = state.g;
      s[20] = state.kJ2;
      s[21] = state.I1_3;
    }
    static State
    load(const VA *s)
    {
      State state;
      for (unsigned int a = 0; a < 9; ++a)
        {
          state.F[a / 3][a % 3]     = s[a];
          state.FinvT[a / 3][a % 3] = s[9 + a];
        }
      state.a    = s[18];
      state.g    = s[19];
      state.kJ2  = s[20];
      state.I1_3 = s[21];
      return state;
    }

    /// F = I + grad u at point @p q of @p phi (gradients evaluated).
    static Grad
    deformation_gradient(const Eval &phi, const unsigned int q)
    {
      Grad F = phi.get_gradient(q);
      for (unsigned int d = 0; d < 3; ++d)
        F[d][d] += 1.0;
      return F;
    }

    /// dst = K src (dst += K src with @p add); constrained rows: the
    /// identity.
    void
    apply(Vector &dst, const Vector &src, const bool add) const
    {
      if (face_pressures.empty())
        matrix_free.cell_loop(
          &TangentOperator::loop_cells<&TangentOperator::apply_batch>,
          this,
          dst,
          src,
          /*zero_dst_vector=*/!add);
      else
        matrix_free.loop(
          &TangentOperator::loop_cells<&TangentOperator::apply_batch>,
          &TangentOperator::no_inner_faces,
          &TangentOperator::apply_boundary_faces,
          this,
          dst,
          src,
          /*zero_dst_vector=*/!add);
      for (const unsigned int i : matrix_free.get_constrained_dofs())
        if (add)
          dst.local_element(i) += src.local_element(i);
        else
          dst.local_element(i) = src.local_element(i);
    }

    /// A worker of MatrixFree::cell_loop(): per cell batch of @p cells,
    /// @p batch reads @p src into phi and submits its gradients, which are
    /// integrated and added to @p dst.
    template <void (
      TangentOperator::*batch)(Eval &, const Vector &, const Range &) const>
    void
    loop_cells(const MF &,
               Vector       &dst,
               const Vector &src,
               const Range  &cells) const
    {
      Eval phi(matrix_free);
      for (unsigned int cell = cells.first; cell < cells.second; ++cell)
        {
          phi.reinit(cell);
          (this->*batch)(phi, src, cells);
          phi.integrate_scatter(dealii::EvaluationFlags::gradients, dst);
        }
    }

    void
    no_inner_faces(const MF &, Vector &, const Vector &, const Range &) const
    {}

    /// The follower pressure's stiffness on the boundary faces @p faces:
    /// p int phi_a . (dcof(F)[grad phi_b]) N dA (the assembly's
    /// add_volume_flux() with the scale p; cof F quadratic in F:
    /// (dcof(F)[G] N)_i = eps_ijk eps_JKL G_jK F_kL N_J).
    void
    apply_boundary_faces(const MF &,
                         Vector       &dst,
                         const Vector &src,
                         const Range  &faces) const
    {
      const auto &perm = levi_civita;
      FaceEval    phi(matrix_free, true), phi_u(matrix_free, true);
      for (unsigned int face = faces.first; face < faces.second; ++face)
        {
          const auto p = face_pressures.find(matrix_free.get_boundary_id(face));
          if (p == face_pressures.end())
            continue;
          phi_u.reinit(face);
          phi_u.read_dof_values_plain(u);
          phi_u.evaluate(dealii::EvaluationFlags::gradients);
          phi.reinit(face);
          phi.gather_evaluate(src, dealii::EvaluationFlags::gradients);
          for (unsigned int q = 0; q < phi.n_q_points; ++q)
            {
              Grad F = phi_u.get_gradient(q);
              for (unsigned int d = 0; d < 3; ++d)
                F[d][d] += 1.0;
              const auto               N = phi.get_normal_vector(q);
              const Grad               G = phi.get_gradient(q);
              dealii::Tensor<1, 3, VA> value;
              for (const auto &a : perm)
                for (const auto &b : perm)
                  value[a[0]] += (a[3] * b[3] * p->second) * G[a[1]][b[1]] *
                                 F[a[2]][b[2]] * N[b[0]];
              phi.submit_value(value, q);
            }
          phi.integrate_scatter(dealii::EvaluationFlags::values, dst);
        }
    }

    /// K src on the batch of @p phi (one of @p cells).
    void
    apply_batch(Eval &phi, const Vector &src, const Range &cells) const;

    /// R(src) on the batch of @p phi.
    void
    residual_batch(Eval &phi, const Vector &src, const Range &) const;

    /// out = A h with A the upper triangle of a symmetric 9 x 9 matrix, row
    /// by row.
    template <typename Stored>
    static void
    apply_symmetric(const Stored *A, const VA *h, VA *out)
    {
      for (unsigned int a = 0; a < 9; ++a)
        out[a] = 0.0;
      unsigned int index = 0;
      for (unsigned int a = 0; a < 9; ++a)
        {
          out[a] += to_double(A[index++]) * h[a];
          for (unsigned int b = a + 1; b < 9; ++b, ++index)
            {
              const VA entry = to_double(A[index]);
              out[a] += entry * h[b];
              out[b] += entry * h[a];
            }
        }
    }

    /// The cached operator at the points of the batch @p cell, on the
    /// gradients of @p phi in unit-cell coordinates (in place: what
    /// integrate() takes), so that no geometry is read.
    template <typename Evaluation = Eval>
    void
    apply_cached(Evaluation &phi, const unsigned int cell) const
    {
      constexpr unsigned int n_q = Evaluation::static_n_q_points;
      static_assert(n_q == Eval::static_n_q_points);
      VA *g = phi.begin_gradients();
      // (The augmented Lagrangian reads B u before g is overwritten.)
      const auto b = pressure.active() ? pressure.rows(cell, g)
                                       : decltype(pressure.rows(cell, g))();
      for (unsigned int q = 0; q < n_q; ++q)
        {
          // Entry 3 i + alpha: component i, unit direction alpha.
          std::array<VA, 9> h, out;
          for (unsigned int a = 0; a < 9; ++a)
            h[a] = g[a * n_q + q];
          if (variant == Variant::cached_single)
            apply_symmetric(point_single(cell, q), h.data(), out.data());
          else
            apply_symmetric(point(cell, q), h.data(), out.data());
          for (unsigned int a = 0; a < 9; ++a)
            g[a * n_q + q] = out[a];
        }
      if (pressure.active())
        pressure.add_augmentation(cell, b, g);
    }

    /// The cached tangent at one point, pulled back to the unit cell: the
    /// upper triangle of
    /// @f$\hat A_{(i\alpha)(k\beta)} = JxW\, G_{J\alpha} A_{iJkL} G_{L\beta}@f$
    /// (A = dP/dF, G the inverse Jacobian as deal.II stores it: physical
    /// gradient_J = sum_alpha G_{J alpha} unit gradient_alpha), built column
    /// by column from @p linearization (H -> dP = A : H: the law's
    /// linearization() or the caller's A).
    template <typename Linearization>
    static void
    pulled_back_tangent(const Linearization &linearization,
                        const Grad          &inverse_jacobian,
                        const VA            &JxW,
                        VA                  *A)
    {
      std::array<std::array<VA, 9>, 9> columns;
      for (unsigned int b = 0; b < 9; ++b)
        {
          const unsigned int k = b / 3, beta = b % 3;
          Grad               H; // physical gradient of e_k N, unit grad e_beta
          for (unsigned int L = 0; L < 3; ++L)
            H[k][L] = inverse_jacobian[L][beta];
          const Grad dP = linearization(H);
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int alpha = 0; alpha < 3; ++alpha)
              {
                VA sum = 0.0;
                for (unsigned int J = 0; J < 3; ++J)
                  sum += inverse_jacobian[J][alpha] * dP[i][J];
                columns[b][3 * i + alpha] = JxW * sum;
              }
        }
      unsigned int index = 0;
      for (unsigned int a = 0; a < 9; ++a)
        for (unsigned int b = a; b < 9; ++b, ++index)
          // Symmetric up to round-off; average the two halves.
          A[index] = 0.5 * (columns[b][a] + columns[a][b]);
    }

    /// pulled_back_tangent() with the law's linearization at @p state.
    void
    tangent_of(const State &state,
               const Grad  &inverse_jacobian,
               const VA    &JxW,
               VA          *A) const
    {
      pulled_back_tangent(
        [&](const Grad &H) { return law.linearization(state, H); },
        inverse_jacobian,
        JxW,
        A);
    }

    /// The pressure coupling's shape values (of @p element at the points)
    /// and its storage.
    void
    pressure_shape_values(const dealii::FiniteElement<3> &element);

    /// Size the point storage for update() and update_from().
    void
    resize_storage()
    {
      const std::size_t n_points =
        static_cast<std::size_t>(matrix_free.n_cell_batches()) *
        Eval::static_n_q_points;
      if (variant == Variant::cached_single)
        storage_single.resize(n_points * n_sym);
      // (cached_single: one point's tangent in double before rounding)
      storage.resize(
        variant == Variant::cached_single ? n_sym : n_points * per_point());
    }

    /// Store the tangent @p A (double) of point @p q of the batch @p cell,
    /// for cached_single in single precision.
    void
    store_tangent(const unsigned int cell, const unsigned int q)
    {
      if (variant != Variant::cached_single)
        return; // tangent_of() wrote it in place
      VAf *single =
        &storage_single[(cell * Eval::static_n_q_points + q) * n_sym];
      for (unsigned int a = 0; a < n_sym; ++a)
        for (unsigned int l = 0; l < VA::size(); ++l)
          single[a][l] = static_cast<float>(storage[a][l]);
    }

    /// Where tangent_of() writes the tangent of point @p q of the batch
    /// @p cell (cached_single: the buffer store_tangent() rounds).
    VA *
    tangent_destination(const unsigned int cell, const unsigned int q)
    {
      return variant == Variant::cached_single ? &storage[0] : point(cell, q);
    }
  };


  template <typename VA>
  void
  TangentOperator<VA>::update(const Vector &u_in)
  {
    u.copy_locally_owned_data_from(u_in);
    u.update_ghost_values();
    resize_storage();
    Eval   phi(matrix_free);
    double min_J = 1.0;
    for (unsigned int cell = 0; cell < matrix_free.n_cell_batches(); ++cell)
      {
        phi.reinit(cell);
        phi.read_dof_values_plain(u);
        phi.evaluate(dealii::EvaluationFlags::gradients);
        const unsigned int lanes =
          matrix_free.n_active_entries_per_cell_batch(cell);
        for (unsigned int q = 0; q < phi.n_q_points; ++q)
          {
            const Grad F = deformation_gradient(phi, q);
            const VA   J = determinant(F);
            for (unsigned int l = 0; l < lanes; ++l)
              min_J = std::min(min_J, J[l]);
            const State state = law.state(F);
            if (variant == Variant::recompute)
              store(state, point(cell, q));
            else
              {
                tangent_of(state,
                           phi.inverse_jacobian(q),
                           phi.JxW(q),
                           tangent_destination(cell, q));
                store_tangent(cell, q);
              }
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


  template <typename VA>
  void
  TangentOperator<VA>::update_from(
    const MatrixFreeTangent::CellTangents &tangents)
  {
    update_from(
      [&tangents](const dealii::DoFHandler<3>::cell_iterator &cell,
                  std::vector<dealii::Tensor<4, 3>>          &A,
                  std::vector<MatrixFreeTangent::PointPressure> &) {
        tangents(cell, A);
      },
      MatrixFreeTangent::MixedConstants());
  }


  template <typename VA>
  void
  TangentOperator<VA>::update_from(
    const MatrixFreeTangent::MixedCellTangents &tangents,
    const MatrixFreeTangent::MixedConstants    &constants)
  {
    AssertThrow(cached(), dealii::ExcInternalError());
    resize_storage();
    constexpr unsigned int n_q   = Eval::static_n_q_points;
    const bool             mixed = constants.pressure_element != nullptr;
    if (mixed)
      pressure_shape_values(*constants.pressure_element);
    using Tangent = dealii::Tensor<4, 3, VA>;
    std::vector<dealii::Tensor<4, 3>>             lane(n_q);
    std::vector<MatrixFreeTangent::PointPressure> lane_p(n_q);
    std::vector<Tangent>                          batch(n_q);
    std::vector<Grad>                             cofactor(n_q);
    std::vector<double> JxW(n_q), weight(n_q), schur(n_q);
    Eval                phi(matrix_free);
    for (unsigned int cell = 0; cell < matrix_free.n_cell_batches(); ++cell)
      {
        phi.reinit(cell);
        // The lanes of the batch; the empty ones keep a zero tangent.
        std::fill(batch.begin(), batch.end(), Tangent());
        std::fill(cofactor.begin(), cofactor.end(), Grad());
        for (unsigned int l = 0;
             l < matrix_free.n_active_entries_per_cell_batch(cell);
             ++l)
          {
            tangents(matrix_free.get_cell_iterator(cell, l), lane, lane_p);
            AssertThrow(lane.size() == n_q, dealii::ExcInternalError());
            for (unsigned int q = 0; q < n_q; ++q)
              for (unsigned int e = 0; e < 81; ++e)
                {
                  const auto index = Tangent::unrolled_to_component_indices(e);
                  batch[q][index][l] = lane[q][index];
                }
            if (!mixed)
              continue;
            for (unsigned int q = 0; q < n_q; ++q)
              {
                for (unsigned int e = 0; e < 9; ++e)
                  cofactor[q][e / 3][e % 3][l] =
                    lane_p[q].cofactor[e / 3][e % 3];
                JxW[q]    = phi.JxW(q)[l];
                weight[q] = lane_p[q].augmentation_weight;
                schur[q]  = lane_p[q].schur_weight;
              }
            pressure.set_matrices(cell,
                                  l,
                                  JxW,
                                  weight,
                                  schur,
                                  constants.inverse_kappa,
                                  constants.gamma);
          }
        for (unsigned int q = 0; q < n_q; ++q)
          {
            const Tangent &A = batch[q];
            pulled_back_tangent(
              [&A](const Grad &H) {
                return dealii::double_contract<2, 0, 3, 1>(A, H);
              },
              phi.inverse_jacobian(q),
              phi.JxW(q),
              tangent_destination(cell, q));
            store_tangent(cell, q);
            if (mixed)
              pressure.set_d(cell,
                             q,
                             cofactor[q],
                             phi.inverse_jacobian(q),
                             phi.JxW(q));
          }
      }
  }


  template <typename VA>
  void
  TangentOperator<VA>::pressure_shape_values(
    const dealii::FiniteElement<3> &element)
  {
    AssertThrow(element.n_dofs_per_cell() == decltype(pressure)::n_p &&
                  element.n_components() == 1,
                dealii::ExcMessage(
                  "The matrix-free mixed tangent needs a discontinuous P1 "
                  "pressure (four DoFs per hexahedron); got " +
                  element.get_name() + "."));
    const dealii::QGauss<3> rule(n_q_1d);
    pressure.psi.resize(decltype(pressure)::n_p);
    for (unsigned int k = 0; k < pressure.psi.size(); ++k)
      for (unsigned int q = 0; q < rule.size(); ++q)
        pressure.psi[k][q] = element.shape_value(k, rule.point(q));
    pressure.storage.resize(
      static_cast<std::size_t>(matrix_free.n_cell_batches()) *
      decltype(pressure)::per_batch);
  }


  template <typename VA>
  void
  TangentOperator<VA>::compute_inverse_diagonal(Vector &inverse) const
  {
    AssertThrow(cached(), dealii::ExcNotImplemented());
    matrix_free.initialize_dof_vector(inverse);
    if (coupled_constraints)
      // (The condensed diagonal: deal.II's, column by column.)
      dealii::MatrixFreeTools::compute_diagonal(
        matrix_free,
        inverse,
        std::function<void(Eval &)>([this](Eval &phi) {
          phi.evaluate(dealii::EvaluationFlags::gradients);
          apply_cached(phi, phi.get_current_cell_index());
          phi.integrate(dealii::EvaluationFlags::gradients);
        }));
    else
      add_point_diagonal(inverse);
    for (const unsigned int i : matrix_free.get_constrained_dofs())
      inverse.local_element(i) = 1.0;
    for (unsigned int i = 0; i < inverse.locally_owned_size(); ++i)
      {
        const double d = inverse.local_element(i);
        AssertThrow(d > 0.0,
                    dealii::ExcMessage("MatrixFreeTangent: a diagonal entry "
                                       "of the tangent is not positive (" +
                                       std::to_string(d) + ")."));
        inverse.local_element(i) = 1.0 / d;
      }
  }


  template <typename VA>
  void
  TangentOperator<VA>::add_point_diagonal(Vector &diagonal) const
  {
    // K_ii of the shape function i = (component c, node A) straight from the
    // stored points: sum_q g_A(q)^T Ahat_q[c c] g_A(q) (+ b^T Gamma b, b = B
    // e_i, with the pressure coupling), g_A the unit-cell gradient of node
    // A: a few numbers per point, where deal.II's compute_diagonal() applies
    // the cell operator to each of the 81 unit vectors of a cell.
    constexpr unsigned int n_q   = Eval::static_n_q_points;
    constexpr unsigned int n_1d  = degree + 1;
    constexpr unsigned int nodes = n_1d * n_1d * n_1d;
    const auto            &shape = matrix_free.get_shape_info(0).data[0];
    std::vector<std::array<std::array<double, 3>, n_q>> grad(nodes);
    for (unsigned int A = 0; A < nodes; ++A)
      for (unsigned int q = 0; q < n_q; ++q)
        {
          const unsigned int a[3] = {A % n_1d,
                                     (A / n_1d) % n_1d,
                                     A / (n_1d * n_1d)};
          const unsigned int p[3] = {q % n_q_1d,
                                     (q / n_q_1d) % n_q_1d,
                                     q / (n_q_1d * n_q_1d)};
          for (unsigned int d = 0; d < 3; ++d)
            {
              double g = 1.0;
              for (unsigned int e = 0; e < 3; ++e)
                g *= e == d ? shape.shape_gradients[a[e] * n_q_1d + p[e]][0]
                            : shape.shape_values[a[e] * n_q_1d + p[e]][0];
              grad[A][q][d] = g;
            }
        }
    // Index of entry (a, b), a <= b, in the stored upper triangle.
    const auto entry = [](const unsigned int a, const unsigned int b) {
      return 9 * a - a * (a - 1) / 2 + (b - a);
    };
    Eval phi(matrix_free);
    for (unsigned int cell = 0; cell < matrix_free.n_cell_batches(); ++cell)
      {
        phi.reinit(cell);
        for (unsigned int c = 0; c < 3; ++c)
          for (unsigned int A = 0; A < nodes; ++A)
            {
              VA                                      D = 0.0;
              std::array<VA, decltype(pressure)::n_p> b;
              for (auto &x : b)
                x = 0.0;
              for (unsigned int q = 0; q < n_q; ++q)
                {
                  const auto &h = grad[A][q];
                  for (unsigned int al = 0; al < 3; ++al)
                    for (unsigned int be = 0; be < 3; ++be)
                      {
                        const unsigned int i = 3 * c + std::min(al, be);
                        const unsigned int j = 3 * c + std::max(al, be);
                        const VA           Aq =
                          variant == Variant::cached_single
                                      ? to_double(point_single(cell, q)[entry(i, j)])
                                      : point(cell, q)[entry(i, j)];
                        D += (h[al] * h[be]) * Aq;
                      }
                  if (pressure.active())
                    {
                      const VA *dq  = pressure.d(cell, q);
                      const VA  dot = dq[3 * c] * h[0] + dq[3 * c + 1] * h[1] +
                                     dq[3 * c + 2] * h[2];
                      for (unsigned int k = 0; k < b.size(); ++k)
                        b[k] -= pressure.psi[k][q] * dot;
                    }
                }
              if (pressure.active())
                {
                  const auto Gb =
                    pressure.multiply(cell,
                                      decltype(pressure)::gamma_inverse_weight,
                                      b);
                  for (unsigned int k = 0; k < b.size(); ++k)
                    D += b[k] * Gb[k];
                }
              phi.begin_dof_values()[c * nodes + A] = D;
            }
        phi.distribute_local_to_global(diagonal);
      }
    diagonal.compress(dealii::VectorOperation::add);
  }


  template <typename VA>
  template <typename Matrix>
  void
  TangentOperator<VA>::add_coarse_matrix(Matrix &matrix) const
  {
    AssertThrow(cached() && coarse_constraints != nullptr,
                dealii::ExcInternalError());
    // As deal.II's MatrixFreeTools::compute_matrix(), into a PETSc matrix.
    Eval1              phi(matrix_free, 1);
    const unsigned int n = phi.dofs_per_cell;
    const auto        &lexicographic =
      matrix_free.get_shape_info(1).lexicographic_numbering;
    const dealii::AffineConstraints<double> &constraints = *coarse_constraints;
    std::array<dealii::FullMatrix<double>, VA::size()> cell_matrices;
    for (auto &m : cell_matrices)
      m.reinit(n, n);
    std::vector<dealii::types::global_dof_index> dofs(n), dofs_mf(n);
    for (unsigned int cell = 0; cell < matrix_free.n_cell_batches(); ++cell)
      {
        phi.reinit(cell);
        const unsigned int lanes =
          matrix_free.n_active_entries_per_cell_batch(cell);
        for (unsigned int j = 0; j < n; ++j)
          {
            for (unsigned int i = 0; i < n; ++i)
              phi.begin_dof_values()[i] = static_cast<double>(i == j);
            phi.evaluate(dealii::EvaluationFlags::gradients);
            apply_cached(phi, cell);
            phi.integrate(dealii::EvaluationFlags::gradients);
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int l = 0; l < lanes; ++l)
                cell_matrices[l](i, j) = phi.begin_dof_values()[i][l];
          }
        for (unsigned int l = 0; l < lanes; ++l)
          {
            matrix_free.get_cell_iterator(cell, l, 1)->get_dof_indices(dofs);
            for (unsigned int j = 0; j < n; ++j)
              dofs_mf[j] = dofs[lexicographic[j]];
            constraints.distribute_local_to_global(cell_matrices[l],
                                                   dofs_mf,
                                                   matrix);
          }
      }
    matrix.compress(dealii::VectorOperation::add);
  }


  template <typename VA>
  void
  TangentOperator<VA>::apply_batch(Eval         &phi,
                                   const Vector &src,
                                   const Range  &cells) const
  {
    const unsigned int cell = phi.get_current_cell_index();
    // Start loading the next batch's point data while this one's sum
    // factorization runs (the cached tangent is streamed from memory).
    if (cell + 1 < cells.second)
      {
        const bool  single = variant == Variant::cached_single;
        const char *next =
          single ? reinterpret_cast<const char *>(point_single(cell + 1, 0))
                 : reinterpret_cast<const char *>(point(cell + 1, 0));
        const std::size_t bytes = (single ? sizeof(VAf) : sizeof(VA)) *
                                  per_point() * Eval::static_n_q_points;
        for (std::size_t offset = 0; offset < bytes; offset += 64)
          __builtin_prefetch(next + offset, 0, 1);
      }
    phi.gather_evaluate(src, dealii::EvaluationFlags::gradients);
    if (cached())
      apply_cached(phi, cell);
    else
      for (unsigned int q = 0; q < phi.n_q_points; ++q)
        phi.submit_gradient(law.linearization(load(point(cell, q)),
                                              phi.get_gradient(q)),
                            q);
  }


  template <typename VA>
  void
  TangentOperator<VA>::residual_batch(Eval         &phi,
                                      const Vector &src,
                                      const Range &) const
  {
    phi.read_dof_values_plain(src);
    phi.evaluate(dealii::EvaluationFlags::gradients);
    for (unsigned int q = 0; q < phi.n_q_points; ++q)
      {
        Grad P;
        law.evaluate<VA>(deformation_gradient(phi, q), nullptr, P, nullptr);
        phi.submit_gradient(P, q);
      }
  }

  /// The vectorization of the matrix-free mechanics: cell batches of
  /// SYSTOLE_MATRIX_FREE_LANES cells (matrix_free_simd.h; 1 on the
  /// installed deal.II's own width).
  using Lanes = dealii::VectorizedArray<double, SYSTOLE_MATRIX_FREE_LANES>;

  /// The operator on those lanes (MatrixFreeTangent's) and the Chebyshev
  /// smoother on its inverse diagonal: the levels of MatrixFreeMultigrid,
  /// the Q2 level of MatrixFreeSolver.
  using Operator = TangentOperator<Lanes>;
  using Smoother =
    dealii::PreconditionChebyshev<Operator,
                                  Operator::Vector,
                                  dealii::DiagonalMatrix<Operator::Vector>>;
} // namespace systole::Mechanics::internal

namespace systole::Mechanics
{
  /// The operator of MatrixFreeTangent on the matrix-free mechanics' width.
  struct MatrixFreeTangent::Impl : public internal::Operator
  {
    using internal::Operator::TangentOperator;

    /// Built without a law: the point tangents come from the caller.
    bool general = false;
  };
} // namespace systole::Mechanics
