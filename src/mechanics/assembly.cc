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
#include "mechanics/hyperelastic_kernel.h"
#include "mechanics/matrix_free_mixed_solver.h"
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/petsc_tools.h"
#include "mechanics/problem_impl.h"
#include "mechanics/surface_terms.h"

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <memory>

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

      // D = A JxW, A = dP/dF (hyperelastic_kernel.h).
      const Tensor<4, 3> A = first_elasticity_tangent(F, S, dS_dE);
      double             D[3][3][3][3];
      for (unsigned int c = 0; c < 3; ++c)
        for (unsigned int J = 0; J < 3; ++J)
          for (unsigned int d = 0; d < 3; ++d)
            for (unsigned int L = 0; L < 3; ++L)
              D[c][J][d][L] = A[c][J][d][L] * JxW;

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

    /// The switches of one assembly: what it builds and which terms are on.
    struct AssemblyOptions
    {
      bool with_matrix            = false;
      bool with_volume_derivative = false;
      /// The Schur-complement preconditioner of the mixed iterative solver.
      bool with_pressure_matrix = false;
      bool mixed                = false; ///< a pressure field
      /// The volumetric penalty on its own (reduced) quadrature rule.
      bool reduced_volumetric = false;
      bool dynamic            = false; ///< the inertia of a time step
      /// The rate terms (Kelvin-Voigt viscosity, dashpots) and the viscosity.
      bool with_rates = false, viscous = false;
      /// The augmented Lagrangian's gamma (0: none).
      double gamma = 0.0;
      /// 1 / (1 - alpha_f) and c / (1 - alpha_f) of the inertia (0 when
      /// quasi-static), and dv/du of a time step.
      double inertia_weight = 0.0, mass_weight = 0.0;
      double velocity_coefficient = 0.0;
    };

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
                       const AssemblyOptions     &options,
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
      if (!options.with_matrix)
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
      if (options.with_pressure_matrix)
        {
          const double w =
            schur_weight(inverse_kappa, inverse_mu, options.gamma);
          for (unsigned int i = 0; i < s.p_dofs.size(); ++i)
            for (unsigned int j = 0; j < s.p_dofs.size(); ++j)
              {
                const double psi_psi =
                  s.psi[s.p_dofs[i]] * s.psi[s.p_dofs[j]] * JxW;
                cell.pressure_matrix(i, j) -= w * psi_psi;
                if (options.gamma > 0.0)
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
    /// phi_b P_cd; @p face_u is u less the support's reference
    /// (BoundaryConditions::support_stretch());
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

    /// The material of the bulk term: the laws and their coefficients.
    struct BulkMaterial
    {
      const Materials::PassiveLaw    &passive_law;
      const Materials::VolumetricLaw &volumetric_law;
      /// The two-way coupled tension model (none: nullptr) and its step.
      const Materials::TensionModel *tension_model;
      double                         tension_time, tension_time_step;
      double                         active_tension; ///< uniform [kPa]
      Materials::CrossFibreFractions active_cross_fibre;
      double                         viscosity;                 ///< [kPa ms]
      double                         inverse_bulk_modulus;      ///< [1/kPa]
      double                         reference_shear_stiffness; ///< [kPa]
    };

    /// The work space of the cell loop: FEValues, field values at the
    /// points, the cell system and the local DoF indices.
    struct CellScratch
    {
      /// The scratch of the element and quadrature rules of
      /// @p discretization.
      CellScratch(const Discretization &discretization,
                  const unsigned int    n_cavities,
                  const unsigned int    n_tension_states,
                  const double          gamma)
        : CellScratch(
            discretization.mapping,
            *discretization.fe,
            discretization.cell_quadrature(discretization.n_q_1d),
            discretization.cell_quadrature(discretization.reduced_volumetric
                                             ? discretization.n_q_1d - 1
                                             : discretization.n_q_1d),
            discretization.face_quadrature(discretization.n_q_face_1d),
            n_cavities,
            n_tension_states,
            gamma)
      {}

      CellScratch(const dealii::Mapping<3>       &mapping,
                  const dealii::FiniteElement<3> &fe,
                  const dealii::Quadrature<3>    &quadrature,
                  const dealii::Quadrature<3>    &volumetric_quadrature,
                  const dealii::Quadrature<2>    &face_quadrature,
                  const unsigned int              n_cavities,
                  const unsigned int              n_tension_states,
                  const double                    gamma)
        : fe_values(mapping, fe, quadrature, cell_flags())
        , fe_volumetric(mapping, fe, volumetric_quadrature, cell_flags())
        , fe_face(mapping,
                  fe,
                  face_quadrature,
                  dealii::update_values | dealii::update_gradients |
                    dealii::update_quadrature_points |
                    dealii::update_normal_vectors | dealii::update_JxW_values)
        , cell_system(fe.n_dofs_per_cell(), n_cavities)
        , shape(fe)
        , dofs(fe.n_dofs_per_cell())
        , pressure_dofs(shape.p_dofs.size())
        , displacement_dofs(shape.u_dofs.size())
        , grad_u(quadrature.size())
        , volumetric_grad_u(volumetric_quadrature.size())
        , grad_v(quadrature.size())
        , face_grad_u(face_quadrature.size())
        , p_values(quadrature.size())
        , face_u(face_quadrature.size())
        , face_v(face_quadrature.size())
        , acceleration(quadrature.size())
        , tension_trial(n_tension_states)
      {
        const unsigned int n_p = shape.p_dofs.size();
        cell_system.pressure_matrix.reinit(n_p, n_p);
        if (gamma > 0.0)
          {
            cell_system.pressure_weight.reinit(n_p, n_p);
            cell_system.inverse_weight.reinit(n_p, n_p);
            cell_system.coupling.reinit(shape.u_dofs.size(), n_p);
          }
        for (auto &a : alpha_local)
          a.reinit(fe.n_dofs_per_cell());
      }

      static dealii::UpdateFlags
      cell_flags()
      {
        return dealii::update_values | dealii::update_gradients |
               dealii::update_JxW_values;
      }

      /// The passive (and active) stress is integrated with the full Gauss
      /// rule; in the penalty formulation the volumetric penalty may use one
      /// point less per direction (selective reduced integration,
      /// "Volumetric integration = reduced"), which relieves its locking.
      dealii::FEValues<3>                          fe_values, fe_volumetric;
      dealii::FEFaceValues<3>                      fe_face;
      CellSystem                                   cell_system;
      ShapeScratch                                 shape;
      std::vector<dealii::types::global_dof_index> dofs, pressure_dofs,
        displacement_dofs;
      std::vector<Tensor<2, 3>> grad_u, volumetric_grad_u, grad_v, face_grad_u;
      std::vector<double>       p_values;
      std::vector<Tensor<1, 3>> face_u, face_v, acceleration;
      /// int da_k[phi] dA of a loaded lid's wall face.
      std::array<dealii::Vector<double>, 3> alpha_local;
      /// The tension model's trial state at a point (dropped).
      std::vector<double> tension_trial;
    };

    /// The stress and tangent at one point of the bulk term.
    struct PointStress
    {
      Materials::PassiveInput  in;
      Materials::PassiveOutput out;
      /// 1/mu of the Schur preconditioner (0 without it).
      double inverse_mu = 0.0;
      /// dT/dlambda / lambda of a stretch-dependent tension (0: none).
      double cross_fibre_slope = 0.0;
    };

    /// Two-way coupling: the tension model's step at this iterate's stretch,
    /// from the accepted state (the trial state is dropped;
    /// accept_tension_step() recomputes it). Returns the model's tension and
    /// adds dS/dE += f0 x f0 x dT/dE with dT/dE = dT/dlambda f0 x f0 /
    /// lambda (lambda^2 = 1 + 2 f0.E f0); the cross-fibre part (not major
    /// symmetric) goes in after add_stress_point().
    double
    add_tension_model(const BulkMaterial  &material,
                      const bool           with_matrix,
                      PointData           &data,
                      std::vector<double> &trial,
                      PointStress         &point)
    {
      double       dT_dstretch, stretch;
      const double model_tension =
        step_tension_model(*material.tension_model,
                           data,
                           point.in.F,
                           material.tension_time,
                           material.tension_time_step,
                           trial.data(),
                           dT_dstretch,
                           stretch);
      data.model_tension = model_tension;
      if (with_matrix && dT_dstretch != 0.0)
        {
          const dealii::SymmetricTensor<2, 3> ff = dealii::symmetrize(
            dealii::outer_product(point.in.basis.f, point.in.basis.f));
          point.out.dS_dE +=
            (dT_dstretch / stretch) * dealii::outer_product(ff, ff);
          point.cross_fibre_slope = dT_dstretch / stretch;
        }
      return model_tension;
    }

    /// The stress S and tangent dS/dE of everything at point @p q of the
    /// bulk term: passive, volumetric (penalty on the full rule) or
    /// pressure, active, viscous. Returns false where the element is
    /// inverted (J <= 0).
    bool
    evaluate_point(const BulkMaterial    &material,
                   const AssemblyOptions &options,
                   const unsigned int     q,
                   PointData             &data,
                   CellScratch           &w,
                   PointStress           &point)
    {
      Materials::PassiveInput  &in  = point.in;
      Materials::PassiveOutput &out = point.out;
      in.F            = dealii::unit_symmetric_tensor<3>() + w.grad_u[q];
      in.basis        = data.basis;
      in.with_tangent = options.with_matrix;
      if (!(dealii::determinant(in.F) > 0.0))
        return false;
      material.passive_law.evaluate(in, out);
      point.inverse_mu =
        options.with_pressure_matrix
          ? 1.0 / shear_stiffness(in.F,
                                  out.dS_dE,
                                  material.reference_shear_stiffness)
          : 0.0;
      if (options.mixed)
        Materials::add_volumetric_stress(in, -w.p_values[q], 0.0, out);
      else if (!options.reduced_volumetric)
        material.volumetric_law.add_to(in.F, out.S, out.dS_dE);
      // The active stress comes after the volumetric part: it is not
      // projected.
      double tension = material.active_tension + data.tension;
      if (material.tension_model != nullptr)
        tension += add_tension_model(material,
                                     options.with_matrix,
                                     data,
                                     w.tension_trial,
                                     point);
      if (tension != 0.0)
        Materials::add_active_stress(tension,
                                     material.active_cross_fibre,
                                     in.basis,
                                     out.S);
      // Kelvin-Voigt: S += eta dE/dt, dE/dt = sym(F^T grad v); through v
      // (dv/du = gamma / (beta dt)) it stiffens like eta dv/du dE.
      if (options.viscous)
        {
          out.S += material.viscosity *
                   dealii::symmetrize(dealii::transpose(in.F) * w.grad_v[q]);
          if (options.with_matrix)
            out.dS_dE += (material.viscosity * options.velocity_coefficient) *
                         dealii::identity_tensor<3>();
        }
      return true;
    }

    /// The bulk term of one cell on the full Gauss rule (w.fe_values
    /// reinitialized, w.grad_u, w.p_values and w.grad_v filled): stress,
    /// cross-fibre and viscous tangents, pressure rows. Returns false where
    /// the element is inverted.
    bool
    add_bulk_cell(const BulkMaterial                            &material,
                  const AssemblyOptions                         &options,
                  const std::vector<std::shared_ptr<PointData>> &data,
                  CellScratch                                   &w)
    {
      const dealii::FEValues<3> &values = w.fe_values;
      for (const unsigned int q : values.quadrature_point_indices())
        {
          PointStress point;
          if (!evaluate_point(material, options, q, *data[q], w, point))
            return false;
          const Tensor<2, 3> &F = point.in.F;
          add_stress_point(values,
                           q,
                           F,
                           point.out.S,
                           point.out.dS_dE,
                           options.with_matrix,
                           w.shape,
                           w.cell_system);
          if (point.cross_fibre_slope != 0.0 &&
              material.active_cross_fibre.any())
            add_cross_fibre_tangent(values,
                                    q,
                                    F,
                                    point.in.basis,
                                    material.active_cross_fibre,
                                    point.cross_fibre_slope,
                                    w.shape,
                                    w.cell_system);
          if (options.viscous && options.with_matrix)
            add_viscous_point(values.JxW(q),
                              F,
                              w.grad_v[q],
                              material.viscosity,
                              w.shape,
                              w.cell_system);
          if (options.mixed)
            add_pressure_point(values,
                               q,
                               F,
                               w.p_values[q],
                               material.inverse_bulk_modulus,
                               point.inverse_mu,
                               options,
                               w.shape,
                               w.cell_system);
        }
      return true;
    }

    /// The volumetric penalty of one cell on its reduced rule (selective
    /// reduced integration). Returns false where the element is inverted.
    bool
    add_reduced_volumetric_cell(
      const Materials::VolumetricLaw                    &volumetric_law,
      const dealii::FEValuesExtractors::Vector          &displacement,
      const dealii::DoFHandler<3>::active_cell_iterator &cell,
      const LA::MPI::Vector                             &u,
      const bool                                         with_matrix,
      CellScratch                                       &w)
    {
      w.fe_volumetric.reinit(cell);
      w.fe_volumetric[displacement].get_function_gradients(u,
                                                           w.volumetric_grad_u);
      for (const unsigned int q : w.fe_volumetric.quadrature_point_indices())
        {
          const Tensor<2, 3> F =
            dealii::unit_symmetric_tensor<3>() + w.volumetric_grad_u[q];
          if (!(dealii::determinant(F) > 0.0))
            return false;
          SymmetricTensor<2, 3> S;
          SymmetricTensor<4, 3> dS_dE;
          volumetric_law.add_to(F, S, dS_dE);
          add_stress_point(w.fe_volumetric,
                           q,
                           F,
                           S,
                           dS_dE,
                           with_matrix,
                           w.shape,
                           w.cell_system);
        }
      return true;
    }

    /// The cavity pressures of one assembly and the loaded lids' state: per
    /// cavity whose pressure loads its moving lid too, the fan's apex c,
    /// the wall's vector area (summed over the faces) for the lid's force
    /// on the rim and, with the matrix, alpha_k = int da_k[phi] dA of the
    /// wall (its rank-6 rim-wall coupling, low_rank_u/v).
    struct PressureLoads
    {
      const dealii::Vector<double>                  &pressures;
      const std::vector<dealii::types::boundary_id> &pressure_ids;
      std::vector<bool>                              lid_loaded;
      std::vector<dealii::Point<3>>                  lid_apex;
      std::vector<Tensor<1, 3>>                      lid_area;
      std::vector<std::array<LA::MPI::Vector, 3>>    lid_alpha;
    };

    /// The loads of @p pressures and, for every cavity whose lid is loaded
    /// (@p lid_loaded), the fan's apex at the displacement @p u and, @p
    /// with_matrix, the zeroed alpha_k.
    PressureLoads
    pressure_loads(const dealii::Vector<double>                  &pressures,
                   const std::vector<dealii::types::boundary_id> &pressure_ids,
                   const std::vector<CavityVolume>               &cavities,
                   const std::function<bool(unsigned int)>       &lid_loaded,
                   const dealii::DoFHandler<3>                   &dof_handler,
                   const LA::MPI::Vector                         &u,
                   const bool                                     with_matrix,
                   const dealii::IndexSet                        &owned,
                   const MPI_Comm                                 comm)
    {
      PressureLoads loads{pressures, pressure_ids, {}, {}, {}, {}};
      loads.lid_loaded.resize(pressure_ids.size());
      for (unsigned int i = 0; i < pressure_ids.size(); ++i)
        loads.lid_loaded[i] = i < cavities.size() && lid_loaded(i);
      loads.lid_apex.resize(cavities.size());
      loads.lid_area.resize(cavities.size());
      loads.lid_alpha.resize(cavities.size());
      for (unsigned int i = 0; i < cavities.size(); ++i)
        if (lid_loaded(i))
          {
            loads.lid_apex[i] = cavities[i].rim_center(dof_handler, u);
            if (with_matrix)
              for (auto &a : loads.lid_alpha[i])
                a.reinit(owned, comm);
          }
      return loads;
    }

    /// The pressure load of the wall face w.fe_face of part @p part (and its
    /// cavity's flux B_i = dV_i/du, the load per unit pressure, @p
    /// with_volume_derivative). For a rim-fan cavity
    /// (CavityVolume::Closure::rim_fan) whose rim moves, dV_i/du has the
    /// lid's flux too; the bordered Newton then uses this B in its volume
    /// row, so its Jacobian is not exact there (problem.h).
    void
    add_pressure_face(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                      const unsigned int                                 part,
                      const AssemblyOptions                    &options,
                      const dealii::FEValuesExtractors::Vector &displacement,
                      const LA::MPI::Vector                    &u,
                      const dealii::AffineConstraints<double>  &constraints,
                      PressureLoads                            &loads,
                      CellScratch                              &w)
    {
      CellSystem  &cell_system = w.cell_system;
      const double pressure    = loads.pressures[part];
      w.fe_face[displacement].get_function_gradients(u, w.face_grad_u);
      if (options.with_volume_derivative)
        {
          add_volume_flux(w.fe_face,
                          w.face_grad_u,
                          -1.0,
                          cell_system.volume_derivative[part],
                          nullptr);
          cell_system.on_cavity[part] = true;
        }
      dealii::FullMatrix<double> *matrix =
        options.with_matrix ? &cell_system.matrix : nullptr;
      // R -= p dV/du, K -= p d2V/du2 with the wall normal: the pressure
      // pushes the wall along -N (into the body). With the lid loaded too:
      // the fan's dV/du and d2V/du2 (at fixed c; the lid's force on the rim
      // in add_lid_rim_terms()).
      if (!loads.lid_loaded[part])
        {
          if (pressure != 0.0)
            add_volume_flux(w.fe_face,
                            w.face_grad_u,
                            pressure,
                            cell_system.residual,
                            matrix);
          return;
        }
      w.fe_face[displacement].get_function_values(u, w.face_u);
      for (auto &a : w.alpha_local)
        a = 0;
      CavityVolume::add_fan_face(w.fe_face,
                                 w.face_u,
                                 w.face_grad_u,
                                 loads.lid_apex[part],
                                 -pressure,
                                 cell_system.residual,
                                 matrix,
                                 loads.lid_area[part],
                                 &w.alpha_local);
      if (options.with_matrix)
        {
          cell->get_dof_indices(w.dofs);
          for (unsigned int k = 0; k < 3; ++k)
            constraints.distribute_local_to_global(w.alpha_local[k],
                                                   w.dofs,
                                                   loads.lid_alpha[part][k]);
        }
    }

    /// The boundary terms of one cell: pressure loads (and cavity fluxes)
    /// and the spring-dashpot supports.
    void
    add_boundary_cell(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                      const AssemblyOptions                    &options,
                      const dealii::FEValuesExtractors::Vector &displacement,
                      const LA::MPI::Vector                    &u,
                      const LA::MPI::Vector                    &velocity,
                      const dealii::AffineConstraints<double>  &constraints,
                      const BoundaryConditions                 &boundaries,
                      PressureLoads                            &loads,
                      CellScratch                              &w)
    {
      CellSystem &cell_system = w.cell_system;
      for (unsigned int i = 0; i < cell_system.on_cavity.size(); ++i)
        if (cell_system.on_cavity[i])
          {
            cell_system.volume_derivative[i] = 0;
            cell_system.on_cavity[i]         = false;
          }
      if (!cell->at_boundary())
        return;
      for (const auto &face : cell->face_iterators())
        {
          if (!face->at_boundary())
            continue;
          const auto id = face->boundary_id();
          // The pressure part of the face (the cavity, when there are
          // cavities), if any.
          const auto part = std::find(loads.pressure_ids.begin(),
                                      loads.pressure_ids.end(),
                                      id) -
                            loads.pressure_ids.begin();
          if (part < static_cast<std::ptrdiff_t>(loads.pressure_ids.size()) &&
              (loads.pressures[part] != 0.0 || options.with_volume_derivative))
            {
              w.fe_face.reinit(cell, face);
              add_pressure_face(cell,
                                part,
                                options,
                                displacement,
                                u,
                                constraints,
                                loads,
                                w);
            }
          const auto support = boundaries.robin_supports.find(id);
          if (support == boundaries.robin_supports.end())
            continue;
          w.fe_face.reinit(cell, face);
          boundaries.support_stretch(w.fe_face,
                                     displacement,
                                     u,
                                     support->second,
                                     w.face_u,
                                     w.face_v);
          if (options.with_rates && support->second.damping != 0.0)
            w.fe_face[displacement].get_function_values(velocity, w.face_v);
          add_robin_face(w.fe_face,
                         w.face_u,
                         w.face_v,
                         support->second,
                         options.with_rates,
                         options.velocity_coefficient,
                         options.with_matrix,
                         w.shape,
                         cell_system);
        }
    }

    /// The inertia of one cell (w.fe_values reinitialized): int rho phi_i .
    /// A dV / (1 - alpha_f) and c int rho phi_i . phi_j dV / (1 - alpha_f)
    /// (the same displacement component; nothing in a pressure row), A the
    /// effective acceleration.
    void
    add_inertia_cell(const dealii::FiniteElement<3>           &fe,
                     const double                              density,
                     const AssemblyOptions                    &options,
                     const dealii::FEValuesExtractors::Vector &displacement,
                     const LA::MPI::Vector &effective_acceleration,
                     CellScratch           &w)
    {
      const dealii::FEValues<3> &values = w.fe_values;
      const unsigned int         n      = fe.n_dofs_per_cell();
      values[displacement].get_function_values(effective_acceleration,
                                               w.acceleration);
      for (const unsigned int q : values.quadrature_point_indices())
        {
          const double w_q        = density * values.JxW(q);
          const double w_residual = w_q * options.inertia_weight;
          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int ci = fe.system_to_component_index(i).first;
              if (ci == 3) // the pressure of a mixed formulation
                continue;
              const double phi_i = values.shape_value(i, q);
              w.cell_system.residual(i) +=
                w_residual * phi_i * w.acceleration[q][ci];
              if (options.with_matrix)
                for (unsigned int j = 0; j < n; ++j)
                  if (fe.system_to_component_index(j).first == ci)
                    w.cell_system.matrix(i, j) += options.mass_weight * w_q *
                                                  phi_i *
                                                  values.shape_value(j, q);
            }
        }
    }

    /// The global objects one assembly adds to.
    struct GlobalSystem
    {
      const dealii::AffineConstraints<double> &constraints;
      LA::MPI::SparseMatrix                   &tangent;
      LA::MPI::Vector                         &residual;
      std::vector<LA::MPI::Vector>            &volume_derivatives;
      PressureMatrix                          *pressure_matrix;
      LA::MPI::SparseMatrix                   *augmentation;
    };

    /// Add the cell system of @p cell to the global objects (condensed by
    /// the constraints).
    void
    distribute_cell(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                    const AssemblyOptions                             &options,
                    GlobalSystem                                      &global,
                    CellScratch                                       &w)
    {
      const CellSystem   &cell_system = w.cell_system;
      const ShapeScratch &s           = w.shape;
      cell->get_dof_indices(w.dofs);
      if (options.with_matrix)
        global.constraints.distribute_local_to_global(cell_system.matrix,
                                                      cell_system.residual,
                                                      w.dofs,
                                                      global.tangent,
                                                      global.residual);
      else
        global.constraints.distribute_local_to_global(cell_system.residual,
                                                      w.dofs,
                                                      global.residual);
      if (options.with_volume_derivative)
        for (unsigned int i = 0; i < cell_system.on_cavity.size(); ++i)
          if (cell_system.on_cavity[i])
            global.constraints.distribute_local_to_global(
              cell_system.volume_derivative[i],
              w.dofs,
              global.volume_derivatives[i]);
      if (options.with_pressure_matrix)
        {
          for (unsigned int i = 0; i < s.p_dofs.size(); ++i)
            w.pressure_dofs[i] = w.dofs[s.p_dofs[i]];
          global.pressure_matrix->add(w.pressure_dofs,
                                      cell_system.pressure_matrix);
        }
      if (options.gamma > 0.0)
        {
          for (unsigned int i = 0; i < s.u_dofs.size(); ++i)
            w.displacement_dofs[i] = w.dofs[s.u_dofs[i]];
          global.constraints.distribute_local_to_global(cell_system.coupling,
                                                        w.displacement_dofs,
                                                        w.pressure_dofs,
                                                        *global.augmentation);
        }
    }

    /// Elastodynamics: the effective acceleration (1 - alpha_m) a_{n+1} +
    /// alpha_m a_n + c_M ((1 - alpha_f) v_{n+1} + alpha_f v_n) of the
    /// current displacement @p u_owned, and, @p with_velocity, v_{n+1} for
    /// the rate terms.
    void
    update_dynamic_rates(const LA::MPI::Vector  &u_owned,
                         const dealii::IndexSet &owned,
                         const MPI_Comm          comm,
                         const bool              with_velocity,
                         Dynamics               &dynamics)
    {
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
      if (with_velocity)
        dynamics.velocity = v;
    }

    /// The switches of an assembly from its arguments and the problem's
    /// state (the dynamic coefficients stay 0 when quasi-static).
    AssemblyOptions
    assembly_options(const bool      with_matrix,
                     const bool      with_volume_derivative,
                     const bool      mixed,
                     const bool      has_pressure_matrix,
                     const double    augmented_lagrangian,
                     const bool      reduced_volumetric,
                     const double    viscosity,
                     const Dynamics &dynamics)
    {
      AssemblyOptions options;
      options.with_matrix            = with_matrix;
      options.with_volume_derivative = with_volume_derivative;
      options.mixed                  = mixed;
      options.with_pressure_matrix =
        with_matrix && mixed && has_pressure_matrix;
      options.reduced_volumetric = reduced_volumetric;
      // The augmented Lagrangian of the iterative solver (augmentation: G;
      // augmented_lagrangian is 0 without it).
      options.gamma = options.with_pressure_matrix ? augmented_lagrangian : 0.0;
      // Elastodynamics: the residual becomes R(u) + (alpha_f R(u_n) + M
      // A(u)) / (1 - alpha_f), A the effective acceleration (problem_impl.h,
      // Dynamics), and the tangent K + c / (1 - alpha_f) M: the generalized-
      // alpha balance divided by 1 - alpha_f, so that the cavity pressures
      // enter as in the quasi-static residual (dR/dp_i = -dV_i/du, the
      // border of the volume-constrained solves) and the tolerances keep
      // their scale.
      options.dynamic = dynamics.started && dynamics.time_step > 0.0;
      if (options.dynamic)
        {
          options.inertia_weight = 1.0 / (1.0 - dynamics.alpha_f);
          options.mass_weight =
            dynamics.effective_mass_coefficient() * options.inertia_weight;
          options.velocity_coefficient = dynamics.velocity_coefficient();
        }
      // The rate terms (Kelvin-Voigt viscosity, dashpots) in a time step and
      // in the accepted state's residual R(u_n, v_n).
      options.with_rates =
        dynamics.started && (options.dynamic || dynamics.accepting);
      options.viscous = options.with_rates && viscosity != 0.0;
      return options;
    }

    /// Zero what this assembly adds to.
    void
    clear_global_system(const AssemblyOptions &options, GlobalSystem &global)
    {
      if (options.with_matrix)
        global.tangent = 0;
      if (options.with_pressure_matrix)
        global.pressure_matrix->zero();
      if (options.gamma > 0.0)
        *global.augmentation = 0;
      global.residual = 0;
      if (options.with_volume_derivative)
        for (auto &b : global.volume_derivatives)
          b = 0;
    }

    /// Exchange the off-rank contributions (volume_derivatives: the caller
    /// compresses them).
    void
    compress_global_system(const AssemblyOptions &options, GlobalSystem &global)
    {
      if (options.with_matrix)
        global.tangent.compress(dealii::VectorOperation::add);
      if (options.with_pressure_matrix)
        global.pressure_matrix->compress();
      if (options.gamma > 0.0)
        global.augmentation->compress(dealii::VectorOperation::add);
      global.residual.compress(dealii::VectorOperation::add);
    }

    /// Start @p cell: the field values on the full rule (u, p, v as needed)
    /// and the cell system zeroed.
    void
    begin_cell(const dealii::DoFHandler<3>::active_cell_iterator &cell,
               const AssemblyOptions                             &options,
               const FieldLayout                                 &layout,
               const LA::MPI::Vector                             &u,
               const LA::MPI::Vector                             &velocity,
               CellScratch                                       &w)
    {
      w.fe_values.reinit(cell);
      w.fe_values[layout.displacement].get_function_gradients(u, w.grad_u);
      if (options.mixed)
        w.fe_values[layout.pressure].get_function_values(u, w.p_values);
      if (options.viscous)
        w.fe_values[layout.displacement].get_function_gradients(velocity,
                                                                w.grad_v);
      w.cell_system.matrix          = 0;
      w.cell_system.residual        = 0;
      w.cell_system.pressure_matrix = 0;
      if (options.gamma > 0.0)
        w.cell_system.pressure_weight = 0;
    }

    /// What the terms of a cell read besides the cell: the switches, the
    /// material, the fields and the boundary conditions.
    struct CellTerms
    {
      const AssemblyOptions                   &options;
      const BulkMaterial                       material;
      const FieldLayout                       &layout;
      const dealii::FiniteElement<3>          &fe;
      const LA::MPI::Vector                   &u;
      const Dynamics                          &dynamics;
      const dealii::AffineConstraints<double> &constraints;
      const BoundaryConditions                &boundaries;
      const double                             density;
    };

    /// Every term of the locally owned @p cell (point data @p data) into
    /// @p global (the lids' alpha into @p loads). Returns false, adding
    /// nothing, where the element is inverted.
    bool
    assemble_cell(const CellTerms                                   &terms,
                  const dealii::DoFHandler<3>::active_cell_iterator &cell,
                  const std::vector<std::shared_ptr<PointData>>     &data,
                  PressureLoads                                     &loads,
                  GlobalSystem                                      &global,
                  CellScratch                                       &w)
    {
      const AssemblyOptions                    &options = terms.options;
      const dealii::FEValuesExtractors::Vector &displacement =
        terms.layout.displacement;
      begin_cell(cell,
                 options,
                 terms.layout,
                 terms.u,
                 terms.dynamics.velocity,
                 w);
      if (!add_bulk_cell(terms.material, options, data, w))
        return false;
      if (options.reduced_volumetric &&
          !add_reduced_volumetric_cell(terms.material.volumetric_law,
                                       displacement,
                                       cell,
                                       terms.u,
                                       options.with_matrix,
                                       w))
        return false;
      if (options.with_matrix)
        finish_displacement_block(w.shape, w.cell_system);
      // (Before the boundary terms: the pressure rows hold B and K_pp
      // alone.)
      if (options.gamma > 0.0)
        add_augmented_lagrangian(options.gamma, w.shape, w.cell_system);
      add_boundary_cell(cell,
                        options,
                        displacement,
                        terms.u,
                        terms.dynamics.velocity,
                        terms.constraints,
                        terms.boundaries,
                        loads,
                        w);
      if (options.dynamic)
        add_inertia_cell(terms.fe,
                         terms.density,
                         options,
                         displacement,
                         terms.dynamics.effective_acceleration,
                         w);
      distribute_cell(cell, options, global, w);
      return true;
    }

    /// The material of the bulk term of the laws @p material, the tension
    /// model of @p points and @p params under the uniform @p active_tension
    /// [kPa].
    BulkMaterial
    bulk_material(const MaterialLaws     &material,
                  const QuadraturePoints &points,
                  const Parameters       &params,
                  const double            active_tension)
    {
      return {material.passive_law,
              material.volumetric_law,
              points.tension_model,
              points.tension_time,
              points.tension_time_step,
              active_tension,
              params.active_cross_fibre,
              params.viscosity,
              material.inverse_bulk_modulus,
              material.reference_shear_stiffness};
    }

    /// The assembly's switches with the matrix (no pressure matrix): those
    /// of the matrix-free tangent's point kernel.
    AssemblyOptions
    point_kernel_options(const Discretization &discretization,
                         const Parameters     &params,
                         const Dynamics       &dynamics)
    {
      return assembly_options(true,
                              false,
                              discretization.layout.mixed(),
                              false,
                              0.0,
                              discretization.reduced_volumetric,
                              params.viscosity,
                              dynamics);
    }

    /// Why the matrix-free tangent's point kernel cannot hold the terms of
    /// the formulation (the stored 9 x 9 of a point is a major-symmetric
    /// dP/dF of the full rule, without the rate terms or the inertia);
    /// empty if it can. @p allow_mixed: a pressure field is allowed
    /// (MatrixFreeMixedSolver).
    std::string
    matrix_free_obstacle(const Discretization   &discretization,
                         const Parameters       &params,
                         const QuadraturePoints &points,
                         const Dynamics         &dynamics,
                         const bool              allow_mixed)
    {
      const AssemblyOptions options =
        point_kernel_options(discretization, params, dynamics);
      if ((allow_mixed || !options.mixed) && !options.reduced_volumetric &&
          !options.dynamic && !options.with_rates &&
          discretization.n_q_1d == 3 &&
          !(points.tension_model != nullptr && params.active_cross_fibre.any()))
        return "";
      return std::string("Mechanics: the matrix-free tangent needs ") +
             (allow_mixed ? "Q2 with "
                          : "the penalty formulation on Q2 with ") +
             "the full volumetric rule, quasi-static, and no cross-fibre "
             "tension model (otherwise use Linear solver = iterative or "
             "direct).";
    }

    /// The switches of the matrix-free tangent's point kernel (the
    /// assembly's with the matrix, no pressure matrix). Throws where the
    /// formulation has terms the stored 9 x 9 of a point cannot hold.
    AssemblyOptions
    matrix_free_options(const Discretization   &discretization,
                        const Parameters       &params,
                        const QuadraturePoints &points,
                        const Dynamics         &dynamics,
                        const bool              allow_mixed = false)
    {
      const std::string obstacle = matrix_free_obstacle(discretization,
                                                        params,
                                                        points,
                                                        dynamics,
                                                        allow_mixed);
      AssertThrow(obstacle.empty(), dealii::ExcMessage(obstacle));
      return point_kernel_options(discretization, params, dynamics);
    }

    /// Throws unless there is one pressure per pressure part of @p loads,
    /// and a cavity if @p with_volume_derivative.
    void
    check_loads(const dealii::Vector<double> &pressures,
                const CavityLoads            &loads,
                const bool                    with_volume_derivative)
    {
      AssertThrow(!with_volume_derivative || !loads.cavities.empty(),
                  dealii::ExcMessage("This problem has no cavity."));
      AssertThrow(pressures.size() == loads.pressure_ids.size(),
                  dealii::ExcMessage(
                    "Mechanics: " + std::to_string(pressures.size()) +
                    " pressures given for " +
                    std::to_string(loads.pressure_ids.size()) +
                    " pressure parts."));
    }
  } // namespace

  double
  Problem::Impl::assemble(const dealii::Vector<double> &pressures,
                          const double                  active_tension,
                          const bool                    with_matrix,
                          const bool                    with_volume_derivative)
  {
    if (with_matrix && system.linear_solver != nullptr)
      if (MatrixFreeTangent *tangent =
            system.linear_solver->matrix_free_tangent())
        return assemble_matrix_free(*tangent,
                                    pressures,
                                    active_tension,
                                    with_volume_derivative);
    dealii::TimerOutput::Scope scope(timer, "Mechanics / assembly");
    points.last_active_tension = active_tension;
    check_loads(pressures, loads, with_volume_derivative);
    const AssemblyOptions options =
      assembly_options(with_matrix,
                       with_volume_derivative,
                       discretization.layout.mixed(),
                       system.pressure_matrix != nullptr,
                       system.augmentation != nullptr
                         ? system.augmented_lagrangian
                         : 0.0,
                       discretization.reduced_volumetric,
                       params.viscosity,
                       dynamics);

    PressureLoads pressure_load = pressure_loads(
      pressures,
      loads.pressure_ids,
      loads.cavities,
      [this](const unsigned int i) { return lid_loaded(i); },
      discretization.dof_handler,
      u,
      with_matrix,
      discretization.owned,
      comm);
    if (options.dynamic)
      {
        update_dynamic_rates(u_owned,
                             discretization.owned,
                             comm,
                             params.viscosity != 0.0 ||
                               !boundaries.robin_supports.empty(),
                             dynamics);
      }

    GlobalSystem global{discretization.constraints,
                        system.tangent,
                        system.residual,
                        loads.volume_derivatives,
                        system.pressure_matrix.get(),
                        system.augmentation.get()};
    if (with_matrix)
      factorized.held = false; // PETSc would refactorize on next solve
    clear_global_system(options, global);

    CellScratch     w(discretization,
                  loads.cavities.size(),
                  points.tension_model != nullptr
                        ? points.tension_model->n_states()
                        : 0,
                  options.gamma);
    const CellTerms terms{
      options,
      bulk_material(material, points, params, active_tension),
      discretization.layout,
      *discretization.fe,
      u,
      dynamics,
      discretization.constraints,
      boundaries,
      params.density};
    unsigned int inverted = 0;
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() &&
          !assemble_cell(terms,
                         cell,
                         points.point_data.get_data(cell),
                         pressure_load,
                         global,
                         w))
        {
          inverted = 1; // the assembly is void: skip the other cells
          break;
        }

    add_lid_rim_terms(pressures,
                      pressure_load.lid_area,
                      pressure_load.lid_alpha,
                      with_matrix);
    compress_global_system(options, global);
    if (options.dynamic)
      system.residual.add(dynamics.alpha_f * options.inertia_weight,
                          dynamics.residual_n);
    if (with_volume_derivative)
      {
        for (auto &b : loads.volume_derivatives)
          b.compress(dealii::VectorOperation::add);
        update_volume_rows();
      }

    // An inverted element on any rank fails the step on every rank.
    AssertThrow(dealii::Utilities::MPI::max(inverted, comm) == 0,
                ExcInvertedElement());
    return system.residual.l2_norm();
  }

  double
  Problem::Impl::assemble_matrix_free(MatrixFreeTangent            &tangent,
                                      const dealii::Vector<double> &pressures,
                                      const double active_tension,
                                      const bool   with_volume_derivative)
  {
    AssertThrow(!with_volume_derivative,
                dealii::ExcMessage(
                  "The matrix-free linear solver does not solve "
                  "cavity-volume constraints; use Mechanics / Linear "
                  "solver = iterative or direct."));
    const double norm = assemble(pressures, active_tension, false);
    dealii::TimerOutput::Scope scope(timer, "Mechanics / assembly");
    dealii::TimerOutput::Scope point_tangents(
      timer,
      "Mechanics / matrix-free tangent update");
    factorized.held = false;
    update_matrix_free_tangent(tangent, pressures, active_tension);
    return norm;
  }

  void
  Problem::Impl::check_matrix_free_tangent(const bool allow_mixed) const
  {
    matrix_free_options(discretization, params, points, dynamics, allow_mixed);
  }

  bool
  Problem::Impl::matrix_free_applies() const
  {
    const bool mixed = discretization.layout.mixed();
    bool       lids  = false;
    for (const bool moving : loads.moving_lid)
      lids = lids || (moving && params.lid_pressure);
    return discretization.fe->degree == 2 &&
           !discretization.layout.cell_kind().simplex() &&
           (!mixed ||
            params.pressure_element == PressureElement::discontinuous) &&
           boundaries.robin_supports.empty() && !lids &&
           matrix_free_obstacle(discretization, params, points, dynamics, true)
             .empty();
  }

  namespace
  {
    /// What the point kernel of the matrix-free tangents reads.
    struct PointKernel
    {
      const Discretization  &discretization;
      QuadraturePoints      &points;
      const LA::MPI::Vector &u; ///< ghosted
      const unsigned int     n_cavities;
      const MPI_Comm         comm;

      /// The work space of the kernel.
      CellScratch
      scratch(const double gamma) const
      {
        return CellScratch(discretization,
                           n_cavities,
                           points.tension_model != nullptr
                             ? points.tension_model->n_states()
                             : 0,
                           gamma);
      }
    };

    /// MatrixFreeTangent::update(const CellTangents &) from the point
    /// kernel of @p m (the penalty formulation).
    void
    update_point_tangents(const PointKernel     &m,
                          MatrixFreeTangent     &tangent,
                          const BulkMaterial    &bulk,
                          const AssemblyOptions &options)
    {
      CellScratch  w        = m.scratch(0.0);
      unsigned int inverted = 0;
      tangent.update([&](const dealii::DoFHandler<3>::cell_iterator &cell,
                         std::vector<Tensor<4, 3>>                  &A) {
        AssertThrow(A.size() == w.fe_values.n_quadrature_points,
                    dealii::ExcInternalError());
        w.fe_values.reinit(cell);
        w.fe_values[m.discretization.layout.displacement]
          .get_function_gradients(m.u, w.grad_u);
        const auto data = m.points.point_data.get_data(cell);
        for (const unsigned int q : w.fe_values.quadrature_point_indices())
          {
            PointStress point;
            if (evaluate_point(bulk, options, q, *data[q], w, point))
              A[q] = first_elasticity_tangent(point.in.F,
                                              point.out.S,
                                              point.out.dS_dE);
            else
              {
                inverted = 1;
                A[q]     = 0;
              }
          }
      });
      AssertThrow(dealii::Utilities::MPI::max(inverted, m.comm) == 0,
                  ExcInvertedElement());
    }

    /// MatrixFreeTangent::update(const MixedCellTangents &, ...) from the
    /// point kernel of @p m (the mixed formulations): dP/dF of the
    /// displacement block (the pressure's -p J F^-T included), J F^-T and
    /// the weights of the augmented Lagrangian and of the Schur
    /// preconditioner, as add_pressure_point() has them.
    void
    update_mixed_tangent(const PointKernel     &m,
                         MatrixFreeTangent     &tangent,
                         const BulkMaterial    &bulk,
                         const AssemblyOptions &options,
                         const double           inverse_kappa)
    {
      CellScratch  w        = m.scratch(options.gamma);
      unsigned int inverted = 0;
      const auto  &dofs     = m.discretization.dof_handler;
      const auto  &layout   = m.discretization.layout;
      tangent.update(
        [&](const dealii::DoFHandler<3>::cell_iterator    &d_cell,
            std::vector<Tensor<4, 3>>                     &A,
            std::vector<MatrixFreeTangent::PointPressure> &P) {
          // The cell of the mixed DoFs (the tangent's are displacement-only).
          const dealii::DoFHandler<3>::active_cell_iterator cell(
            &dofs.get_triangulation(),
            d_cell->level(),
            d_cell->index(),
            &dofs);
          w.fe_values.reinit(cell);
          w.fe_values[layout.displacement].get_function_gradients(m.u,
                                                                  w.grad_u);
          w.fe_values[layout.pressure].get_function_values(m.u, w.p_values);
          const auto data = m.points.point_data.get_data(cell);
          for (const unsigned int q : w.fe_values.quadrature_point_indices())
            {
              PointStress point;
              if (!evaluate_point(bulk, options, q, *data[q], w, point))
                {
                  inverted = 1;
                  A[q]     = 0;
                  P[q]     = {dealii::unit_symmetric_tensor<3>(), 1.0, 1.0};
                  continue;
                }
              const Tensor<2, 3> &F = point.in.F;
              A[q] = first_elasticity_tangent(F, point.out.S, point.out.dS_dE);
              P[q].cofactor =
                dealii::determinant(F) * dealii::transpose(dealii::invert(F));
              P[q].augmentation_weight = inverse_kappa + point.inverse_mu;
              P[q].schur_weight =
                schur_weight(inverse_kappa, point.inverse_mu, options.gamma);
            }
        },
        {&m.discretization.fe->base_element(1), inverse_kappa, options.gamma});
      AssertThrow(dealii::Utilities::MPI::max(inverted, m.comm) == 0,
                  ExcInvertedElement());
    }
  } // namespace

  void
  Problem::Impl::update_matrix_free_tangent(
    MatrixFreeTangent            &tangent,
    const dealii::Vector<double> &pressures,
    const double                  active_tension)
  {
    MatrixFreeMixedSolver *mixed   = system.linear_solver != nullptr
                                       ? system.linear_solver->matrix_free_mixed()
                                       : nullptr;
    const AssemblyOptions  options = matrix_free_options(discretization,
                                                        params,
                                                        points,
                                                        dynamics,
                                                        mixed != nullptr);
    check_loads(pressures, loads, false);
    AssertThrow(boundaries.robin_supports.empty(),
                dealii::ExcMessage(
                  "Mechanics: the matrix-free tangent has no spring-dashpot "
                  "(Robin) supports; use Linear solver = direct or "
                  "iterative."));
    std::map<dealii::types::boundary_id, double> face_pressures;
    for (unsigned int i = 0; i < pressures.size(); ++i)
      if (pressures[i] != 0.0)
        {
          AssertThrow(i >= loads.cavities.size() || !lid_loaded(i),
                      dealii::ExcMessage(
                        "Mechanics: the matrix-free tangent has no loaded "
                        "lid (Lid pressure with a moving rim); use Linear "
                        "solver = direct or iterative."));
          face_pressures[loads.pressure_ids[i]] = pressures[i];
        }
    {
      // The displacement in the operator's layout.
      MatrixFreeTangent::Vector u_mf;
      tangent.initialize_dof_vector(u_mf);
      if (mixed != nullptr)
        mixed->displacement_of(u_owned, u_mf);
      else
        copy_owned(u_owned, u_mf);
      tangent.set_follower_pressure(u_mf, face_pressures);
    }
    const BulkMaterial bulk =
      bulk_material(material, points, params, active_tension);
    const PointKernel kernel{discretization,
                             points,
                             u,
                             static_cast<unsigned int>(loads.cavities.size()),
                             comm};
    if (mixed == nullptr)
      update_point_tangents(kernel, tangent, bulk, options);
    else
      // The assembly's switches with the Schur preconditioner and the
      // augmented Lagrangian (evaluate_point() then gives 1/mu).
      update_mixed_tangent(kernel,
                           tangent,
                           bulk,
                           assembly_options(true,
                                            false,
                                            true,
                                            true,
                                            system.augmented_lagrangian,
                                            false,
                                            params.viscosity,
                                            dynamics),
                           material.inverse_bulk_modulus);
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
        loads.low_rank_u.clear();
        loads.low_rank_v.clear();
      }
    for (unsigned int i = 0; i < loads.cavities.size(); ++i)
      if (lid_loaded(i) && with_matrix)
        {
          std::array<LA::MPI::Vector, 3> C;
          dealii::Vector<double>         one(1);
          one[0] = 1.0 / loads.cavities[i].n_rim_vertices();
          std::vector<dealii::types::global_dof_index> dof(1);
          for (unsigned int k = 0; k < 3; ++k)
            {
              C[k].reinit(discretization.owned, comm);
              lid_alpha[i][k].compress(dealii::VectorOperation::add);
            }
          loads.cavities[i].for_each_rim_vertex(
            discretization.dof_handler,
            [&](const std::array<dealii::types::global_dof_index, 3> &dofs) {
              for (unsigned int k = 0; k < 3; ++k)
                {
                  dof[0] = dofs[k];
                  discretization.constraints.distribute_local_to_global(one,
                                                                        dof,
                                                                        C[k]);
                }
            });
          for (unsigned int k = 0; k < 3; ++k)
            {
              C[k].compress(dealii::VectorOperation::add);
              LA::MPI::Vector scaled_C = C[k], scaled_A = lid_alpha[i][k];
              scaled_C *= -pressures[i] / 3.0;
              scaled_A *= -pressures[i] / 3.0;
              loads.low_rank_u.push_back(scaled_C);
              loads.low_rank_v.push_back(lid_alpha[i][k]);
              loads.low_rank_u.push_back(scaled_A);
              loads.low_rank_v.push_back(C[k]);
            }
        }
    for (unsigned int i = 0; i < loads.cavities.size(); ++i)
      if (lid_loaded(i))
        {
          const Tensor<1, 3> area =
            dealii::Utilities::MPI::sum(lid_area[i], comm);
          dealii::Vector<double> share(3);
          for (unsigned int k = 0; k < 3; ++k)
            share[k] = -pressures[i] * area[k] /
                       (3.0 * loads.cavities[i].n_rim_vertices());
          std::vector<dealii::types::global_dof_index> rim(3);
          loads.cavities[i].for_each_rim_vertex(
            discretization.dof_handler,
            [&](const std::array<dealii::types::global_dof_index, 3> &dofs) {
              rim.assign(dofs.begin(), dofs.end());
              discretization.constraints
                .distribute_local_to_global(share, rim, system.residual);
            });
        }
  }

  void
  Problem::Impl::update_volume_rows()
  {
    dealii::TimerOutput::Scope scope(timer, "Mechanics / cavity volume");
    loads.volume_rows.resize(loads.cavities.size());
    for (unsigned int i = 0; i < loads.cavities.size(); ++i)
      {
        if (!loads.moving_lid[i])
          {
            loads.volume_rows[i] = loads.volume_derivatives[i];
            continue;
          }
        // dV/du of the fan lid: the endocardial flux plus the lid's, then
        // condensed as the assembly condenses the flux. With the lid loaded
        // it is the load per unit pressure too.
        LA::MPI::Vector exact(discretization.owned, comm);
        loads.cavities[i].derivative(discretization.mapping,
                                     discretization.dof_handler,
                                     u,
                                     discretization.n_q_face_1d,
                                     exact);
        LA::MPI::Vector ghosted(discretization.owned,
                                discretization.relevant,
                                comm);
        ghosted = exact;
        loads.volume_rows[i].reinit(discretization.owned, comm);
        discretization.constraints.condense(ghosted, loads.volume_rows[i]);
        if (lid_loaded(i))
          loads.volume_derivatives[i] = loads.volume_rows[i];
      }
  }
} // namespace systole::Mechanics
