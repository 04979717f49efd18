// Residual and consistent tangent of the quasi-static mechanics, as a sum of
// terms: the bulk (passive + volumetric or pressure + active), the volume
// flux of the pressure boundary, and the Robin springs.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "base/errors.h"
#include "materials/active_stress.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/problem_impl.h"
#include "mechanics/surface_terms.h"

#include <algorithm>
#include <array>

namespace systole::Mechanics
{
  namespace
  {
    using dealii::SymmetricTensor;
    using dealii::Tensor;

    /// The cell-local arrays every term adds to.
    struct CellSystem
    {
      /// @p n DoFs per cell, @p n_cavities cavities.
      CellSystem(const unsigned int n, const unsigned int n_cavities)
        : matrix(n, n)
        , residual(n)
        , volume_derivative(n_cavities, dealii::Vector<double>(n))
        , on_cavity(n_cavities, false)
      {}

      dealii::FullMatrix<double> matrix;
      dealii::Vector<double>     residual;
      /// dV_i/du of each cavity, and whether the cell has faces on it.
      std::vector<dealii::Vector<double>> volume_derivative;
      std::vector<bool>                   on_cavity;
      /// The Schur-complement preconditioner on the pressure DoFs of the cell.
      dealii::FullMatrix<double> pressure_matrix;
      /// The augmented Lagrangian's weight W = int (1/kappa + 1/mu) psi psi
      /// of the cell, its inverse, and gamma B^T W^-1 (displacement rows,
      /// pressure columns).
      dealii::FullMatrix<double> pressure_weight, inverse_weight, coupling;
    };

    /// Per shape function: block, component, the gradient of its only
    /// nonzero component, J F^{-T} : grad phi and the pressure values; per
    /// node of the displacement element: its three DoFs and scalar gradient;
    /// the displacement block of the cell matrix by node pairs.
    struct ShapeScratch
    {
      explicit ShapeScratch(const dealii::FiniteElement<3> &fe)
        : component(fe.n_dofs_per_cell())
        , grad_phi(fe.n_dofs_per_cell())
        , div_phi(fe.n_dofs_per_cell())
        , psi(fe.n_dofs_per_cell())
      {
        for (unsigned int a = 0; a < fe.n_dofs_per_cell(); ++a)
          {
            const auto [c, index] = fe.system_to_component_index(a);
            component[a]          = c;
            if (c < 3)
              {
                u_dofs.push_back(a);
                if (index >= node_dofs.size())
                  node_dofs.resize(index + 1);
                node_dofs[index][c] = a;
              }
            else
              p_dofs.push_back(a);
          }
        AssertThrow(3 * node_dofs.size() == u_dofs.size(),
                    dealii::ExcInternalError());
        node_grad.resize(node_dofs.size());
        uu.resize(node_dofs.size() * node_dofs.size() * 9);
      }

      std::vector<unsigned int>                component, u_dofs, p_dofs;
      std::vector<std::array<unsigned int, 3>> node_dofs;
      std::vector<Tensor<1, 3>>                grad_phi, node_grad;
      /// J F^{-T} : grad phi (u) and the pressure shape values (p).
      std::vector<double> div_phi, psi;
      /// K_(A c)(B d) of node pairs A <= B at uu[(B n + A) 9 + 3 c + d].
      std::vector<double> uu;
    };

    /// Bulk term at one point, displacement rows and columns:
    /// R_a += P : grad phi_a, K_ab += dE_a : dS/dE : dE_b + S : (grad phi_a^T
    /// grad phi_b) (material and geometric stiffness), for the stress S and
    /// tangent dS/dE of everything at the point (passive, volumetric or
    /// pressure, active). With phi_a = N_A e_c, dE_a = sym(F^T e_c x grad
    /// N_A), so the 3 x 3 block of nodes A, B is
    /// K_(A c)(B d) = grad N_A . D_c.d. grad N_B with
    /// D_cJdL = F_cI C_IJKL F_dK + delta_cd S_JL (one 81-entry tensor per
    /// point instead of one contraction per pair of shape functions).
    void
    add_stress_point(const dealii::FEValues<3>   &values,
                     const unsigned int           q,
                     const Tensor<2, 3>          &F,
                     const SymmetricTensor<2, 3> &S,
                     const SymmetricTensor<4, 3> &dS_dE,
                     const bool                   with_matrix,
                     ShapeScratch                &s,
                     CellSystem                  &cell)
    {
      const Tensor<2, 3> P   = F * Tensor<2, 3>(S);
      const double       JxW = values.JxW(q);
      const unsigned int n   = s.node_dofs.size();
      for (unsigned int A = 0; A < n; ++A)
        {
          const Tensor<1, 3> g = values.shape_grad(s.node_dofs[A][0], q);
          s.node_grad[A]       = g;
          for (unsigned int c = 0; c < 3; ++c)
            {
              const unsigned int a = s.node_dofs[A][c];
              s.grad_phi[a]        = g;
              cell.residual(a) += (P[c] * g) * JxW;
            }
        }
      if (!with_matrix)
        return;

      double C[3][3][3][3], T[3][3][3][3], D[3][3][3][3];
      for (unsigned int I = 0; I < 3; ++I)
        for (unsigned int J = 0; J < 3; ++J)
          for (unsigned int K = 0; K < 3; ++K)
            for (unsigned int L = 0; L < 3; ++L)
              C[I][J][K][L] = dS_dE[I][J][K][L];
      for (unsigned int c = 0; c < 3; ++c)
        for (unsigned int J = 0; J < 3; ++J)
          for (unsigned int K = 0; K < 3; ++K)
            for (unsigned int L = 0; L < 3; ++L)
              T[c][J][K][L] = F[c][0] * C[0][J][K][L] +
                              F[c][1] * C[1][J][K][L] + F[c][2] * C[2][J][K][L];
      for (unsigned int c = 0; c < 3; ++c)
        for (unsigned int J = 0; J < 3; ++J)
          for (unsigned int d = 0; d < 3; ++d)
            for (unsigned int L = 0; L < 3; ++L)
              D[c][J][d][L] =
                (T[c][J][0][L] * F[d][0] + T[c][J][1][L] * F[d][1] +
                 T[c][J][2][L] * F[d][2] + (c == d ? S[J][L] : 0.0)) *
                JxW;

      for (unsigned int B = 0; B < n; ++B)
        {
          // h_cJd = D_cJdL grad N_B,L
          const Tensor<1, 3> &gB = s.node_grad[B];
          double              h[3][3][3];
          for (unsigned int c = 0; c < 3; ++c)
            for (unsigned int J = 0; J < 3; ++J)
              for (unsigned int d = 0; d < 3; ++d)
                h[c][J][d] = D[c][J][d][0] * gB[0] + D[c][J][d][1] * gB[1] +
                             D[c][J][d][2] * gB[2];
          double *block = &s.uu[B * n * 9];
          for (unsigned int A = 0; A <= B; ++A, block += 9)
            {
              const Tensor<1, 3> &gA = s.node_grad[A];
              for (unsigned int c = 0; c < 3; ++c)
                for (unsigned int d = 0; d < 3; ++d)
                  block[3 * c + d] += gA[0] * h[c][0][d] + gA[1] * h[c][1][d] +
                                      gA[2] * h[c][2][d];
            }
        }
    }

