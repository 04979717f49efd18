#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "base/registry.h"
#include "materials/passive_law.h"

#include <string>

namespace systole::Materials
{
  /// The volume ratio J = det F of a quadrature point is not positive
  /// (inverted or degenerate element). Thrown by the volumetric law and by the
  /// isochoric passive laws; a caller that knows the time may translate it
  /// into systole::ExcInvertedElement and cut the step.
  DeclException1(ExcNonPositiveVolumeRatio,
                 double,
                 << "The volume ratio J = det F = " << arg1
                 << " is not positive: the element is inverted or degenerate."
                 << " Reduce the load or time step, or refine the mesh.");

  /// A form of the volumetric energy per unit bulk modulus: U(J)/kappa and
  /// its first and second derivatives in J.
  struct VolumetricForm
  {
    double (*energy)(double J);
    double (*first_derivative)(double J);
    double (*second_derivative)(double J);
  };

  using VolumetricFormRegistry = Registry<VolumetricForm()>;

  /// The table of volumetric forms (volumetric_law.cc). A new form is one
  /// table line: its name, formula and three one-line functions with U(1) =
  /// U'(1) = 0 and U''(1) = 1 (a unit test checks every entry).
  VolumetricFormRegistry &
  volumetric_forms();

  /// Volumetric (penalty) energy @f$U(J)@f$ of a nearly incompressible
  /// material, added to an isochoric or anisotropic PassiveLaw.
  ///
  /// Forms (@f$\kappa@f$ the bulk modulus [kPa], @f$J = \det F@f$ [-]):
  /// - "quadratic":   @f$U = \frac{\kappa}{2}(J-1)^2@f$;
  /// - "logarithmic": @f$U = \frac{\kappa}{2}(\ln J)^2@f$;
  /// - "Simo-Taylor": @f$U = \frac{\kappa}{4}(J^2 - 1 - 2\ln J)@f$
  ///   (Simo and Taylor 1982, CMAME 35:107; Doll and Schweizerhof 2000,
  ///   J. Appl. Mech. 67:17 compare the three).
  ///
  /// All three have @f$U(1) = U'(1) = 0@f$ and @f$U''(1) = \kappa@f$. Each
  /// form requires J > 0 and throws ExcNonPositiveVolumeRatio otherwise (also
  /// "quadratic", which would be defined there, because an inverted element is
  /// never physical). Values used by others: @f$\kappa@f$ about 100 times the
  /// largest stiffness of the passive law (shared/reference/physiology.md).
  /// Immutable after construction; all member functions are thread safe.
  class VolumetricLaw
  {
  public:
    /// The forms of the class documentation (shorthand of their names).
    enum class Form
    {
      quadratic,
      logarithmic,
      simo_taylor
    };

    /// Parameters of subsection "Material / Volumetric".
    struct Parameters
    {
      /// Name of the form: "quadratic", "logarithmic" or "Simo-Taylor".
      std::string form = "Simo-Taylor";
      /// Bulk modulus @f$\kappa@f$ [kPa], >= 0 (0 switches the penalty off).
      double bulk_modulus = 1000.0;

      /// Declares "Form" and "Bulk modulus" in the current subsection (the
      /// factory enters "Material / Volumetric" first).
      static void
      declare(dealii::ParameterHandler &prm);

      /// Reads "Material / Volumetric" with the path getters and validates.
      static Parameters
      parse(const dealii::ParameterHandler &prm);

      /// Throws ExcMessage naming the entry "Material / Volumetric / ..." and
      /// the fix if a value is out of range.
      void
      validate() const;
    };

    /// Name of @p form as shown to users.
    static std::string
    name_of(const Form form);

    /// @param[in] form one of the three forms above.
    /// @param[in] bulk_modulus @f$\kappa@f$ [kPa], >= 0.
    VolumetricLaw(const Form form, const double bulk_modulus);

    /// Law with the form named in @p parameters (validated first).
    explicit VolumetricLaw(const Parameters &parameters);

    /// The name of the form of this law (an entry of volumetric_forms()).
    const std::string &
    form_name() const;

    /// Bulk modulus @f$\kappa@f$ [kPa].
    double
    bulk_modulus() const;

    /// Energy density @f$U(J)@f$ [kPa]; @p J = det F [-] must be > 0.
    double
    energy(const double J) const;

    /// First derivative @f$U'(J)@f$ [kPa] (the pressure-like quantity
    /// @f$p = U'(J)@f$, positive in tension).
    double
    first_derivative(const double J) const;

    /// Second derivative @f$U''(J)@f$ [kPa].
    double
    second_derivative(const double J) const;

    /// Adds the volumetric 2nd Piola-Kirchhoff stress
    /// @f$S_\mathrm{vol} = J U'(J) C^{-1}@f$ [kPa] and its consistent
    /// tangent
    /// @f$\partial S_\mathrm{vol}/\partial E = J (U' + J U'')
    /// C^{-1}\otimes C^{-1} - 2 J U' \, C^{-1}\odot C^{-1}@f$ [kPa]
    /// (with @f$(A\odot A)_{ijkl} = \frac12(A_{ik}A_{jl} + A_{il}A_{jk})@f$,
    /// E the Green-Lagrange strain) to @p S and @p dS_dE.
    /// @param[in] F deformation gradient [-], det F > 0.
    void
    add_to(const dealii::Tensor<2, 3>    &F,
           dealii::SymmetricTensor<2, 3> &S,
           dealii::SymmetricTensor<4, 3> &dS_dE) const;

    /// As above, and also adds U(J) to @p out.psi.
    void
    add_to(const dealii::Tensor<2, 3> &F, PassiveOutput &out) const;

  private:
    std::string    name;
    double         kappa;
    VolumetricForm form;
  };

  /// Adds to @p out the stress of a volumetric energy with the given
  /// derivatives at J = det F: @f$S = J U' C^{-1}@f$ and
  /// @f$\partial S/\partial E = J (U' + J U'') C^{-1}\otimes C^{-1}
  /// - 2 J U' C^{-1}\odot C^{-1}@f$ [kPa] (out.psi untouched). VolumetricLaw
  /// adds so its U'(J), U''(J); the mixed formulation passes U' = -p,
  /// U'' = 0 (the pressure p [kPa] as Lagrange multiplier of J - 1, positive
  /// in compression).
  /// @param[in] in in.F the deformation gradient [-], det F > 0 (not checked
  /// here); in.with_tangent false: S only (out.dS_dE untouched).
  void
  add_volumetric_stress(const PassiveInput &in,
                        const double        dU,
                        const double        d2U,
                        PassiveOutput      &out);
} // namespace systole::Materials
