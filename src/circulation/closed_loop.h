#pragma once

#include <deal.II/base/parameter_handler.h>

#include "circulation/chamber_elastance.h"
#include "circulation/model.h"
#include "circulation/valve.h"
#include "circulation/windkessel.h"

#include <array>

namespace systole::Circulation
{
  /// The closed-loop circulation of Regazzoni et al. 2022 (J. Comput. Phys.
  /// 457:111083; parameters and initial state in reference/physiology.md,
  /// "Closed-loop circulation"): four chambers, four valves, and systemic
  /// and pulmonary arteries and veins, each an R-C-L compartment.
  ///
  /// State (12), internal units:
  /// - 0-3: la_volume, lv_volume, ra_volume, rv_volume, V [mm^3];
  /// - 4-7: systemic_arterial_pressure, systemic_venous_pressure,
  ///   pulmonary_arterial_pressure, pulmonary_venous_pressure, p [kPa];
  /// - 8-11: systemic_arterial_flow, systemic_venous_flow,
  ///   pulmonary_arterial_flow, pulmonary_venous_flow, Q [mm^3/ms] (the flow
  ///   out of each compartment, through its R and L).
  ///
  /// Equations (AR/VEN: arteries/veins, SYS/PUL: systemic/pulmonary):
  /// @f[ \dot V_{LA} = Q_{VEN,PUL} - Q_{MV},\ \dot V_{LV} = Q_{MV} - Q_{AV},
  ///     \ \dot V_{RA} = Q_{VEN,SYS} - Q_{TV},\ \dot V_{RV} = Q_{TV} - Q_{PV},
  /// @f]
  /// @f[ C_{AR,SYS}\dot p_{AR,SYS} = Q_{AV} - Q_{AR,SYS},\quad
  ///     C_{VEN,SYS}\dot p_{VEN,SYS} = Q_{AR,SYS} - Q_{VEN,SYS},\quad
  ///     C_{AR,PUL}\dot p_{AR,PUL} = Q_{PV} - Q_{AR,PUL},\quad
  ///     C_{VEN,PUL}\dot p_{VEN,PUL} = Q_{AR,PUL} - Q_{VEN,PUL}, @f]
  /// @f[ L\dot Q = -R Q - (p_{downstream} - p) @f] for each compartment
  /// (downstream of AR,SYS is VEN,SYS, of VEN,SYS the RA, of AR,PUL the
  /// VEN,PUL, of VEN,PUL the LA), with the chamber pressures
  /// p = E(t)(V - V_0) (ChamberElastance) and the valve flows of non-ideal
  /// diodes (DiodeValve): Q_MV = Q(p_LA - p_LV), Q_AV = Q(p_LV - p_AR,SYS),
  /// Q_TV = Q(p_RA - p_RV), Q_PV = Q(p_RV - p_AR,PUL).
  ///
  /// Cavities: 0 "lv" (inlet mitral, outlet aortic), 1 "rv" (tricuspid,
  /// pulmonary); each an elastance (the LV/RV rows of physiology.md) or
  /// external (a 3D ventricle: its pressure is an input). The atria are
  /// always elastances. Valves: 0 mitral, 1 aortic, 2 tricuspid, 3
  /// pulmonary; their event quantity is the pressure drop across them.
  /// Outputs: la_pressure, lv_pressure, ra_pressure, rv_pressure and the
  /// four valve flows (mitral_valve_flow, ...).
  ///
  /// Blood volume: the four chamber volumes plus C p of the four
  /// compliances; f conserves it exactly (every flow leaves one compartment
  /// and enters another).
  class ClosedLoop : public Model
  {
  public:
    static constexpr const char *model_name = "closed loop";

    /// Indices of the state vector.
    enum State : unsigned int
    {
      la_volume = 0,
      lv_volume,
      ra_volume,
      rv_volume,
      systemic_arterial_pressure,
      systemic_venous_pressure,
      pulmonary_arterial_pressure,
      pulmonary_venous_pressure,
      systemic_arterial_flow,
      systemic_venous_flow,
      pulmonary_arterial_flow,
      pulmonary_venous_flow,
      n_state_components
    };

