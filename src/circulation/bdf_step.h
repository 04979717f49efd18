#pragma once

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include "circulation/model.h"

#include <boost/serialization/vector.hpp>

#include <array>
#include <vector>

namespace systole::Circulation
{
  /// The implicit time step of a 0D circulation Model whose external
  /// cavities are 3D ventricles: variable-step BDF2 (BDF1 on the first step
  /// and on the first step after each restart, i.e. after a valve event,
  /// where the solution has a kink),
  /// @f[ a_0 y_{n+1} - a_1 y_n + a_2 y_{n-1} = h\, f(t_{n+1}, y_{n+1},
  ///     p_{n+1}), \quad a_0 = \frac{1 + 2\omega}{1 + \omega},\ a_1 = 1 +
  ///     \omega,\ a_2 = \frac{\omega^2}{1 + \omega},\ \omega =
  ///     \frac{h}{h_{prev}} @f]
  /// (BDF1: a_0 = a_1 = 1, a_2 = 0), with the pressures p of the external
  /// cavities as inputs. A multistep update keeps every linear invariant of
  /// f, so the closed loop conserves its blood volume to round-off; and the
  /// volume of a cavity is its value at the end of the step, as the volume
  /// constraint of the 3D ventricle requires (a midpoint-type scheme would
  /// constrain the volume at a time where the mechanics is not solved).
  ///
  /// Use, per step: begin(t_new); then solve(p) as often as the coupled
  /// solve needs (the volume target of the 3D cavities: W(p) and dW/dp);
  /// then error_norm() and accept() or, to retry with another step, begin()
  /// again. All functions are deterministic (the same on every MPI rank).
  class BdfStep
  {
  public:
    struct Settings
    {
      double relative_tolerance = 1e-3;
      /// Absolute tolerance of volumes [mm^3]; state i gets this divided by
      /// its StateInfo::volume_scale.
      double absolute_volume_tolerance = 1.0;
      /// Absolute tolerance of the pressures of the external cavities [kPa]
      /// (they are algebraic, not states: their error is how far the linear
      /// interpolation between step ends is off, |p - p_linear| / 8).
      double absolute_pressure_tolerance = 0.01;
    };

    /// @p model must outlive this object. Starts at (@p t0, @p y0) with the
    /// external cavity pressures @p p0 (size n_cavities()).
    BdfStep(const Model                  &model,
            const Settings               &settings,
            const double                  t0,
            const dealii::Vector<double> &y0,
            const dealii::Vector<double> &p0);

    /// The model's cavities of kind external, in order: the k cavities of
    /// the volume target.
    const std::vector<unsigned int> &
    external_cavities() const
    {
      return external;
    }

    /// Time of the last accepted state [ms].
    double
    time() const
    {
      return history.back().t;
    }
    /// The last accepted state and its cavity pressures (all cavities).
    const dealii::Vector<double> &
    state() const
    {
      return history.back().y;
    }
    const dealii::Vector<double> &
    pressures() const
    {
      return history.back().p;
    }

    /// Order of the next step: 1 after start and restart(), else 2.
    unsigned int
    order() const;

    /// Set up the step from time() to @p t_new (> time()). Discards a solve
    /// of an earlier begin().
    void
    begin(const double t_new);

    /// The predicted state at the end of the step (extrapolated from the
    /// history, exact for a solution polynomial of the step's order), and
    /// the predicted pressures of the external cavities (linear
    /// extrapolation of the last two accepted pressures; the last accepted
    /// ones after the start and a restart(), which forgets the point before
    /// the event), in the layout of solve()'s @p p.
    const dealii::Vector<double> &
    predicted_state() const
    {
      return y_predicted;
    }
    dealii::Vector<double>
    predicted_pressures() const;
    /// The pressures a coupled solve starts from: predicted_pressures(), but
    /// the last accepted ones right after the start and a restart(). A
    /// restart follows a valve switch (or end-diastole, where supports may
    /// be re-referred), where the pressure's slope changes; the slope before
    /// it, extrapolated from the short step that located the event, was
    /// 6.9 kPa below the LV's pressure in the BiV heartbeat's first filling
    /// (a negative cavity pressure, an indefinite tangent, a failed solve).
    dealii::Vector<double>
    start_pressures() const;

