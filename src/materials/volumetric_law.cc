#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  namespace
  {
    constexpr const char *quadratic_name   = "quadratic";
    constexpr const char *logarithmic_name = "logarithmic";
    constexpr const char *simo_taylor_name = "Simo-Taylor";

    /// add_volumetric_stress() on F, S and dS/dE.
    void
    add_stress(const dealii::Tensor<2, 3>    &F,
               const double                   dU,
               const double                   d2U,
               dealii::SymmetricTensor<2, 3> &S,
               dealii::SymmetricTensor<4, 3> &dS_dE,
               const bool                     with_tangent)
    {
      const double                        J = dealii::determinant(F);
      const dealii::SymmetricTensor<2, 3> C_inv =
        dealii::invert(dealii::symmetrize(dealii::transpose(F) * F));
      // S = 2 dU/dC = J U' C^{-1} (dJ/dC = J/2 C^{-1}); dS/dE = 2 dS/dC with
      // dC^{-1}/dC = -C^{-1} (.) C^{-1}, (A (.) B)_IJKL = (A_IK B_JL + A_IL
      // B_JK) / 2 (what deal.II's dC_inv_dC returns).
      S += (J * dU) * C_inv;
      if (!with_tangent)
        return;
      const double a = J * (dU + J * d2U), b = -J * dU;
      for (unsigned int I = 0; I < 3; ++I)
        for (unsigned int J_ = I; J_ < 3; ++J_)
          for (unsigned int K = 0; K < 3; ++K)
            for (unsigned int L = K; L < 3; ++L)
              dS_dE[I][J_][K][L] +=
                a * C_inv[I][J_] * C_inv[K][L] +
                b * (C_inv[I][K] * C_inv[J_][L] + C_inv[I][L] * C_inv[J_][K]);
    }
  } // namespace


  VolumetricFormRegistry &
  volumetric_forms()
  {
    // Every form: U(J)/kappa, U'(J)/kappa, U''(J)/kappa; alphabetical
    // (case-insensitive).
    static VolumetricFormRegistry registry(
      "Material / Volumetric / Form",
      {{logarithmic_name,
        "kappa/2 (ln J)^2;",
        nullptr,
        [] {
          return VolumetricForm{
            [](const double J) { return 0.5 * std::log(J) * std::log(J); },
            [](const double J) { return std::log(J) / J; },
            [](const double J) { return (1.0 - std::log(J)) / (J * J); }};
        }},
       {quadratic_name,
        "kappa/2 (J-1)^2;",
        nullptr,
        [] {
          return VolumetricForm{[](const double J) {
                                  return 0.5 * (J - 1.0) * (J - 1.0);
                                },
                                [](const double J) { return J - 1.0; },
                                [](const double) { return 1.0; }};
        }},
       {simo_taylor_name, "kappa/4 (J^2 - 1 - 2 ln J).", nullptr, [] {
          return VolumetricForm{
            [](const double J) {
              return 0.25 * (J * J - 1.0 - 2.0 * std::log(J));
            },
            [](const double J) { return 0.5 * (J - 1.0 / J); },
            [](const double J) { return 0.5 * (1.0 + 1.0 / (J * J)); }};
        }}});
    return registry;
  }


  void
  VolumetricLaw::Parameters::declare(dealii::ParameterHandler &prm)
  {
    const Parameters defaults;
    volumetric_forms().declare_selection(
      prm,
      "Form",
      defaults.form,
      "Volumetric penalty energy U(J), J = det F; every form has U''(1) = "
      "kappa (Simo and Taylor 1982, CMAME 35:107).");
    prm.declare_entry(
      "Bulk modulus",
      dealii::Patterns::Tools::to_string(defaults.bulk_modulus),
      dealii::Patterns::Double(0.0),
      "Bulk modulus kappa of the volumetric penalty (0 switches it off). "
      "Units: kPa. Range: about 100 x the largest passive stiffness, "
      "100-1000 kPa in the Land et al. 2015 benchmarks, 1000 kPa with "
      "Holzapfel-Ogden (shared/reference/physiology.md); show convergence as "
      "it grows.");
  }


  VolumetricLaw::Parameters
  VolumetricLaw::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> path = {"Material", "Volumetric"};
    Parameters                     p;
    p.form         = prm.get(path, "Form");
    p.bulk_modulus = prm.get_double(path, "Bulk modulus");
    p.validate();
    return p;
  }


  void
  VolumetricLaw::Parameters::validate() const
  {
    volumetric_forms().find(form);
    AssertThrow(std::isfinite(bulk_modulus) && bulk_modulus >= 0.0,
                dealii::ExcMessage(
                  "Material / Volumetric / Bulk modulus = " +
                  dealii::Patterns::Tools::to_string(bulk_modulus) +
                  " kPa must be >= 0; set e.g. 1000 kPa (about 100 x the "
                  "largest passive stiffness)."));
  }


  std::string
  VolumetricLaw::name_of(const Form form)
  {
    switch (form)
      {
        case Form::quadratic:
          return quadratic_name;
        case Form::logarithmic:
          return logarithmic_name;
        case Form::simo_taylor:
          return simo_taylor_name;
      }
    return "";
  }


  VolumetricLaw::VolumetricLaw(const Form form, const double bulk_modulus)
    : VolumetricLaw(Parameters{name_of(form), bulk_modulus})
  {}


  VolumetricLaw::VolumetricLaw(const Parameters &parameters)
    : name(parameters.form)
    , kappa(parameters.bulk_modulus)
  {
    parameters.validate();
    form = volumetric_forms().create(name);
  }


  const std::string &
  VolumetricLaw::form_name() const
  {
    return name;
  }


  double
  VolumetricLaw::bulk_modulus() const
  {
    return kappa;
  }


  double
  VolumetricLaw::energy(const double J) const
  {
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    return kappa * form.energy(J);
  }


  double
  VolumetricLaw::first_derivative(const double J) const
  {
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    return kappa * form.first_derivative(J);
  }


  double
  VolumetricLaw::second_derivative(const double J) const
  {
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    return kappa * form.second_derivative(J);
  }


  void
  VolumetricLaw::add_to(const dealii::Tensor<2, 3>    &F,
                        dealii::SymmetricTensor<2, 3> &S,
                        dealii::SymmetricTensor<4, 3> &dS_dE) const
  {
    const double J = dealii::determinant(F);
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    add_stress(F, first_derivative(J), second_derivative(J), S, dS_dE, true);
  }


  void
  add_volumetric_stress(const PassiveInput &in,
                        const double        dU,
                        const double        d2U,
                        PassiveOutput      &out)
  {
    add_stress(in.F, dU, d2U, out.S, out.dS_dE, in.with_tangent);
  }


  void
  VolumetricLaw::add_to(const dealii::Tensor<2, 3> &F, PassiveOutput &out) const
  {
    add_to(F, out.S, out.dS_dE);
    out.psi += energy(dealii::determinant(F));
  }
} // namespace systole::Materials
