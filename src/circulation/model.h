#pragma once

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

/// @file
/// The interface of a 0D circulation model: a state vector y with
/// dy/dt = f(t, y; p_ext), the valves whose opening and closing are events,
/// and n >= 1 cavities, each a (pressure, volume) pair. Internal units: ms,
/// kPa, mm^3 (flows in mm^3/ms = mL/s).

namespace systole::Circulation
{
  /// What a state or an output measures. It fixes the internal unit (mm^3,
  /// kPa, mm^3/ms) and the unit in output files (mL, mmHg, mL/s).
  enum class Quantity
  {
    volume,
    pressure,
    flow
  };

  /// Suffix of an output column of @p q: "_mL", "_mmHg" or "_mL_per_s".
  const char *
  output_suffix(const Quantity q);

  /// Unit of an output column of @p q: "mL", "mmHg" or "mL/s".
  const char *
  output_unit(const Quantity q);

  /// @p value [internal unit of @p q] in the output unit of @p q.
  double
  to_output_unit(const Quantity q, const double value);

  /// One component of the state vector.
  struct StateInfo
  {
    /// snake_case name, unique among the states and outputs of the model
    /// ("lv_volume", "systemic_arterial_pressure", ...).
    std::string name;
    Quantity    quantity;
    /// The blood volume [mm^3] that one internal unit of this state stands
    /// for: 1 for a volume, the compliance C [mm^3/kPa] for the pressure of
    /// a compliance, 1 ms for a flow (an error held for 1 ms). The absolute
    /// tolerance of the state is the volume tolerance divided by this.
    double volume_scale;
  };

  /// Where the pressure of a cavity comes from.
  enum class CavityKind
  {
    /// A 0D time-varying elastance inside the model: p = E(t) (V - V_0).
    elastance,
    /// Supplied from outside (a 3D ventricle): an input of f, see
    /// Model::rhs(). The model still owns the cavity volume as a state, so
    /// a coupled step imposes V_3D(u) = y[volume_state] with the pressure
    /// as the Lagrange multiplier of that constraint.
    external
  };

  /// A cavity (ventricle) the model couples to.
  struct CavityInfo
  {
    std::string  name; ///< prefix of its columns: "lv", "rv"
    CavityKind   kind;
    unsigned int volume_state; ///< index of its volume in y
    unsigned int inlet_valve;  ///< index into Model::valves()
    unsigned int outlet_valve; ///< index into Model::valves()
  };

  /// A valve. Its event quantity (Model::valve_indicators()) is positive
  /// while it is open and changes sign when it opens or closes.
  struct ValveInfo
  {
    std::string name; ///< "mitral", "aortic", ...
  };

  /// A named pressure or flow that the model computes from the state.
  struct OutputInfo
  {
    /// snake_case, unique among the states and outputs of the model
    std::string name;
    Quantity    quantity;
  };

  /// The arguments of every evaluation of a Model: the time @p t [ms], the
  /// state @p y (size n_states()), and @p p_ext (size n_cavities()): the
  /// pressures [kPa] of the external cavities, entries of elastance cavities
  /// ignored. Callers pass them braced: model.rhs({t, y, p_ext}, f).
  struct Arguments
  {
    double                        t;
    const dealii::Vector<double> &y;
    const dealii::Vector<double> &p_ext;
  };

  /// A 0D circulation model. Implementations are immutable after
  /// construction; all functions are const and thread-safe, and the state is
  /// passed in (nothing is cached), so a stepper can evaluate any state.
  ///
  /// Every evaluation is at one Arguments (t, y, p_ext).
  ///
  /// How to add a model: (1) write circulation/<model>.{h,cc} deriving from
  /// this class, filling the state, cavity, valve and output lists in its
  /// constructor, with a nested Parameters struct (declare/parse in the
  /// units of the parameter file, converted to internal units, every entry
  /// documented with its unit); (2) add one line to the table in
  /// circulation/model_factory.cc; (3) add tests/unit/circulation tests: the
  /// finite-difference check of both Jacobians (model_test.cc does it for
  /// every table entry) and an analytic solution.
  class Model
  {
  public:
    virtual ~Model() = default;

    /// Name of the table entry ("closed loop", ...).
    virtual std::string
    name() const = 0;

    const std::vector<StateInfo> &
    states() const
    {
      return state_info;
    }
    const std::vector<CavityInfo> &
    cavities() const
    {
      return cavity_info;
    }
    const std::vector<ValveInfo> &
    valves() const
    {
      return valve_info;
    }
    const std::vector<OutputInfo> &
    outputs() const
    {
      return output_info;
    }
    unsigned int
    n_states() const
    {
      return state_info.size();
    }
    unsigned int
    n_cavities() const
    {
      return cavity_info.size();
    }
    unsigned int
    n_valves() const
    {
      return valve_info.size();
    }

    /// True if every cavity lies on the one loop of a closed circulation
    /// (in series): the blood one ejects reaches the next, so at a periodic
    /// state all of them eject the same volume per beat (the beat summary's
    /// SV_difference, ModelBeatRecorder). False for a single cavity behind
    /// an open afterload (a Windkessel).
    bool
    cavities_in_series() const
    {
      return in_series;
    }

    /// The state at time 0 (resized to n_states()).
    virtual void
    initial_state(dealii::Vector<double> &y) const = 0;

    /// The pressure of every cavity [kPa] (resized to n_cavities()): p_ext
    /// for external ones, E(t) (V - V_0) for elastance ones.
    virtual void
    cavity_pressures(const Arguments &a, dealii::Vector<double> &p) const = 0;

    /// f = dy/dt (resized to n_states()).
    virtual void
    rhs(const Arguments &a, dealii::Vector<double> &f) const = 0;

    /// The Jacobians of f (analytic): @p df_dy = df/dy (n_states x
    /// n_states) at fixed p_ext, and @p df_dp = df/dp_ext (n_states x
    /// n_cavities; the columns of elastance cavities are zero). f is
    /// piecewise smooth: a valve's resistance jumps where its indicator
    /// changes sign, and the Jacobian there is the one of the side the
    /// indicator is on (open for > 0).
    virtual void
    jacobian(const Arguments            &a,
             dealii::FullMatrix<double> &df_dy,
             dealii::FullMatrix<double> &df_dp) const = 0;

    /// The event quantity of every valve (resized to n_valves()): positive
    /// while the valve is open, a sign change is its opening or closing (the
    /// pressure drop across a diode valve [kPa], or the flow through it when
    /// the flow is a state).
    virtual void
    valve_indicators(const Arguments &a, dealii::Vector<double> &g) const = 0;

    /// The values of outputs() (resized to their number), internal units.
    virtual void
    evaluate_outputs(const Arguments        &a,
                     dealii::Vector<double> &values) const = 0;

    /// Blood volume [mm^3]: every chamber and cavity volume plus the
    /// stressed volume C p of every compliance (the unstressed volumes of
    /// the vessels are constants and left out). Linear in y; constant in
    /// time for a closed loop (its f conserves it exactly).
    virtual double
    total_blood_volume(const dealii::Vector<double> &y) const = 0;

  protected:
    std::vector<StateInfo>  state_info;
    std::vector<CavityInfo> cavity_info;
    std::vector<ValveInfo>  valve_info;
    std::vector<OutputInfo> output_info;
    /// See cavities_in_series(); set by a closed-loop model.
    bool in_series = false;
  };
} // namespace systole::Circulation
