// ten Tusscher-Panfilov 2006, written once from
// src/electrophysiology/ode/tentusscher_panfilov_2006_{epi,endo,M}_cell.ode
// (fenicsx-beat 0.7.2, MIT; the variants from myokit/models, BSD 3-clause).
// The expressions, each the .ode's expression of the same name in the .ode's
// units (mV, ms, mM, pA/pF, nS/pF, um^3, pF) and in the .ode's order, are in
// ten_tusscher_panfilov_impl.h, which the batched kernel shares; here
// they are evaluated point by point with the C library's exp and log.

#include "electrophysiology/ten_tusscher_panfilov.h"

#include "electrophysiology/ten_tusscher_panfilov_impl.h"

namespace systole::Electrophysiology
{
  namespace
  {
    namespace Equations = TenTusscherPanfilovEquations;
    using Math          = Equations::LibmMath;

    // Initial values of the .ode (states(...) entries).
    constexpr double initial_V = -85.23;

    /// The equations' view of a point: value k is V (k = 0) or state k - 1.
    struct PointValues
    {
      const double  V;
      const double *y;

      double
      operator()(const unsigned int k) const
      {
        return k == 0 ? V : y[k - 1];
      }
    };

    /// Where gate_rates() writes the gates' steady states and time constants.
    struct GateRates
    {
      double *steady;
      double *tau;

      void
      time_constant(const unsigned int gate,
                    const double       steady_state,
                    const double       time_constant) const
      {
        steady[gate] = steady_state;
        tau[gate]    = time_constant;
      }

      void
      rate(const unsigned int gate,
           const double       steady_state,
           const double       rate) const
      {
        steady[gate] = steady_state;
        tau[gate]    = 1 / rate;
      }
    };
  } // namespace


  void
  TenTusscherPanfilov::Parameters::declare(dealii::ParameterHandler &prm)
  {
    prm.declare_entry(
      "Cell type",
      "epicardial",
      dealii::Patterns::Selection("endocardial|mid-myocardial|epicardial"),
      "Variant of the ten Tusscher-Panfilov 2006 cell: they differ in the "
      "transient outward current (G_to 0.073 nS/pF and slower s-gate "
      "recovery endocardially, 0.294 nS/pF otherwise) and the slow delayed "
      "rectifier (G_Ks 0.098 nS/pF mid-myocardially, 0.392 nS/pF "
      "otherwise). Units: -. Source: ten Tusscher and Panfilov 2006; the "
      "Niederer et al. 2011 benchmark uses the epicardial cell.");
  }


  TenTusscherPanfilov::Parameters
  TenTusscherPanfilov::Parameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::string type =
      prm.get({"Electrophysiology", model_name}, "Cell type");
    Parameters p;
    p.cell_type = type == "endocardial"      ? CellType::endocardial
                  : type == "mid-myocardial" ? CellType::mid_myocardial
                                             : CellType::epicardial;
    return p;
  }


  TenTusscherPanfilov::TenTusscherPanfilov(const Parameters &parameters)
    : params(parameters)
    , g_to(parameters.cell_type == CellType::endocardial ? 0.073 : 0.294)
    , g_Ks(parameters.cell_type == CellType::mid_myocardial ? 0.098 : 0.392)
  {}


  std::string
  TenTusscherPanfilov::cell_type_name(const CellType type)
  {
    switch (type)
      {
        case CellType::endocardial:
          return "endocardial";
        case CellType::mid_myocardial:
          return "mid-myocardial";
        case CellType::epicardial:
          return "epicardial";
      }
    return "";
  }

  std::string
  TenTusscherPanfilov::name() const
  {
    return model_name;
  }

  unsigned int
  TenTusscherPanfilov::n_states() const
  {
    return n_all_states;
  }

  unsigned int
  TenTusscherPanfilov::n_gates() const
  {
    return n_gate_states;
  }

  double
  TenTusscherPanfilov::resting_potential() const
  {
    return initial_V;
  }

  void
  TenTusscherPanfilov::resting_state(double *y) const
  {
    y[x_r1]    = 0.00621;
    y[x_r2]    = 0.4712;
    y[x_s]     = 0.0095;
    y[m]       = 0.00172;
    y[h]       = 0.7444;
    y[j]       = 0.7045;
    y[d]       = 3.373e-5;
    y[f]       = 0.7888;
    y[f2]      = 0.9755;
    y[f_cass]  = 0.9953;
    y[s]       = 0.999998;
    y[r]       = 2.42e-8;
    y[r_prime] = 0.9073;
    y[ca_i]    = 0.000126;
    y[ca_sr]   = 3.64;
    y[ca_ss]   = 0.00036;
    y[na_i]    = 8.604;
    y[k_i]     = 136.89;
  }


  double
  TenTusscherPanfilov::ionic_current(const double v, const double *state) const
  {
    return Equations::currents<Math>(PointValues{v, state}, g_to, g_Ks).total;
  }


  void
  TenTusscherPanfilov::state_rhs(const double  v,
                                 const double *state,
                                 double       *rhs) const
  {
    ionic_current_and_state_rhs(v, state, rhs);
  }


  double
  TenTusscherPanfilov::ionic_current_and_state_rhs(const double  v,
                                                   const double *y,
                                                   double       *rhs) const
  {
    const PointValues         in{v, y};
    const Equations::Currents c = Equations::currents<Math>(in, g_to, g_Ks);
    for (unsigned int g = 0; g < n_gate_states; ++g)
      rhs[g] = 0;
    Equations::concentration_rates(in,
                                   c,
                                   [rhs](const unsigned int state,
                                         const double       rate) {
                                     rhs[state] = rate;
                                   });
    return c.total;
  }


  void
  TenTusscherPanfilov::gate_rates(const double  V,
                                  const double *y,
                                  double       *steady,
                                  double       *tau) const
  {
    const GateRates g{steady, tau};
    Equations::channel_gates<Math>(V, g);
    if (params.cell_type == CellType::endocardial)
      Equations::calcium_gates<Math, true>(V, y[ca_ss], g);
    else
      Equations::calcium_gates<Math, false>(V, y[ca_ss], g);
  }


  bool
  TenTusscherPanfilov::has_calcium() const
  {
    return true;
  }

  double
  TenTusscherPanfilov::calcium_uM(const double *state) const
  {
    return 1000 * state[ca_i];
  }

  double
  TenTusscherPanfilov::potential_scale_mV() const
  {
    return 1.0;
  }

  double
  TenTusscherPanfilov::potential_offset_mV() const
  {
    return 0.0;
  }

  double
  TenTusscherPanfilov::transient_outward_conductance() const
  {
    return g_to;
  }

  double
  TenTusscherPanfilov::slow_delayed_rectifier_conductance() const
  {
    return g_Ks;
  }
} // namespace systole::Electrophysiology
