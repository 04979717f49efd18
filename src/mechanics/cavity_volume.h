#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "base/linear_algebra.h"
#include "geometry/mesh.h"

#include <array>
#include <functional>
#include <vector>

namespace systole::Mechanics
{
  /// Volume of the cavity bounded by the endocardium and closed over its rim,
  /// in the configuration deformed by a displacement field u. Two closures:
  ///
  /// **Plane lid** (Closure::plane; the base plane, or the plane of a planar
  /// basal ring). With a field h(x) = ((x - x_0) . e) e (div h = 1, h . n = 0
  /// on the lid plane through x_0 with unit normal e), the divergence theorem
  /// gives
  /// @f[ V = \int_{\Gamma_{endo}} ((x - x_0)\cdot e)\,(e \cdot n_{cav})\,da
  ///       = -\int_{\Gamma_{endo,0}} ((X + u - x_0)\cdot e)\,(e \cdot J F^{-T}
  ///       N)\,dA, @f]
  /// with N the outward normal of the wall (into the cavity) and Nanson's
  /// formula. This is exact while the basal ring stays in the lid plane (a base
  /// held in its plane); otherwise it is the volume closed by the reference lid
  /// plane.
  ///
  /// **Rim fan** (Closure::rim_fan; for rims that are not one plane). The lid
  /// is the cone of segments from a point c to the (current, discrete) rim
  /// curve. On that cone (x - c) . n = 0, so it adds nothing to the field
  /// (x - c)/3 (div = 1), and
  /// @f[ V = \frac13\int_{\Gamma_{endo}} (x - c)\cdot n_{cav}\,da
  ///       = -\frac13\int_{\Gamma_{endo,0}} (X + u - c)\cdot \mathrm{cof}(F)
  ///       N\,dA, \qquad c = \frac1{n_r}\sum_{v \in \mathrm{rim}} (X_v +
  ///       u_v), @f]
  /// exact for any rim shape (curved rim edges of Q2/P2 included): c is the
  /// mean of the current positions of the n_r rim vertices, so the lid follows
  /// a moving rim. The rim vertices are the vertices shared by the
  /// endocardium and the base, or, without a base, the endpoints of the
  /// boundary edges of the endocardium (edges of exactly one of its faces).
  /// For a planar rim and c in its plane the cone is the plane lid and both
  /// closures give the same volume (to round-off; tested).
  ///
  /// Units: mm^3.
  class CavityVolume
  {
  public:
    /// How the cavity is closed.
    enum class Closure
    {
      plane,  ///< the plane lid
      rim_fan ///< the cone from the rim's vertex mean to the rim
    };

    /// A cavity closed by a plane lid.
    /// @param[in] endocardium boundary id of the endocardial faces
    /// @param[in] lid         plane that closes the cavity
    /// (Geometry::cavity_closure)
    CavityVolume(const dealii::types::boundary_id endocardium,
                 const Geometry::Plane           &lid);

    /// A cavity closed by the fan over its rim (collective). The rim's
    /// vertices are found here once, on the active cells of @p tria, which
    /// must not be refined or repartitioned afterwards. Each rim vertex is
    /// counted by exactly one rank (the lowest subdomain id among the cells
    /// around it), so c does not depend on the partition.
    /// @param[in] tria        the mesh (serial or distributed)
    /// @param[in] endocardium boundary id of the endocardial faces
    /// @param[in] base        boundary id of the base, or
    ///            dealii::numbers::invalid_boundary_id: the rim is then the
    ///            boundary edges of the endocardium itself
    /// Throws unless the rim has at least 3 vertices.
    CavityVolume(const dealii::Triangulation<3, 3> &tria,
                 const dealii::types::boundary_id   endocardium,
                 const dealii::types::boundary_id   base);

    Closure
    closure() const
    {
      return kind;
    }

    /// Number of rim vertices (all ranks; 0 for the plane lid).
    unsigned int
    n_rim_vertices() const
    {
      return n_rim;
    }

    /// Cavity volume for the displacement @p u (ghosted, on @p dof_handler, an
    /// FESystem whose first 3 components are the displacement, each a
    /// Lagrange element with vertex DoFs), integrated with a Gauss rule of
    /// @p n_points per direction. Collective over the mesh's communicator.
    double
    volume(const dealii::Mapping<3, 3>    &mapping,
           const dealii::DoFHandler<3, 3> &dof_handler,
           const LA::MPI::Vector          &u,
           const unsigned int              n_points) const;

