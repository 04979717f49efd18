#include "materials/volumetric_law.h"

#include <cmath>

namespace systole::Materials
{
  namespace
  {
    constexpr const char *quadratic_name   = "quadratic";
    constexpr const char *logarithmic_name = "logarithmic";
    constexpr const char *simo_taylor_name = "Simo-Taylor";
  } // namespace


  void
  VolumetricLaw::Parameters::declare(dealii::ParameterHandler &prm)
  {
    const Parameters defaults;
    prm.declare_entry(
      "Form",
      defaults.form,
      dealii::Patterns::Selection(form_names()),
      "Volumetric penalty energy U(J), J = det F: quadratic kappa/2 (J-1)^2, "
      "logarithmic kappa/2 (ln J)^2, Simo-Taylor kappa/4 (J^2 - 1 - 2 ln J). "
      "Units: none. Source: Simo and Taylor 1982 (CMAME 35:107); all three "
      "have U''(1) = kappa.");
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
    AssertThrow(form == quadratic_name || form == logarithmic_name ||
                  form == simo_taylor_name,
                dealii::ExcMessage("Material / Volumetric / Form = \"" + form +
                                   "\" is unknown; choose one of " +
                                   form_names() + "."));
    AssertThrow(std::isfinite(bulk_modulus) && bulk_modulus >= 0.0,
                dealii::ExcMessage(
                  "Material / Volumetric / Bulk modulus = " +
                  dealii::Patterns::Tools::to_string(bulk_modulus) +
                  " kPa must be >= 0; set e.g. 1000 kPa (about 100 x the "
                  "largest passive stiffness)."));
  }


  std::string
  VolumetricLaw::form_names()
  {
    return std::string(logarithmic_name) + "|" + quadratic_name + "|" +
           simo_taylor_name;
  }


  VolumetricLaw::Form
  VolumetricLaw::form_from_name(const std::string &name)
  {
    if (name == quadratic_name)
      return Form::quadratic;
    if (name == logarithmic_name)
      return Form::logarithmic;
    if (name == simo_taylor_name)
      return Form::simo_taylor;
    AssertThrow(false,
                dealii::ExcMessage("Unknown volumetric form \"" + name +
                                   "\"; choose one of " + form_names() + "."));
    return Form::quadratic;
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
    : volumetric_form(form)
    , kappa(bulk_modulus)
  {
    Parameters p;
    p.form         = name_of(form);
    p.bulk_modulus = bulk_modulus;
    p.validate();
  }


  VolumetricLaw::VolumetricLaw(const Parameters &parameters)
    : volumetric_form(form_from_name(parameters.form))
    , kappa(parameters.bulk_modulus)
  {
    parameters.validate();
  }


  VolumetricLaw::Form
  VolumetricLaw::form() const
  {
    return volumetric_form;
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
    switch (volumetric_form)
      {
        case Form::quadratic:
          return 0.5 * kappa * (J - 1.0) * (J - 1.0);
        case Form::logarithmic:
          return 0.5 * kappa * std::log(J) * std::log(J);
        case Form::simo_taylor:
          return 0.25 * kappa * (J * J - 1.0 - 2.0 * std::log(J));
      }
    return 0.0;
  }


  double
  VolumetricLaw::first_derivative(const double J) const
  {
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    switch (volumetric_form)
      {
        case Form::quadratic:
          return kappa * (J - 1.0);
        case Form::logarithmic:
          return kappa * std::log(J) / J;
        case Form::simo_taylor:
          return 0.5 * kappa * (J - 1.0 / J);
      }
    return 0.0;
  }


  double
  VolumetricLaw::second_derivative(const double J) const
  {
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    switch (volumetric_form)
      {
        case Form::quadratic:
          return kappa;
        case Form::logarithmic:
          return kappa * (1.0 - std::log(J)) / (J * J);
        case Form::simo_taylor:
          return 0.5 * kappa * (1.0 + 1.0 / (J * J));
      }
    return 0.0;
  }


  void
  VolumetricLaw::add_to(const dealii::Tensor<2, 3>    &F,
                        dealii::SymmetricTensor<2, 3> &S,
                        dealii::SymmetricTensor<4, 3> &dS_dE) const
  {
    const double J = dealii::determinant(F);
    AssertThrow(J > 0.0, ExcNonPositiveVolumeRatio(J));
    add_volumetric_stress(F,
                          first_derivative(J),
                          second_derivative(J),
                          S,
                          dS_dE);
  }


  void
  add_volumetric_stress(const dealii::Tensor<2, 3>    &F,
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


  void
  VolumetricLaw::add_to(const dealii::Tensor<2, 3> &F, PassiveOutput &out) const
  {
    add_to(F, out.S, out.dS_dE);
    out.psi += energy(dealii::determinant(F));
  }
} // namespace systole::Materials
