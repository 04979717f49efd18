#pragma once

#include <deal.II/base/parameter_handler.h>

#include "materials/tension_model.h"

#include <array>

namespace systole::Materials
{
  /// The human cross-bridge model of Land et al. 2017 (J. Mol. Cell.
  /// Cardiol. 106:68, "A model of cardiac contraction based on novel
  /// measurements of tension development in human cardiomyocytes"), active
  /// part: states XS, XW (strongly and weakly bound cross-bridges),
  /// CaTRPN (calcium-bound troponin C), TmBlocked and the distortions ζs,
  /// ζw, with XU = 1 - XS - XW - TmBlocked,
  /// @f[ \dot{XS} = k_{ws} XW - k_{su} XS - \gamma_{su}(\zeta_s) XS, @f]
  /// @f[ \dot{XW} = k_{uw} XU - k_{wu} XW - k_{ws} XW
  ///     - \gamma_{wu}(\zeta_w) XW, @f]
  /// @f[ \dot{CaTRPN} = k_{TRPN}\big((Ca/Ca_{50})^{n_{TRPN}}(1 - CaTRPN)
  ///     - CaTRPN\big), @f]
  /// @f[ \dot{TmB} = k_b \min(CaTRPN^{-n_{TM}/2}, 100)\, XU
  ///     - k_u CaTRPN^{n_{TM}/2}\, TmB, @f]
  /// @f[ \dot\zeta_{s,w} = A \dot\lambda - c_{s,w} \zeta_{s,w}, @f]
  /// with k_wu = k_uw (1/r_w - 1) - k_ws, k_su = k_ws r_w (1/r_s - 1),
  /// k_b = k_u TRPN_50^{n_TM} / (1 - r_s - (1 - r_s) r_w),
  /// A = A_eff r_s / ((1 - r_s) r_w + r_s), c_w = φ k_uw (1 - r_w)/r_w,
  /// c_s = φ k_ws r_w (1 - r_s)/r_s, γ_wu = γ_w |ζw|,
  /// γ_su = γ_s max(ζs, -1 - ζs, 0), the length-dependent sensitivity
  /// Ca_50 = Ca_50,ref + β1 (min(λ, 1.2) - 1) (as in the authors' code and
  /// simcardems; calcium in µM), and the tension
  /// @f[ T_a = h(\lambda) \frac{T_{ref}}{r_s}\big((\zeta_s + 1) XS
  ///     + \zeta_w XW\big),\quad
  ///     h = \max\big(0, 1 + \beta_0(\lambda' + \min(\lambda', 0.87)
  ///     - 1.87)\big),\ \lambda' = \min(\lambda, 1.2). @f]
  ///
  /// Time stepping: backward Euler, solved exactly (no Newton): ζ depends
  /// on λ alone (linear), CaTRPN on the calcium alone (linear), and with
  /// those at the new time the XS, XW, TmB equations are linear (a 3x3
  /// solve). Unconditionally stable, first order; at the mechanics steps of
  /// a heartbeat (1-10 ms) the fast distortion decay (c_w ≈ 0.4 /ms) is
  /// damped, not oscillating.
  class Land : public TensionModel
  {
  public:
    static constexpr const char *model_name = "Land";

    /// The state's entries.
    enum State : unsigned int
    {
      XS = 0,
      XW,
      CaTRPN,
      TmBlocked,
      zeta_s,
      zeta_w,
      n_state_values
    };

    /// Subsection "Active tension / Land" (units: kPa, ms, µM). Defaults:
    /// Land et al. 2017, Table 1 (shared/reference/physiology.md).
    struct Parameters
    {
      double T_ref    = 120;    ///< [kPa]
      double TRPN_50  = 0.35;   ///< [-]
      double n_TRPN   = 2;      ///< [-]
      double k_TRPN   = 0.1;    ///< [1/ms]
      double n_TM     = 2.4;    ///< [-]
      double k_u      = 0.04;   ///< [1/ms]
      double k_uw     = 0.182;  ///< [1/ms]
      double k_ws     = 0.012;  ///< [1/ms]
      double r_w      = 0.5;    ///< [-]
      double r_s      = 0.25;   ///< [-]
      double gamma_s  = 0.0085; ///< [-]
      double gamma_w  = 0.615;  ///< [-]
      double phi      = 2.23;   ///< [-]
      double A_eff    = 25;     ///< [-]
      double beta_0   = 2.3;    ///< [-]
      double beta_1   = -2.4;   ///< [µM]
      double Ca50_ref = 0.805;  ///< [µM]

      static void
      declare(dealii::ParameterHandler &prm);
      static Parameters
      parse(const dealii::ParameterHandler &prm);
    };

    explicit Land(const Parameters &params);

    /// At rest: no calcium bound, every cross-bridge blocked (TmBlocked =
    /// 1), no distortion.
    void
    initial_state(double *state) const override;
    void
    step(const double       *accepted,
         const TensionInput &in,
         double             *trial,
         TensionOutput      &out) const override;
    double
    tension_of_state(const double *state, const double stretch) const override;

    /// dT_a/dt of the ODEs (the right-hand side) at @p state, calcium @p ca
    /// [µM], stretch @p stretch and rate @p rate [1/ms] (for tests and
    /// references).
    void
    rhs(const double *state,
        const double  ca,
        const double  stretch,
        const double  rate,
        double       *dstate) const;

    /// The calcium sensitivity Ca_50(λ) [µM].
    double
    ca50(const double stretch) const;

    /// The length factor h(λ) [-] and its derivative.
    double
    length_factor(const double stretch, double *derivative = nullptr) const;

    /// The isometric steady-state tension at calcium @p ca [µM] and stretch
    /// @p stretch (closed form from the ODEs' fixed point with ζ = 0) [kPa].
    double
    steady_state_tension(const double ca, const double stretch) const;

    const Parameters &
    parameters() const;

  private:
    Parameters p;
    // Derived rates [1/ms] and distortion coefficients.
    double k_wu, k_su, k_b, A, c_w, c_s;
  };
} // namespace systole::Materials
