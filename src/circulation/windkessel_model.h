#pragma once

#include <deal.II/base/parameter_handler.h>

#include "circulation/chamber_elastance.h"
#include "circulation/model.h"
#include "circulation/valve.h"
#include "circulation/windkessel.h"

namespace systole::Circulation
{
  /// The left ventricle between a constant atrial pressure and a 2-, 3- or
  /// 4-element Windkessel (the table entries "2-element Windkessel", ...),
  /// with non-ideal diode valves (DiodeValve): an open system, no blood
  /// volume is conserved.
  ///
  /// The Windkessel seen from the aortic valve obeys the 4-element law of
  /// reference/physiology.md,
  /// @f[ C\dot p + \frac{p - p_{ven}}{R_p} - \left(1 + \frac{Z_c}{R_p}\right)Q
  ///     - \left(C Z_c + \frac{L}{R_p}\right)\dot Q - L C \ddot Q = 0, @f]
  /// p the aortic root pressure and Q the aortic flow: the inductance L and
  /// the characteristic impedance Z_c in series, then the peripheral
  /// resistance R_p parallel to the compliance C, whose (distal) pressure
  /// p_ar is a state. L = 0 gives the 3-element model, L = Z_c = 0 the
  /// 2-element model.
  ///
  /// States: 0 lv_volume V [mm^3], 1 arterial_pressure p_ar [kPa] and, with
  /// 4 elements, 2 arterial_flow Q [mm^3/ms] (the flow through L):
  /// @f[ \dot V = Q_{mv} - Q_{av},\quad
  ///     C\dot p_{ar} = Q_{av} - \frac{p_{ar} - p_{ven}}{R_p}, @f]
  /// with Q_mv = Q(p_at - p_lv) (mitral diode) and
  /// - 2, 3 elements: Q_av = (p_lv - p_ar) / (R(p_lv - p_ar) + Z_c), the
  ///   aortic diode in series with Z_c (0 for 2 elements); its event
  ///   quantity is p_lv - p_ar (same sign as the drop across the valve);
  /// - 4 elements: Q_av = Q, L dQ/dt = p_lv - p_ar - (R(Q) + Z_c) Q, the
  ///   valve's resistance R(Q) by the sign of the flow through it (which is
  ///   that of the drop across it), its event quantity Q. A closed valve
  ///   makes this equation stiff (time constant L / R_max): use an implicit
  ///   integrator.
  ///
  /// Cavity 0 "lv" (inlet valve 0 mitral, outlet 1 aortic), an elastance
  /// or external. Outputs: lv_pressure, atrial_pressure,
  /// aortic_root_pressure (downstream of the valve: p_ar + Z_c Q_av with 3
  /// elements, p_lv - R(Q) Q with 4), mitral_valve_flow, aortic_valve_flow.
  /// Blood volume: V + C p_ar.
  class WindkesselModel : public Model
  {
  public:
    /// Internal units; the defaults are those of the parameter file.
    struct Parameters
    {
      unsigned int n_elements = 3; ///< 2, 3 or 4
      double       period     = 800.0;
      /// R_p [kPa ms/mm^3]
      double peripheral_resistance = resistance_from_mmHg_s_per_mL(1.0);
      /// C [mm^3/kPa]
      double compliance = compliance_from_mL_per_mmHg(1.5);
      /// Z_c [kPa ms/mm^3] (3 and 4 elements)
      double characteristic_impedance = resistance_from_mmHg_s_per_mL(0.05);
      /// L [kPa ms^2/mm^3] (4 elements)
      double     inductance   = inductance_from_mmHg_s2_per_mL(0.005);
      DiodeValve mitral_valve = {resistance_from_mmHg_s_per_mL(0.0075),
                                 resistance_from_mmHg_s_per_mL(75006.2)};
      DiodeValve aortic_valve = {resistance_from_mmHg_s_per_mL(0.0075),
                                 resistance_from_mmHg_s_per_mL(75006.2)};
      /// p_at [kPa], constant
      double atrial_pressure = Units::mmHg_to_kPa(10.0);
      /// p_ven [kPa], the pressure behind R_p
      double venous_pressure = 0.0;
      /// p_ar(0) [kPa]
      double initial_arterial_pressure = Units::mmHg_to_kPa(80.0);
      /// Q(0) [mm^3/ms] (4 elements)
      double                       initial_arterial_flow = 0.0;
      ChamberElastance::Parameters left_ventricle = default_left_ventricle();
      /// An external ventricle uses only the initial volume of its row.
      CavityKind left_ventricle_kind = CavityKind::elastance;

      /// Declares "Closed valve resistance" (in the current subsection,
      /// "Circulation") and subsection "4-element Windkessel". The other
      /// entries are the Windkessel entries of subsection Circulation that
      /// the heartbeat uses too (Circulation::Parameters).
      static void
      declare(dealii::ParameterHandler &prm);

      /// Reads them (the left ventricle and the period from the caller);
      /// validates.
      static Parameters
      parse(const dealii::ParameterHandler     &prm,
            const unsigned int                  n_elements,
            const double                        period,
            const ChamberElastance::Parameters &left_ventricle);

      /// Throws ExcMessage naming the entry for a value out of range.
      void
      validate() const;
    };

    explicit WindkesselModel(const Parameters &parameters);

    /// "2-element Windkessel", "3-element Windkessel" or "4-element
    /// Windkessel".
    std::string
    name() const override;

    void
    initial_state(dealii::Vector<double> &y) const override;

    void
    cavity_pressures(const Arguments        &a,
                     dealii::Vector<double> &p) const override;

    void
    rhs(const Arguments &a, dealii::Vector<double> &f) const override;

    void
    jacobian(const Arguments            &a,
             dealii::FullMatrix<double> &df_dy,
             dealii::FullMatrix<double> &df_dp) const override;

    void
    valve_indicators(const Arguments        &a,
                     dealii::Vector<double> &g) const override;

    void
    evaluate_outputs(const Arguments        &a,
                     dealii::Vector<double> &values) const override;

    double
    total_blood_volume(const dealii::Vector<double> &y) const override;

    const Parameters &
    parameters() const
    {
      return params;
    }

  private:
    /// Cavity pressure [kPa].
    double
    lv_pressure(const Arguments &a) const;

    /// Aortic valve flow [mm^3/ms].
    double
    aortic_flow(const double p_lv, const dealii::Vector<double> &y) const;

    const Parameters       params;
    const ChamberElastance left_ventricle;
  };
} // namespace systole::Circulation