    /// The derivative as a vector on the DoFs of @p dof_handler (owned,
    /// non-ghosted @p dV_du, overwritten). Collective.
    ///
    /// Plane lid: the volume flux
    /// @f$-\int_{\Gamma_{endo,0}} \varphi\cdot\mathrm{cof}(F)N\,dA@f$
    /// (add_volume_flux with scale -1), which is also the follower-pressure
    /// load per unit pressure. It equals the derivative of volume() while
    /// the basal ring stays in the lid plane.
    ///
    /// Rim fan: the exact dV/du,
    /// @f[ \frac{dV}{du}\cdot\varphi = -\frac13\int_{\Gamma_{endo,0}}
    ///     \big[\varphi\cdot\mathrm{cof}(F)N + (x - c)\cdot
    ///     (\partial_F\mathrm{cof}(F)[\nabla\varphi])N\big]\,dA
    ///     + \frac13\,\delta c[\varphi]\cdot\int_{\Gamma_{endo,0}}
    ///     \mathrm{cof}(F)N\,dA, @f]
    /// @f$\delta c[\varphi] = \frac1{n_r}\sum_{v\in\mathrm{rim}}
    /// \varphi(X_v)@f$: the endocardial flux plus the flux of the moving
    /// lid. The follower-pressure load of the mechanics stays the endocardial
    /// flux alone (the lid is not a surface of the body): the two agree while
    /// the rim does not move (a fixed base).
    void
    derivative(const dealii::Mapping<3, 3>    &mapping,
               const dealii::DoFHandler<3, 3> &dof_handler,
               const LA::MPI::Vector          &u,
               const unsigned int              n_points,
               LA::MPI::Vector                &dV_du) const;

    /// Rim fan: c for @p u, the mean of X_v + u_v over the rim vertices
    /// (collective; @p u ghosted).
    dealii::Point<3>
    rim_center(const dealii::DoFHandler<3, 3> &dof_handler,
               const LA::MPI::Vector          &u) const;

    /// Rim fan: @p f(dofs) for every rim vertex this rank counts (each rim
    /// vertex on one rank), with the global indices of its 3 displacement
    /// DoFs.
    void
    for_each_rim_vertex(
      const dealii::DoFHandler<3, 3> &dof_handler,
      const std::function<
        void(const std::array<dealii::types::global_dof_index, 3> &)> &f) const;

    /// Rim fan, one endocardial face: with w = X + u - c and a = cof(F) N,
    /// adds @p scale times the face's part of dV/du and of d2V/du2 at fixed
    /// c,
    /// @f[ v_a \mathrel{+}= -\frac{s}{3}\int \varphi_a\cdot a +
    ///     w\cdot\partial a[\varphi_a]\,dA, \quad M_{ab} \mathrel{+}=
    ///     -\frac{s}{3}\int \varphi_a\cdot\partial a[\varphi_b] +
    ///     \varphi_b\cdot\partial a[\varphi_a] + w\cdot\partial^2 a[\varphi_a,
    ///     \varphi_b]\,dA, @f]
    /// with @f$w\cdot\partial^2 a[e_i g_a, e_j g_b] = (w\cdot(e_i\times
    /// e_j))(N\cdot(g_a\times g_b))@f$, and adds @f$\int a\,dA@f$ to @p
    /// area. The rest of dV/du is the lid's apex term (1/3)(int a dA) . dc;
    /// the rest of d2V/du2, (1/3)(dc[phi] . alpha[psi] + dc[psi] .
    /// alpha[phi]) with alpha[phi] = int da[phi] dA, couples the rim to the
    /// whole wall (rank 6): with @p matrix and @p alpha, alpha_k[phi_b] is
    /// added to (*alpha)[k](b) (unscaled).
    /// @param[in] fe_face values on the face (values, gradients, quadrature
    ///            points, normal vectors, JxW)
    static void
    add_fan_face(const dealii::FEFaceValues<3, 3>        &fe_face,
                 const std::vector<dealii::Tensor<1, 3>> &u_values,
                 const std::vector<dealii::Tensor<2, 3>> &u_gradients,
                 const dealii::Point<3>                  &c,
                 const double                             scale,
                 dealii::Vector<double>                  &vector,
                 dealii::FullMatrix<double>              *matrix,
                 dealii::Tensor<1, 3>                    &area,
                 std::array<dealii::Vector<double>, 3>   *alpha = nullptr);

  private:
    Closure                    kind;
    dealii::types::boundary_id endocardium;
    Geometry::Plane            lid;
    /// Per vertex of the triangulation (rank-local numbering): whether this
    /// rank counts it as a rim vertex (each rim vertex on one rank only).
    std::vector<bool> counted_rim_vertex;
    unsigned int      n_rim = 0;
  };
} // namespace systole::Mechanics
