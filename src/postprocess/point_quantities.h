#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "fibres/fibre_basis.h"

#include <limits>

namespace systole::Postprocess
{
  /// The local cardiac frame at a point of the reference wall: orthonormal
  /// circumferential e_c, longitudinal e_l (apex to base, tangent to the
  /// wall) and radial e_r (wall normal, endocardium to epicardium), e_c =
  /// e_l x e_r (the frame of Fibres::WallFrame: e_c, e_l, e_t).
  struct CardiacFrame
  {
    dealii::Tensor<1, 3> circumferential;
    dealii::Tensor<1, 3> longitudinal;
    dealii::Tensor<1, 3> radial;
    /// The transmural wall coordinate phi: 0 on the endocardium, 1 on the
    /// epicardium (Fibres::WallFrame::transmural; NaN if unknown).
    double transmural = std::numeric_limits<double>::quiet_NaN();
  };

  /// What the field postprocessors write at one point.
  struct PointQuantities
  {
    double fibre_stretch  = 0; ///< lambda_f = |F f0| [-]
    double active_tension = 0; ///< T_a [kPa]
    double J              = 0; ///< det F [-]
    /// Largest eigenvalue of the Cauchy stress sigma [kPa].
    double first_principal_stress = 0;
    /// Cauchy stress along the current fibre, f . sigma f with f = F f0 /
    /// |F f0| [kPa].
    double fibre_stress = 0;
    /// Green-Lagrange strain E = (F^T F - I) / 2 in the reference cardiac
    /// frame: e_c . E e_c, e_l . E e_l, e_r . E e_r [-] (NaN without a
    /// frame).
    double strain_circumferential = 0;
    double strain_longitudinal    = 0;
    double strain_radial          = 0;
  };

  /// The quantities at a point with deformation gradient @p F, fibre frame
  /// @p basis, Cauchy stress @p sigma [kPa], active tension @p tension [kPa]
  /// and cardiac frame @p frame (null: the strains are NaN).
  PointQuantities
  point_quantities(const dealii::Tensor<2, 3>          &F,
                   const Fibres::FibreBasis            &basis,
                   const dealii::SymmetricTensor<2, 3> &sigma,
                   const double                         tension,
                   const CardiacFrame                  *frame);
} // namespace systole::Postprocess
