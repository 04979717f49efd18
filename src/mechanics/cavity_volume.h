#pragma once

#include "base/linear_algebra.h"
#include "geometry/mesh.h"

namespace dealii
{
  template <int dim, int spacedim>
  class DoFHandler;
  template <int dim, int spacedim>
  class Mapping;
} // namespace dealii

namespace systole::Mechanics
{
  /// Volume of the cavity bounded by the endocardium and closed by the base
  /// plane ("lid"), in the configuration deformed by a displacement field u.
  ///
  /// With a field h(x) = ((x - x_0) . e) e (div h = 1, h . n = 0 on the lid
  /// plane through x_0 with unit normal e), the divergence theorem gives
  /// @f[ V = \int_{\Gamma_{endo}} ((x - x_0)\cdot e)\,(e \cdot n_{cav})\,da
  ///       = -\int_{\Gamma_{endo,0}} ((X + u - x_0)\cdot e)\,(e \cdot J F^{-T}
  ///       N)\,dA, @f]
  /// with N the outward normal of the wall (into the cavity) and Nanson's
  /// formula. This is exact while the basal ring stays in the lid plane (a base
  /// held in its plane); otherwise it is the volume closed by the reference lid
  /// plane. Units: mm^3.
  class CavityVolume
  {
  public:
    /// @param[in] endocardium boundary id of the endocardial faces
    /// @param[in] lid         plane that closes the cavity
    /// (Geometry::boundary_plane of the base)
    CavityVolume(const dealii::types::boundary_id endocardium,
                 const Geometry::Plane           &lid);

    /// Cavity volume for the displacement @p u (ghosted, on @p dof_handler, an
    /// FESystem of 3 equal scalar elements), integrated with a Gauss rule of @p
    /// n_points per direction. Collective over the mesh's communicator.
    double
    volume(const dealii::Mapping<3, 3>    &mapping,
           const dealii::DoFHandler<3, 3> &dof_handler,
           const LA::MPI::Vector          &u,
           const unsigned int              n_points) const;

    /// The derivative dV/du as a vector on the DoFs of @p dof_handler
    /// (owned, non-ghosted @p dV_du, overwritten): the volume flux
    /// @f$-\int_{\Gamma_{endo,0}} \varphi\cdot\mathrm{cof}(F)N\,dA@f$
    /// (add_volume_flux with scale -1), which is also the follower-pressure
    /// load per unit pressure. It equals the derivative of volume() while
    /// the basal ring stays in the lid plane. Collective.
    void
    derivative(const dealii::Mapping<3, 3>    &mapping,
               const dealii::DoFHandler<3, 3> &dof_handler,
               const LA::MPI::Vector          &u,
               const unsigned int              n_points,
               LA::MPI::Vector                &dV_du) const;

  private:
    dealii::types::boundary_id endocardium;
    Geometry::Plane            lid;
  };
} // namespace systole::Mechanics