    /// The tangent of the cross-fibre part of a stretch-dependent tension:
    /// dS = c G (f0 x f0 : dE) with G = eta_s s0 x s0 + eta_n n0 x n0 and c
    /// = dT/dlambda / lambda, so K_(Ac)(Bd) += c (F G grad N_A)_c (F f0)_d
    /// (f0 . grad N_B) JxW: rank one per point and not symmetric (every
    /// node pair, into the cell matrix). Needs the node gradients of
    /// add_stress_point().
    void
    add_cross_fibre_tangent(const dealii::FEValues<3>            &values,
                            const unsigned int                    q,
                            const Tensor<2, 3>                   &F,
                            const Fibres::FibreBasis             &basis,
                            const Materials::CrossFibreFractions &cross,
                            const double                          slope,
                            const ShapeScratch                   &s,
                            CellSystem                           &cell)
    {
      const SymmetricTensor<2, 3> G =
        Materials::active_stress_direction(cross, basis) -
        dealii::symmetrize(dealii::outer_product(basis.f, basis.f));
      const Tensor<2, 3> FG = F * Tensor<2, 3>(G);
      const Tensor<1, 3> Ff = F * basis.f;
      const double       w  = slope * values.JxW(q);
      const unsigned int n  = s.node_dofs.size();
      for (unsigned int A = 0; A < n; ++A)
        {
          const Tensor<1, 3> a = FG * s.node_grad[A];
          for (unsigned int B = 0; B < n; ++B)
            {
              const double b = w * (basis.f * s.node_grad[B]);
              for (unsigned int c = 0; c < 3; ++c)
                for (unsigned int d = 0; d < 3; ++d)
                  cell.matrix(s.node_dofs[A][c], s.node_dofs[B][d]) +=
                    a[c] * b * Ff[d];
            }
        }
    }

    /// Move the node-pair blocks of the displacement block (both triangles)
    /// into the cell matrix and zero them.
    void
    finish_displacement_block(ShapeScratch &s, CellSystem &cell)
    {
      const unsigned int n = s.node_dofs.size();
      for (unsigned int B = 0; B < n; ++B)
        for (unsigned int A = 0; A <= B; ++A)
          {
            double *block = &s.uu[(B * n + A) * 9];
            for (unsigned int c = 0; c < 3; ++c)
              for (unsigned int d = 0; d < 3; ++d)
                {
                  const unsigned int a = s.node_dofs[A][c];
                  const unsigned int b = s.node_dofs[B][d];
                  cell.matrix(a, b) += block[3 * c + d];
                  if (A != B)
                    cell.matrix(b, a) += block[3 * c + d];
                }
            std::fill(block, block + 9, 0.0);
          }
    }

    /// Weight of the Schur preconditioner -w int psi psi at a point of
    /// shear stiffness mu (1/mu given) with the augmented Lagrangian gamma.
    /// The Schur complement of T K is S' = -C - (1 - gamma theta) B
    /// A_gamma^-1 B^T with C = M / kappa, A_gamma = A + gamma' B^T M^-1 B,
    /// theta = mu / (kappa + mu), gamma' = gamma / (1/kappa + 1/mu). Taking
    /// B A^-1 B^T ~ M / mu (a Stokes-like A) and the Sherman-Morrison identity
    /// (B A_gamma^-1 B^T)^-1 = (B A^-1 B^T)^-1 + gamma' M^-1 gives w = 1/kappa
    /// + (1 - gamma theta) / (mu + gamma'); gamma = 0: 1/kappa + 1/mu. Where
    /// B A^-1 B^T is far larger than M / mu (the dilations the isochoric A
    /// does not resist), S' stays near -(1/kappa + (1 - gamma theta) /
    /// gamma') M, so the approximation is within about 1 + 1/gamma.
    double
    schur_weight(const double inverse_kappa,
                 const double inverse_mu,
                 const double gamma)
    {
      const double theta =
        inverse_kappa / (inverse_kappa + inverse_mu); // mu / (kappa + mu)
      const double gamma_prime = gamma / (inverse_kappa + inverse_mu);
      return inverse_kappa + std::max(0.0, 1.0 - gamma * theta) /
                               (1.0 / inverse_mu + gamma_prime);
    }