    /// Solve the step's equations for y given the pressures @p p of the
    /// external cavities (size external_cavities().size()), by Newton's
    /// method with the model's Jacobian (from the predictor, or from the
    /// last solve of this step). Returns the volume states of the external
    /// cavities @p W [mm^3] and @p dW_dp = dW/dp [mm^3/kPa] (k x k), the
    /// volume target of the 3D cavities. Throws ExcNewtonDidNotConverge
    /// (recoverable: retry with a shorter step) when Newton fails.
    void
    solve(const dealii::Vector<double> &p,
          dealii::Vector<double>       &W,
          dealii::FullMatrix<double>   &dW_dp);

    /// The state of the last solve() and the pressures of all cavities
    /// there (the given ones of the external cavities, E(t) (V - V_0) of the
    /// elastance ones).
    const dealii::Vector<double> &
    solution() const
    {
      return y_solution;
    }
    const dealii::Vector<double> &
    solution_pressures() const
    {
      return p_solution;
    }

    /// Newton iterations of the 0D equations in solves of this step.
    unsigned int
    newton_iterations() const
    {
      return step_iterations;
    }

    /// The weighted local errors of the last solve (<= 1: acceptable):
    /// {states, pressures}. States: the largest over i of |LTE_i| / (atol_i
    /// + rtol |y_i|), the LTE estimated from the difference to the predictor
    /// (Milne's device with the error constants of the step's order and step
    /// ratio). Pressures of the external cavities: |p - p_pred| / 8 over
    /// (atol_p + rtol |p|), p_pred the linear extrapolation of the last two
    /// accepted pressures (0 when there is only one: the first step after
    /// the start and after a restart()), which is h^2 |p''|/8, the error of
    /// linear interpolation over the step.
    std::array<double, 2>
    error_norms() const;

    /// The step ratio h_next / h that brings the larger of error_norms() to
    /// about 0.8 of the tolerance (exponent 1 / (order + 1) for the states,
    /// 1/2 for the pressures), clamped to [0.2, 2].
    double
    step_ratio() const;

    /// Accept the last solve: it becomes the state at the step's end time.
    void
    accept();

    /// Forget the history before the last accepted state: the next step is
    /// BDF1 (after a valve event, where f has a kink).
    void
    restart();

    /// Write or read the accepted history (the last two points) and the
    /// order of the next step: everything the next begin() uses (boost
    /// serialization, for checkpoints). A step in progress is not kept.
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &history &first_order;
      solved = false;
    }

  private:
    /// atol_i + rtol |value| of state i: the scale of its error and of the
    /// Newton updates.
    double
    tolerance(const unsigned int i, const double value) const;

    struct Point
    {
      double                 t = 0;
      dealii::Vector<double> y, p;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int /*version*/)
      {
        archive &t &y &p;
      }
    };

    const Model              &model;
    const Settings            settings;
    std::vector<unsigned int> external;
    /// Accepted points, oldest first: the last two (one at the start).
    std::vector<Point> history;
    /// The next step is BDF1 (start, restart()).
    bool first_order = true;

    // The current step.
    double                 t_new = 0, h = 0;
    double                 a0 = 1, a1 = 1, a2 = 0;
    dealii::Vector<double> y_predicted, known; // known = a1 y_n - a2 y_n-1
    dealii::Vector<double> y_solution, p_solution;
    bool                   solved          = false;
    unsigned int           step_iterations = 0;
    /// LTE ~ error_constant (y - y_predicted).
    double error_constant = 0.5;
  };
} // namespace systole::Circulation
