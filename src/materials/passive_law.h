#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "fibres/fibre_basis.h"

namespace systole::Materials
{
  /// Everything a passive law may look at, at one quadrature point.
  struct PassiveInput
  {
    dealii::Tensor<2, 3> F; ///< deformation gradient (reference -> current) [-]
    Fibres::FibreBasis basis; ///< orthonormal f0, s0, n0 in the reference frame
    /// false when the caller needs psi and S only (a residual without its
    /// tangent): a law may then skip dS_dE, which is left unspecified.
    bool with_tangent = true;
  };

  /// What a passive law returns at one quadrature point.
  struct PassiveOutput
  {
    double                        psi = 0.0; ///< strain energy density [kPa]
    dealii::SymmetricTensor<2, 3> S; ///< 2nd Piola-Kirchhoff stress [kPa]
    dealii::SymmetricTensor<4, 3>
      dS_dE; ///< tangent dS/dE (E Green-Lagrange) [kPa]
  };

  /// A hyperelastic strain-energy law of the myocardium (deviatoric/passive
  /// part; the volumetric penalty is a separate VolumetricLaw). Implementations
  /// are immutable after construction and evaluate() is thread safe.
  ///
  /// How to add one:
  /// 1. write materials/<law>.{h,cc}: a struct <Law>Parameters (law_name,
  ///    declare/parse/validate, units in every help text, bounds checked in
  ///    validate) and the law deriving from
  ///    PassiveLawWithParameters<<Law>Parameters>
  ///    (materials/passive_law_with_parameters.h), which writes evaluate();
  /// 2. add one line to the table in materials/factory.cc;
  /// 3. add its test parameter sets to tests/support/law_parameters.cc and
  /// its closed-form stress (derived by hand from the formula) to
  /// tests/unit/materials/closed_form_test.cc. The tests take their list of
  /// laws from the factory table, so the finite-difference, objectivity,
  /// symmetry and mechanics tangent checks then cover the law, and a law
  /// missing from either file fails them.
  class PassiveLaw
  {
  public:
    virtual ~PassiveLaw() = default;

    /// Energy, stress and tangent at one point.
    virtual void
    evaluate(const PassiveInput &in, PassiveOutput &out) const = 0;

    /// Name used in the parameter file.
    virtual std::string
    name() const = 0;
  };
} // namespace systole::Materials