    /// Pressure rows and columns of the mixed formulations at one point
    /// (energy -p (J - 1) - p^2 / (2 kappa)):
    /// R_p,a = -psi_a (J - 1 + p / kappa), K_up = K_pu^T = -J F^{-T} : grad
    /// phi_u psi_p, K_pp = -psi psi / kappa; the displacement rows' share is
    /// in the stress -p J C^{-1} of add_stress_point(). The Schur
    /// preconditioner adds -w psi psi (schur_weight(), mu the shear stiffness
    /// of the point), the augmented Lagrangian's weight (1/kappa + 1/mu) psi
    /// psi.
    void
    add_pressure_point(const dealii::FEValues<3> &values,
                       const unsigned int         q,
                       const Tensor<2, 3>        &F,
                       const double               p,
                       const double               inverse_kappa,
                       const double               inverse_mu,
                       const double               gamma,
                       const bool                 with_matrix,
                       const bool                 with_pressure_matrix,
                       ShapeScratch              &s,
                       CellSystem                &cell)
    {
      const double       J     = dealii::determinant(F);
      const double       JxW   = values.JxW(q);
      const Tensor<2, 3> J_F_T = J * dealii::transpose(dealii::invert(F));
      for (const unsigned int a : s.p_dofs)
        {
          s.psi[a] = values.shape_value(a, q);
          cell.residual(a) -= s.psi[a] * (J - 1.0 + p * inverse_kappa) * JxW;
        }
      if (!with_matrix)
        return;
      // (grad_phi of the displacement functions was set by add_stress_point.)
      for (const unsigned int b : s.u_dofs)
        s.div_phi[b] = J_F_T[s.component[b]] * s.grad_phi[b];
      for (const unsigned int a : s.p_dofs)
        {
          for (const unsigned int b : s.u_dofs)
            {
              const double value = -s.psi[a] * s.div_phi[b] * JxW;
              cell.matrix(a, b) += value;
              cell.matrix(b, a) += value;
            }
          for (const unsigned int b : s.p_dofs)
            cell.matrix(a, b) -= s.psi[a] * s.psi[b] * inverse_kappa * JxW;
        }
      if (with_pressure_matrix)
        {
          const double w = schur_weight(inverse_kappa, inverse_mu, gamma);
          for (unsigned int i = 0; i < s.p_dofs.size(); ++i)
            for (unsigned int j = 0; j < s.p_dofs.size(); ++j)
              {
                const double psi_psi =
                  s.psi[s.p_dofs[i]] * s.psi[s.p_dofs[j]] * JxW;
                cell.pressure_matrix(i, j) -= w * psi_psi;
                if (gamma > 0.0)
                  cell.pressure_weight(i, j) +=
                    (inverse_kappa + inverse_mu) * psi_psi;
              }
        }
    }

    /// The augmented Lagrangian of one cell (T K with T = [I, G; 0, I], G =
    /// gamma B^T W^-1, W = pressure_weight): K_uu += G K_pu, K_up += G K_pp;
    /// coupling = G_e. Exact cell by cell because a discontinuous pressure
    /// makes W block-diagonal by cells.
    void
    add_augmented_lagrangian(const double        gamma,
                             const ShapeScratch &s,
                             CellSystem         &cell)
    {
      const unsigned int n_p = s.p_dofs.size(), n_u = s.u_dofs.size();
      cell.inverse_weight.invert(cell.pressure_weight);
      for (unsigned int i = 0; i < n_u; ++i)
        for (unsigned int k = 0; k < n_p; ++k)
          {
            double g = 0;
            for (unsigned int j = 0; j < n_p; ++j)
              g += cell.matrix(s.p_dofs[j], s.u_dofs[i]) *
                   cell.inverse_weight(j, k);
            cell.coupling(i, k) = gamma * g;
          }
      for (unsigned int i = 0; i < n_u; ++i)
        {
          const unsigned int a = s.u_dofs[i];
          for (unsigned int k = 0; k < n_p; ++k)
            {
              const double g = cell.coupling(i, k);
              if (g == 0.0)
                continue;
              const unsigned int pk = s.p_dofs[k];
              for (const unsigned int b : s.u_dofs)
                cell.matrix(a, b) += g * cell.matrix(pk, b);
              for (const unsigned int b : s.p_dofs)
                cell.matrix(a, b) += g * cell.matrix(pk, b);
            }
        }
    }

