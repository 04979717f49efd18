#pragma once

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/passive_law_with_parameters.h"

#include <array>
#include <string>

namespace systole::Materials
{
  /// Parameters of subsection "Material / Holzapfel-Ogden".
  /// Defaults: Holzapfel and Ogden 2009, Table 1.
  struct HolzapfelOgdenParameters : LawParameters<HolzapfelOgdenParameters>
  {
    static constexpr const char *law_name = "Holzapfel-Ogden";

    double a    = 0.059;  ///< isotropic stiffness [kPa], > 0
    double b    = 8.023;  ///< isotropic exponent [-], > 0
    double a_f  = 18.472; ///< fibre stiffness [kPa], >= 0
    double b_f  = 16.026; ///< fibre exponent [-], > 0
    double a_s  = 2.481;  ///< sheet stiffness [kPa], >= 0
    double b_s  = 11.120; ///< sheet exponent [-], > 0
    double a_fs = 0.216;  ///< fibre-sheet coupling stiffness [kPa], >= 0
    double b_fs = 11.436; ///< fibre-sheet coupling exponent [-], > 0
    /// width @f$\delta@f$ of the tension switch in @f$I_4 - 1@f$ [-], >= 0
    double switch_width = 0.01;
    /// The form of the tension switch.
    enum class Switch
    {
      smootherstep, ///< C^2 quintic of width switch_width (default)
      logistic      ///< 1 / (1 + exp(-k (I4 - 1))), k = switch_sharpness
    };
    Switch switch_form = Switch::smootherstep;
    /// sharpness k of the logistic switch [-], > 0
    double switch_sharpness = 100.0;

    /// Entries "a", "b", "a_f", "b_f", "a_s", "b_s", "a_fs", "b_fs", "Tension
    /// switch width" and "Tension switch sharpness".
    static const std::vector<LawEntry<HolzapfelOgdenParameters>> &
    entries();

    /// Declares the selection "Tension switch" (switch_form).
    static void
    declare_more(dealii::ParameterHandler &prm);

    /// Reads "Tension switch" from @p path into switch_form.
    void
    parse_more(const dealii::ParameterHandler &prm,
               const std::vector<std::string> &path);
  };

  /// Orthotropic exponential law of Holzapfel and Ogden (Phil. Trans. R. Soc.
  /// A 367:3445, 2009, eq. 5.38), with a smooth tension-only switch:
  /// @f[
  ///   W = \frac{a}{2b}\left(e^{b(\bar I_1 - 3)} - 1\right)
  ///     + \sum_{i=f,s} w(I_{4i} - 1)\,\frac{a_i}{2b_i}
  ///       \left(e^{b_i (I_{4i} - 1)^2} - 1\right)
  ///     + \frac{a_{fs}}{2b_{fs}}\left(e^{b_{fs} I_{8fs}^2} - 1\right),
  /// @f]
  /// W [kPa], with
  /// - the isotropic (matrix) term on the isochoric invariant
  ///   @f$\bar I_1 = J^{-2/3}\,\mathrm{tr}\,C@f$, so the law is stress free
  ///   at F = I and its bulk response comes from a VolumetricLaw;
  /// - the fibre and sheet terms on the full invariants
  ///   @f$I_{4f} = f_0\cdot C f_0@f$, @f$I_{4s} = s_0\cdot C s_0@f$ and
  ///   @f$I_{8fs} = f_0\cdot C s_0@f$ (the "anisotropic invariants are not
  ///   split" choice recommended by Sansour 2008 and Helfenstein et al. 2010).
  ///
  /// Tension-only switch: the fibre and sheet terms act only when stretched
  /// (@f$I_{4i} > 1@f$), as in the paper. A hard switch would leave a jump of
  /// @f$4a_i@f$ in the tangent at @f$I_{4i} = 1@f$, so the terms are weighted
  /// by the quintic "smootherstep" @f$w(x) = t^3(10 - 15t + 6t^2)@f$,
  /// @f$t = x/\delta@f$ clamped to [0, 1], with @f$\delta@f$ the parameter
  /// "Tension switch width". Then w = 0 for @f$I_{4i} \le 1@f$ (a compressed
  /// fibre carries exactly no stress), w = 1 for
  /// @f$I_{4i} \ge 1 + \delta@f$ (exactly the 2009 law), and W is
  /// @f$C^2@f$ in C, so the tangent is continuous for Newton. Because the
  /// term itself vanishes like @f$a_i x^2/2@f$, the blend changes the
  /// tangent only by O(a_i) however small @f$\delta@f$ is. @f$\delta = 0@f$
  /// restores the hard switch (discontinuous tangent). The I8 term is even
  /// in @f$I_{8fs}@f$ and is not switched.
  ///
  /// Logistic switch ("Tension switch = logistic"): the form of the Aróstica
  /// et al. 2025 benchmark, as its participants implement it (Simula's
  /// cardiac_benchmark, svMultiPhysics' HolzapfelOgden-ModifiedAnisotropy):
  /// @f$w(x) = 1/(1 + e^{-k x})@f$, @f$x = I_{4i} - 1@f$, sharpness k
  /// ("Tension switch sharpness", 100 in the benchmark), multiplying the
  /// whole term, so its derivative enters the stress. It is smooth
  /// everywhere but never exactly 0 or 1: w(0) = 1/2, and a compressed
  /// fibre keeps a small stress (w = 0.007 at I4 = 0.95 for k = 100).
  ///
  /// Transversely isotropic reduction: a_s = a_fs = 0 leaves only the
  /// isotropic and fibre terms (the form "keep a, b, a_f, b_f only" of
  /// physiology.md); b_s and b_fs then have no effect but must stay > 0.
  class HolzapfelOgden
    : public PassiveLawWithParameters<HolzapfelOgdenParameters>
  {
  public:
    using PassiveLawWithParameters::PassiveLawWithParameters;

    /// Energy [kPa], 2nd Piola-Kirchhoff stress [kPa] and dS/dE [kPa].
    /// Requires det F > 0 (throws ExcNonPositiveVolumeRatio).
    void
    evaluate(const PassiveInput &in, PassiveOutput &out) const override;

    /// The tension switch @f$w(x)@f$ and its first two derivatives at
    /// @f$x = I_4 - 1@f$ [-] for width @p delta [-] (see the class
    /// documentation); returned as {w, w', w''}.
    static std::array<double, 3>
    tension_switch(const double x, const double delta);

    /// The logistic switch @f$w(x) = 1/(1 + e^{-k x})@f$ and its first two
    /// derivatives at @f$x = I_4 - 1@f$, sharpness @p k [-] > 0; {w, w', w''}.
    static std::array<double, 3>
    logistic_switch(const double x, const double k);

    /// A switched fibre or sheet term @f$w(x)\,\frac{a}{2b}(e^{b x^2} - 1)@f$
    /// [kPa] and its first two derivatives in @f$x = I_4 - 1@f$, with
    /// @f$w@f$ = tension_switch(x, delta); returned as {value, first,
    /// second}, all exactly 0 where w = 0.
    /// @param[in] a stiffness [kPa]
    /// @param[in] b exponent [-], > 0
    static std::array<double, 3>
    switched_exponential(const double x,
                         const double a,
                         const double b,
                         const double delta);
  };
} // namespace systole::Materials