    enum Valve : unsigned int
    {
      mitral = 0,
      aortic,
      tricuspid,
      pulmonary
    };

    /// An arterial or venous compartment: C dp/dt = Q_in - Q, L dQ/dt = -R Q
    /// - (p_downstream - p). Internal units.
    struct Compartment
    {
      double resistance;       ///< R [kPa ms/mm^3], > 0
      double compliance;       ///< C [mm^3/kPa], > 0
      double inductance;       ///< L [kPa ms^2/mm^3], > 0
      double initial_pressure; ///< p(0) [kPa]
      double initial_flow;     ///< Q(0) [mm^3/ms]

      /// From R [mmHg s/mL], C [mL/mmHg], L [mmHg s^2/mL], p(0) [mmHg],
      /// Q(0) [mL/s].
      static Compartment
      from_file_units(const double R,
                      const double C,
                      const double L,
                      const double p0,
                      const double Q0);
    };

    /// Internal units. The defaults are those of reference/physiology.md
    /// and of the parameter file.
    struct Parameters
    {
      double                       period          = 800.0; ///< T [ms]
      ChamberElastance::Parameters left_atrium     = default_left_atrium();
      ChamberElastance::Parameters right_atrium    = default_right_atrium();
      ChamberElastance::Parameters left_ventricle  = default_left_ventricle();
      ChamberElastance::Parameters right_ventricle = default_right_ventricle();
      /// An external ventricle uses only the initial volume of its row.
      CavityKind  left_ventricle_kind  = CavityKind::elastance;
      CavityKind  right_ventricle_kind = CavityKind::elastance;
      Compartment systemic_arteries =
        Compartment::from_file_units(0.733, 1.372, 0.005, 87.675, 71.104);
      Compartment systemic_veins =
        Compartment::from_file_units(0.32, 11.363, 0.0005, 35.898, 94.039);
      Compartment pulmonary_arteries =
        Compartment::from_file_units(0.046, 20.0, 0.0005, 19.545, 94.084);
      Compartment pulmonary_veins =
        Compartment::from_file_units(0.0015, 16.0, 0.0005, 15.004, 473.279);
      /// R_min, R_max of all four valves.
      DiodeValve valve = {resistance_from_mmHg_s_per_mL(0.0075),
                          resistance_from_mmHg_s_per_mL(75006.2)};

      /// Declares the entries of subsection "Closed loop" (enter it first):
      /// Open valve resistance, Closed valve resistance and the subsections
      /// Left atrium, Right atrium, Systemic arteries, Systemic veins,
      /// Pulmonary arteries, Pulmonary veins.
      static void
      declare(dealii::ParameterHandler &prm);

      /// Reads subsection "Circulation / Closed loop"; the period and the
      /// ventricles come from the caller (the shared entries "Circulation /
      /// Period", "Circulation / Left ventricle", ...). Validates.
      static Parameters
      parse(const dealii::ParameterHandler     &prm,
            const double                        period,
            const ChamberElastance::Parameters &left_ventricle,
            const ChamberElastance::Parameters &right_ventricle);

      /// Throws ExcMessage naming the entry ("Circulation / Closed loop /
      /// Systemic arteries / Compliance ...") for a value out of range.
      void
      validate() const;
    };

    explicit ClosedLoop(const Parameters &parameters);

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
    /// A chamber: its elastance, or, if external, the cavity whose pressure
    /// (an entry of p_ext) it takes.
    struct Chamber
    {
      const ChamberElastance *elastance;
      bool                    external;
      unsigned int            cavity;
    };

    /// The four chambers in the order of their volume states (LA, LV, RA,
    /// RV).
    std::array<Chamber, 4>
    chambers() const;

    /// The four chamber pressures (LA, LV, RA, RV) [kPa].
    std::array<double, 4>
    chamber_pressures(const Arguments &a) const;

    const Parameters       params;
    const ChamberElastance left_atrium, right_atrium, left_ventricle,
      right_ventricle;
  };
} // namespace systole::Circulation