    /// Spring-dashpot (Robin) support on one face: R_a += phi_a s (P (alpha
    /// u + beta v))_c with P the support's projection (I, N x N or I - N x
    /// N) and s its taper, and the tangent (alpha + beta dv/du) s phi_a
    /// phi_b P_cd;
    /// @p face_v (the velocity) is read only when @p with_rates.
    void
    add_robin_face(const dealii::FEFaceValues<3>   &fe_face,
                   const std::vector<Tensor<1, 3>> &face_u,
                   const std::vector<Tensor<1, 3>> &face_v,
                   const RobinSupport              &support,
                   const bool                       with_rates,
                   const double                     velocity_coefficient,
                   const bool                       with_matrix,
                   const ShapeScratch              &s,
                   CellSystem                      &cell)
    {
      const double beta = with_rates ? support.damping : 0.0;
      for (const unsigned int q : fe_face.quadrature_point_indices())
        {
          const Tensor<1, 3> &N = fe_face.normal_vector(q);
          // The taper's scale at the reference point, in the weight.
          const double JxW =
            fe_face.JxW(q) * support.scale(fe_face.quadrature_point(q));
          const double k     = support.stiffness + beta * velocity_coefficient;
          Tensor<1, 3> force = support.stiffness * face_u[q];
          if (beta != 0.0)
            force += beta * face_v[q];
          const Tensor<2, 3> P        = support.projection(N);
          const Tensor<1, 3> traction = P * force;
          for (const unsigned int a : s.u_dofs)
            {
              const double phi_a = fe_face.shape_value(a, q);
              if (phi_a == 0.0)
                continue;
              cell.residual(a) += phi_a * traction[s.component[a]] * JxW;
              if (!with_matrix)
                continue;
              for (const unsigned int b : s.u_dofs)
                {
                  const double phi_b    = fe_face.shape_value(b, q);
                  const double coupling = P[s.component[a]][s.component[b]];
                  cell.matrix(a, b) += k * phi_a * phi_b * coupling * JxW;
                }
            }
        }
    }

    /// The part of the Kelvin-Voigt tangent that dE/dt = sym(F^T grad v)
    /// owes to F at a fixed velocity: dS = eta sym(dF^T Fdot), so that
    /// K_(Ac)(Bd) += eta/2 ((F g_B)_c (Fdot g_A)_d + (g_A . g_B)
    /// (F Fdot^T)_cd) (not symmetric; the part through the velocity, eta
    /// dv/du dE, is in dS/dE). Needs the node gradients of
    /// add_stress_point().
    void
    add_viscous_point(const double        JxW,
                      const Tensor<2, 3> &F,
                      const Tensor<2, 3> &F_dot,
                      const double        viscosity,
                      const ShapeScratch &s,
                      CellSystem         &cell)
    {
      const unsigned int        n      = s.node_dofs.size();
      const double              w      = 0.5 * viscosity * JxW;
      const Tensor<2, 3>        F_Fdot = F * dealii::transpose(F_dot);
      std::vector<Tensor<1, 3>> Fg(n), Fdot_g(n);
      for (unsigned int A = 0; A < n; ++A)
        {
          Fg[A]     = F * s.node_grad[A];
          Fdot_g[A] = F_dot * s.node_grad[A];
        }
      for (unsigned int A = 0; A < n; ++A)
        for (unsigned int B = 0; B < n; ++B)
          {
            const double gg = s.node_grad[A] * s.node_grad[B];
            for (unsigned int c = 0; c < 3; ++c)
              for (unsigned int d = 0; d < 3; ++d)
                cell.matrix(s.node_dofs[A][c], s.node_dofs[B][d]) +=
                  w * (Fg[B][c] * Fdot_g[A][d] + gg * F_Fdot[c][d]);
          }
    }

    /// Shear stiffness of a point for the Schur preconditioner: the mean of
    /// the shear entries c_(ij)(ij), i < j, of the spatial tangent
    /// c_ijkl = J^-1 F_iI F_jJ F_kK F_lL (dS/dE)_IJKL of the passive law
    /// (mu for an isotropic linear law; the spatial form follows rotations
    /// and stretches), floored at @p floor.
    double
    shear_stiffness(const Tensor<2, 3>          &F,
                    const SymmetricTensor<4, 3> &dS_dE,
                    const double                 floor)
    {
      const double J  = dealii::determinant(F);
      double       mu = 0;
      for (const auto &[i, j] :
           {std::pair<unsigned int, unsigned int>{0, 1}, {0, 2}, {1, 2}})
        {
          // c_ijij = J^-1 F_iI F_jJ F_iK F_jL C_IJKL
          double c = 0;
          for (unsigned int I = 0; I < 3; ++I)
            for (unsigned int J_ = 0; J_ < 3; ++J_)
              for (unsigned int K = 0; K < 3; ++K)
                for (unsigned int L = 0; L < 3; ++L)
                  c +=
                    F[i][I] * F[j][J_] * F[i][K] * F[j][L] * dS_dE[I][J_][K][L];
          mu += c / J;
        }
      return std::max(mu / 3.0, floor);
    }
  } // namespace

  double
  Problem::Impl::assemble(const dealii::Vector<double> &pressures,
                          const double                  active_tension,
                          const bool                    with_matrix,
                          const bool                    with_volume_derivative)
  {
    dealii::TimerOutput::Scope scope(timer, "Mechanics / assembly");
    last_active_tension = active_tension;
    const bool mixed    = layout.mixed();
    const bool with_pressure_matrix =
      with_matrix && mixed && pressure_matrix != nullptr;

    // The passive (and active) stress is integrated with the full Gauss rule;
    // in the penalty formulation the volumetric penalty may use one point
    // less per direction (selective reduced integration, "Volumetric
    // integration = reduced"), which relieves its locking.
    const dealii::Quadrature<3> quadrature = cell_quadrature(n_q_1d);
    const dealii::Quadrature<3> volumetric_quadrature =
      cell_quadrature(reduced_volumetric ? n_q_1d - 1 : n_q_1d);
    const dealii::Quadrature<2> face_quadrature =
      this->face_quadrature(n_q_face_1d);
    const auto cell_flags = dealii::update_values | dealii::update_gradients |
                            dealii::update_JxW_values;
    dealii::FEValues<3>     fe_values(mapping, *fe, quadrature, cell_flags);
    dealii::FEValues<3>     fe_volumetric(mapping,
                                      *fe,
                                      volumetric_quadrature,
                                      cell_flags);
    dealii::FEFaceValues<3> fe_face(mapping,
                                    *fe,
                                    face_quadrature,
                                    dealii::update_values |
                                      dealii::update_gradients |
                                      dealii::update_quadrature_points |
                                      dealii::update_normal_vectors |
                                      dealii::update_JxW_values);

    const unsigned int n = fe->n_dofs_per_cell();
    CellSystem         cell_system(n, cavities.size());
    ShapeScratch       scratch(*fe);
    cell_system.pressure_matrix.reinit(scratch.p_dofs.size(),
                                       scratch.p_dofs.size());
    // The augmented Lagrangian of the iterative solver (augmentation: G).
    const double gamma = with_pressure_matrix && augmentation != nullptr
                           ? augmented_lagrangian
                           : 0.0;
    if (gamma > 0.0)
      {
        cell_system.pressure_weight.reinit(scratch.p_dofs.size(),
                                           scratch.p_dofs.size());
        cell_system.inverse_weight.reinit(scratch.p_dofs.size(),
                                          scratch.p_dofs.size());
        cell_system.coupling.reinit(scratch.u_dofs.size(),
                                    scratch.p_dofs.size());
      }
    std::vector<dealii::types::global_dof_index> displacement_dofs(
      scratch.u_dofs.size());
    AssertThrow(!with_volume_derivative || !cavities.empty(),
                dealii::ExcMessage("This problem has no cavity."));
    AssertThrow(pressures.size() == pressure_ids.size(),
                dealii::ExcMessage(
                  "Mechanics: " + std::to_string(pressures.size()) +
                  " pressures given for " +
                  std::to_string(pressure_ids.size()) + " pressure parts."));
    std::vector<dealii::types::global_dof_index> dofs(n),
      pressure_dofs(scratch.p_dofs.size());
    std::vector<Tensor<2, 3>> grad_u(quadrature.size()),
      face_grad_u(face_quadrature.size());
    std::vector<double>       p_values(quadrature.size());
    std::vector<Tensor<1, 3>> face_u(face_quadrature.size());
    // Cavities whose pressure loads their moving lid too: the fan's apex c,
    // and the wall's vector area (summed below) for the lid's force on the
    // rim.
    std::vector<dealii::Point<3>> lid_apex(cavities.size());
    std::vector<Tensor<1, 3>>     lid_area(cavities.size());
    // With the matrix: alpha_k = int da_k[phi] dA of each loaded lid's wall
    // (its rank-6 rim-wall coupling, low_rank_u/v).
    std::vector<std::array<LA::MPI::Vector, 3>> lid_alpha(cavities.size());
    std::array<dealii::Vector<double>, 3>       alpha_local;
    for (auto &a : alpha_local)
      a.reinit(n);
    for (unsigned int i = 0; i < cavities.size(); ++i)
      if (lid_loaded(i))
        {
          lid_apex[i] = cavities[i].rim_center(dof_handler, u);
          if (with_matrix)
            for (auto &a : lid_alpha[i])
              a.reinit(owned, comm);
        }

    // Elastodynamics: the residual becomes R(u) + (alpha_f R(u_n) + M
    // A(u)) / (1 - alpha_f), A the effective acceleration (problem_impl.h,
    // Dynamics), and the tangent K + c / (1 - alpha_f) M: the generalized-
    // alpha balance divided by 1 - alpha_f, so that the cavity pressures
    // enter as in the quasi-static residual (dR/dp_i = -dV_i/du, the border
    // of the volume-constrained solves) and the tolerances keep their scale.
    const bool   dynamic = dynamics.started && dynamics.time_step > 0.0;
    const double inertia_weight =
      dynamic ? 1.0 / (1.0 - dynamics.alpha_f) : 0.0;
    const double mass_weight =
      dynamic ? dynamics.effective_mass_coefficient() * inertia_weight : 0.0;
    std::vector<Tensor<1, 3>> acceleration(quadrature.size());
    if (dynamic)
      {
        AssertThrow(!mixed,
                    dealii::ExcMessage("Mechanics: the inertia is implemented "
                                       "for the penalty formulation only."));
        LA::MPI::Vector a(owned, comm), v(owned, comm), A(owned, comm);
        dynamics.rates(u_owned, a, v);
        A = a;
        A *= 1.0 - dynamics.alpha_m;
        A.add(dynamics.alpha_m, dynamics.a_n);
        if (dynamics.mass_damping != 0.0)
          {
            A.add(dynamics.mass_damping * (1.0 - dynamics.alpha_f), v);
            A.add(dynamics.mass_damping * dynamics.alpha_f, dynamics.v_n);
          }
        dynamics.effective_acceleration = A;
        if (params.viscosity != 0.0 || !robin_supports.empty())
          dynamics.velocity = v;
      }
    // The rate terms (Kelvin-Voigt viscosity, dashpots) in a time step and
    // in the accepted state's residual R(u_n, v_n).
    const bool with_rates = dynamics.started && (dynamic || dynamics.accepting);
    const bool viscous    = with_rates && params.viscosity != 0.0;
    const double velocity_coefficient =
      dynamic ? dynamics.velocity_coefficient() : 0.0;
    std::vector<Tensor<2, 3>> grad_v(quadrature.size());
    std::vector<Tensor<1, 3>> face_v(face_quadrature.size());

    if (with_matrix)
      {
        tangent            = 0;
        have_factorization = false; // PETSc would refactorize on next solve
      }
    if (with_pressure_matrix)
      pressure_matrix->zero();
    if (gamma > 0.0)
      *augmentation = 0;
    residual = 0;
    if (with_volume_derivative)
      for (auto &b : volume_derivatives)
        b = 0;

    std::vector<double> tension_trial(
      tension_model != nullptr ? tension_model->n_states() : 0);
    unsigned int inverted = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned() || inverted)
          continue;
        fe_values.reinit(cell);
        fe_values[layout.displacement].get_function_gradients(u, grad_u);
        if (mixed)
          fe_values[layout.pressure].get_function_values(u, p_values);
        if (viscous)
          fe_values[layout.displacement]
            .get_function_gradients(dynamics.velocity, grad_v);
        cell_system.matrix          = 0;
        cell_system.residual        = 0;
        cell_system.pressure_matrix = 0;
        if (gamma > 0.0)
          cell_system.pressure_weight = 0;
        const auto data = point_data.get_data(cell);

        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            Materials::PassiveInput in;
            in.F            = dealii::unit_symmetric_tensor<3>() + grad_u[q];
            in.basis        = data[q]->basis;
            in.with_tangent = with_matrix;
            if (!(dealii::determinant(in.F) > 0.0))
              {
                inverted = 1;
                break;
              }
            Materials::PassiveOutput out;
            passive_law.evaluate(in, out);
            const double inverse_mu =
              with_pressure_matrix
                ? 1.0 /
                    shear_stiffness(in.F, out.dS_dE, reference_shear_stiffness)
                : 0.0;
            if (mixed)
              Materials::add_volumetric_stress(in.F,
                                               -p_values[q],
                                               0.0,
                                               out.S,
                                               out.dS_dE,
                                               with_matrix);
            else if (!reduced_volumetric)
              volumetric_law.add_to(in.F, out.S, out.dS_dE);
            // The active stress comes after the volumetric part: it is not
            // projected.
            double tension = active_tension + data[q]->tension;
            // dT/dlambda / lambda of a stretch-dependent tension, for the
            // tangent of its cross-fibre part.
            double cross_fibre_slope = 0.0;
            if (tension_model != nullptr)
              {
                // Two-way coupling: the model's step at this iterate's
                // stretch, from the accepted state (the trial state is
                // dropped; accept_tension_step() recomputes it).
                double       dT_dstretch, stretch;
                const double model_tension =
                  step_tension_model(*tension_model,
                                     *data[q],
                                     in.F,
                                     tension_time,
                                     tension_time_step,
                                     tension_trial.data(),
                                     dT_dstretch,
                                     stretch);
                data[q]->model_tension = model_tension;
                tension += model_tension;
                // dS/dE += f0 x f0 x dT/dE with dT/dE = dT/dlambda f0 x f0 /
                // lambda (lambda^2 = 1 + 2 f0.E f0). The cross-fibre part
                // (not major symmetric) goes in after add_stress_point().
                if (with_matrix && dT_dstretch != 0.0)
                  {
                    const dealii::SymmetricTensor<2, 3> ff = dealii::symmetrize(
                      dealii::outer_product(in.basis.f, in.basis.f));
                    out.dS_dE +=
                      (dT_dstretch / stretch) * dealii::outer_product(ff, ff);
                    cross_fibre_slope = dT_dstretch / stretch;
                  }
              }
            if (tension != 0.0)
              Materials::add_active_stress(tension,
                                           params.active_cross_fibre,
                                           in.basis,
                                           out.S);
            // Kelvin-Voigt: S += eta dE/dt, dE/dt = sym(F^T grad v); through
            // v (dv/du = gamma / (beta dt)) it stiffens like eta dv/du dE.
            if (viscous)
              {
                out.S +=
                  params.viscosity *
                  dealii::symmetrize(dealii::transpose(in.F) * grad_v[q]);
                if (with_matrix)
                  out.dS_dE += (params.viscosity * velocity_coefficient) *
                               dealii::identity_tensor<3>();
              }
            add_stress_point(fe_values,
                             q,
                             in.F,
                             out.S,
                             out.dS_dE,
                             with_matrix,
                             scratch,
                             cell_system);
            if (cross_fibre_slope != 0.0 && params.active_cross_fibre.any())
              add_cross_fibre_tangent(fe_values,
                                      q,
                                      in.F,
                                      in.basis,
                                      params.active_cross_fibre,
                                      cross_fibre_slope,
                                      scratch,
                                      cell_system);
            if (viscous && with_matrix)
              add_viscous_point(fe_values.JxW(q),
                                in.F,
                                grad_v[q],
                                params.viscosity,
                                scratch,
                                cell_system);
            if (mixed)
              add_pressure_point(fe_values,
                                 q,
                                 in.F,
                                 p_values[q],
                                 inverse_bulk_modulus,
                                 inverse_mu,
                                 gamma,
                                 with_matrix,
                                 with_pressure_matrix,
                                 scratch,
                                 cell_system);
          }

        if (reduced_volumetric && !inverted)
          {
            fe_volumetric.reinit(cell);
            fe_volumetric[layout.displacement].get_function_gradients(u,
                                                                      grad_u);
            for (const unsigned int q :
                 fe_volumetric.quadrature_point_indices())
              {
                const Tensor<2, 3> F =
                  dealii::unit_symmetric_tensor<3>() + grad_u[q];
                if (!(dealii::determinant(F) > 0.0))
                  {
                    inverted = 1;
                    break;
                  }
                SymmetricTensor<2, 3> S;
                SymmetricTensor<4, 3> dS_dE;
                volumetric_law.add_to(F, S, dS_dE);
                add_stress_point(fe_volumetric,
                                 q,
                                 F,
                                 S,
                                 dS_dE,
                                 with_matrix,
                                 scratch,
                                 cell_system);
              }
          }
        if (inverted)
          continue;
        if (with_matrix)
          finish_displacement_block(scratch, cell_system);
        // (Before the boundary terms: the pressure rows hold B and K_pp
        // alone.)
        if (gamma > 0.0)
          add_augmented_lagrangian(gamma, scratch, cell_system);

        // Boundary terms.
        for (unsigned int i = 0; i < cavities.size(); ++i)
          if (cell_system.on_cavity[i])
            {
              cell_system.volume_derivative[i] = 0;
              cell_system.on_cavity[i]         = false;
            }
        if (cell->at_boundary())
          for (const auto &face : cell->face_iterators())
            {
              if (!face->at_boundary())
                continue;
              const auto id = face->boundary_id();
              // The pressure part of the face (the cavity, when there are
              // cavities), if any.
              const auto part =
                std::find(pressure_ids.begin(), pressure_ids.end(), id) -
                pressure_ids.begin();
              const bool on_part =
                part < static_cast<std::ptrdiff_t>(pressure_ids.size());
              if (on_part && (pressures[part] != 0.0 || with_volume_derivative))
                {
                  fe_face.reinit(cell, face);
                  fe_face[layout.displacement]
                    .get_function_gradients(u, face_grad_u);
                  // B_i = the endocardial flux, the load per unit pressure.
                  // For a rim-fan cavity (CavityVolume::Closure::rim_fan)
                  // whose rim moves, dV_i/du has the lid's flux too; the
                  // bordered Newton then uses this B in its volume row, so
                  // its Jacobian is not exact there (problem.h).
                  if (with_volume_derivative)
                    {
                      add_volume_flux(fe_face,
                                      face_grad_u,
                                      -1.0,
                                      cell_system.volume_derivative[part],
                                      nullptr);
                      cell_system.on_cavity[part] = true;
                    }
                  // R -= p dV/du, K -= p d2V/du2 with the wall normal: the
                  // pressure pushes the wall along -N (into the body).
                  // With the lid loaded too: the fan's dV/du and d2V/du2
                  // (at fixed c; the lid's force on the rim below).
                  if (lid_loaded(part))
                    {
                      fe_face[layout.displacement].get_function_values(u,
                                                                       face_u);
                      for (auto &a : alpha_local)
                        a = 0;
                      CavityVolume::add_fan_face(fe_face,
                                                 face_u,
                                                 face_grad_u,
                                                 lid_apex[part],
                                                 -pressures[part],
                                                 cell_system.residual,
                                                 with_matrix
                                                   ? &cell_system.matrix
                                                   : nullptr,
                                                 lid_area[part],
                                                 &alpha_local);
                      if (with_matrix)
                        {
                          cell->get_dof_indices(dofs);
                          for (unsigned int k = 0; k < 3; ++k)
                            constraints.distribute_local_to_global(
                              alpha_local[k],
                              dofs,
                              lid_alpha[part][k]);
                        }
                    }
                  else if (pressures[part] != 0.0)
                    add_volume_flux(fe_face,
                                    face_grad_u,
                                    pressures[part],
                                    cell_system.residual,
                                    with_matrix ? &cell_system.matrix
                                                : nullptr);
                }
              const auto support = robin_supports.find(id);
              if (support != robin_supports.end())
                {
                  fe_face.reinit(cell, face);
                  fe_face[layout.displacement].get_function_values(u, face_u);
                  if (with_rates && support->second.damping != 0.0)
                    fe_face[layout.displacement]
                      .get_function_values(dynamics.velocity, face_v);
                  add_robin_face(fe_face,
                                 face_u,
                                 face_v,
                                 support->second,
                                 with_rates,
                                 velocity_coefficient,
                                 with_matrix,
                                 scratch,
                                 cell_system);
                }
            }

        if (dynamic)
          {
            // The inertia: int rho phi_i . A dV / (1 - alpha_f) and c int
            // rho phi_i . phi_j dV / (1 - alpha_f) (the same component).
            fe_values[layout.displacement].get_function_values(
              dynamics.effective_acceleration,
              acceleration);
            for (const unsigned int q : fe_values.quadrature_point_indices())
              {
                const double w          = params.density * fe_values.JxW(q);
                const double w_residual = w * inertia_weight;
                for (unsigned int i = 0; i < n; ++i)
                  {
                    const unsigned int ci =
                      fe->system_to_component_index(i).first;
                    const double phi_i = fe_values.shape_value(i, q);
                    cell_system.residual(i) +=
                      w_residual * phi_i * acceleration[q][ci];
                    if (with_matrix)
                      for (unsigned int j = 0; j < n; ++j)
                        if (fe->system_to_component_index(j).first == ci)
                          cell_system.matrix(i, j) +=
                            mass_weight * w * phi_i *
                            fe_values.shape_value(j, q);
                  }
              }
          }

        cell->get_dof_indices(dofs);
        if (with_matrix)
          constraints.distribute_local_to_global(cell_system.matrix,
                                                 cell_system.residual,
                                                 dofs,
                                                 tangent,
                                                 residual);
        else
          constraints.distribute_local_to_global(cell_system.residual,
                                                 dofs,
                                                 residual);
        if (with_volume_derivative)
          for (unsigned int i = 0; i < cavities.size(); ++i)
            if (cell_system.on_cavity[i])
              constraints.distribute_local_to_global(
                cell_system.volume_derivative[i],
                dofs,
                volume_derivatives[i]);
        if (with_pressure_matrix)
          {
            for (unsigned int i = 0; i < scratch.p_dofs.size(); ++i)
              pressure_dofs[i] = dofs[scratch.p_dofs[i]];
            pressure_matrix->add(pressure_dofs, cell_system.pressure_matrix);
          }
        if (gamma > 0.0)
          {
            for (unsigned int i = 0; i < scratch.u_dofs.size(); ++i)
              displacement_dofs[i] = dofs[scratch.u_dofs[i]];
            constraints.distribute_local_to_global(cell_system.coupling,
                                                   displacement_dofs,
                                                   pressure_dofs,
                                                   *augmentation);
          }
      }

    add_lid_rim_terms(pressures, lid_area, lid_alpha, with_matrix);
    if (with_matrix)
      tangent.compress(dealii::VectorOperation::add);
    if (with_pressure_matrix)
      pressure_matrix->compress();
    if (gamma > 0.0)
      augmentation->compress(dealii::VectorOperation::add);
    residual.compress(dealii::VectorOperation::add);
    if (dynamic)
      residual.add(dynamics.alpha_f * inertia_weight, dynamics.residual_n);
    if (with_volume_derivative)
      {
        for (auto &b : volume_derivatives)
          b.compress(dealii::VectorOperation::add);
        update_volume_rows();
      }

    // An inverted element on any rank fails the step on every rank.
    inverted = dealii::Utilities::MPI::max(inverted, comm);
    AssertThrow(inverted == 0, ExcInvertedElement());
    return residual.l2_norm();
  }

  // The lids' force on their rims: -p (1/3) (int cof(F) N dA) / n_rim on
  // every rim vertex (the rest of -p dV/du of the fan); with the matrix
  // the rest of -p d2V/du2, -(p/3) sum_k (C_k A_k^T + A_k C_k^T) with
  // C_k = dc_k/du (1/n_rim on the rim's DoFs of component k) and A_k =
  // alpha_k: low_rank_u = -(p/3) [C, A], low_rank_v = [A, C].
  void
  Problem::Impl::add_lid_rim_terms(
    const dealii::Vector<double>                &pressures,
    const std::vector<Tensor<1, 3>>             &lid_area,
    std::vector<std::array<LA::MPI::Vector, 3>> &lid_alpha,
    const bool                                   with_matrix)
  {
    if (with_matrix)
      {
        low_rank_u.clear();
        low_rank_v.clear();
      }
    for (unsigned int i = 0; i < cavities.size(); ++i)
      if (lid_loaded(i) && with_matrix)
        {
          std::array<LA::MPI::Vector, 3> C;
          dealii::Vector<double>         one(1);
          one[0] = 1.0 / cavities[i].n_rim_vertices();
          std::vector<dealii::types::global_dof_index> dof(1);
          for (unsigned int k = 0; k < 3; ++k)
            {
              C[k].reinit(owned, comm);
              lid_alpha[i][k].compress(dealii::VectorOperation::add);
            }
          cavities[i].for_each_rim_vertex(
            dof_handler,
            [&](const std::array<dealii::types::global_dof_index, 3> &dofs) {
              for (unsigned int k = 0; k < 3; ++k)
                {
                  dof[0] = dofs[k];
                  constraints.distribute_local_to_global(one, dof, C[k]);
                }
            });
          for (unsigned int k = 0; k < 3; ++k)
            {
              C[k].compress(dealii::VectorOperation::add);
              LA::MPI::Vector scaled_C = C[k], scaled_A = lid_alpha[i][k];
              scaled_C *= -pressures[i] / 3.0;
              scaled_A *= -pressures[i] / 3.0;
              low_rank_u.push_back(scaled_C);
              low_rank_v.push_back(lid_alpha[i][k]);
              low_rank_u.push_back(scaled_A);
              low_rank_v.push_back(C[k]);
            }
        }
    for (unsigned int i = 0; i < cavities.size(); ++i)
      if (lid_loaded(i))
        {
          const Tensor<1, 3> area =
            dealii::Utilities::MPI::sum(lid_area[i], comm);
          dealii::Vector<double> share(3);
          for (unsigned int k = 0; k < 3; ++k)
            share[k] =
              -pressures[i] * area[k] / (3.0 * cavities[i].n_rim_vertices());
          std::vector<dealii::types::global_dof_index> rim(3);
          cavities[i].for_each_rim_vertex(
            dof_handler,
            [&](const std::array<dealii::types::global_dof_index, 3> &dofs) {
              rim.assign(dofs.begin(), dofs.end());
              constraints.distribute_local_to_global(share, rim, residual);
            });
        }
  }

  void
  Problem::Impl::update_volume_rows()
  {
    dealii::TimerOutput::Scope scope(timer, "Mechanics / cavity volume");
    volume_rows.resize(cavities.size());
    for (unsigned int i = 0; i < cavities.size(); ++i)
      {
        if (!moving_lid[i])
          {
            volume_rows[i] = volume_derivatives[i];
            continue;
          }
        // dV/du of the fan lid: the endocardial flux plus the lid's, then
        // condensed as the assembly condenses the flux. With the lid loaded
        // it is the load per unit pressure too.
        LA::MPI::Vector exact(owned, comm);
        cavities[i].derivative(mapping, dof_handler, u, n_q_face_1d, exact);
        LA::MPI::Vector ghosted(owned, relevant, comm);
        ghosted = exact;
        volume_rows[i].reinit(owned, comm);
        constraints.condense(ghosted, volume_rows[i]);
        if (lid_loaded(i))
          volume_derivatives[i] = volume_rows[i];
      }
  }
} // namespace systole::Mechanics
