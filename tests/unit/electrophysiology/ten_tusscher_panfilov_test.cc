// The ten Tusscher-Panfilov 2006 model on its own: the initial state, the
// variants, the I_CaL singularity, an action potential of a paced cell and
// a sub-threshold stimulus. (Its agreement with SciPy on the model file is
// scripts/tests/test_ten_tusscher_panfilov_reference.py.)
#include "electrophysiology/action_potential.h"
#include "electrophysiology/ionic_factory.h"
#include "electrophysiology/single_cell.h"
#include "electrophysiology/ten_tusscher_panfilov.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace systole;
using namespace systole::Electrophysiology;

using TTP = TenTusscherPanfilov;

namespace
{
  TTP
  variant(const TTP::CellType type)
  {
    TTP::Parameters p;
    p.cell_type = type;
    return TTP(p);
  }

  /// The beats of a cell paced at 1 Hz with @p amplitude [pA/pF], dt 0.02.
  std::vector<BeatSummary>
  paced_beats(const IonicModel  &model,
              const unsigned int n_beats,
              const double       amplitude = 52)
  {
    SingleCell::Settings settings;
    settings.time_step = 0.02;
    SingleCell::Pacing pacing;
    pacing.amplitude = amplitude;
    SingleCell               cell(model, settings, pacing, 0.0);
    std::vector<BeatSummary> beats;
    for (unsigned int k = 0; k < n_beats; ++k)
      {
        const double onset = 1000.0 * k + pacing.start;
        cell.advance(onset);
        ActionPotentialRecorder recorder;
        recorder.start(onset,
                       model.to_mV(cell.potential()),
                       model.calcium_uM(cell.state().data()));
        cell.advance(1000.0 * (k + 1),
                     [&](const double t, const double v, const double *s) {
                       recorder.add(t, model.to_mV(v), model.calcium_uM(s));
                     });
        beats.push_back(recorder.summary());
      }
    return beats;
  }
} // namespace

TEST_CASE("ten Tusscher-Panfilov starts close to rest from the model file's "
          "state",
          "[ep][ionic][ttp]")
{
  const auto model = create_ionic_model("ten Tusscher-Panfilov");
  REQUIRE(model->n_states() == 18);
  REQUIRE(model->n_gates() == 12);
  std::vector<double> s(model->n_states()), ds(model->n_states());
  model->resting_state(s.data());
  const double v = model->resting_potential();
  CHECK(model->to_mV(v) == Approx(-85.23));
  CHECK(model->potential_scale_mV() == 1.0);
  // The .ode's initial state is a snapshot of the paced cell: |dV/dt| is
  // 3.7e-4 mV/ms there (SciPy on the generated Python: -3.706e-4).
  CHECK(model->ionic_current(v, s.data()) == Approx(3.706e-4).epsilon(2e-3));
  const double I = model->ionic_current_and_state_rhs(v, s.data(), ds.data());
  CHECK(I == model->ionic_current(v, s.data()));
  for (unsigned int g = 0; g < model->n_gates(); ++g)
    CHECK(ds[g] == 0.0); // the gates advance by Rush-Larsen
  // dCa_i/dt of the generated Python at that state: -1.7842e-7 mM/ms.
  CHECK(ds[TTP::ca_i] == Approx(-1.7842e-7).epsilon(1e-3));
  std::vector<double> steady(12), tau(12);
  model->gate_rates(v, s.data(), steady.data(), tau.data());
  for (unsigned int g = 0; g < 12; ++g)
    {
      CHECK(steady[g] >= 0.0);
      CHECK(steady[g] <= 1.0);
      CHECK(tau[g] > 0.0);
    }
  // The m gate at rest is far faster than any explicit step.
  CHECK(tau[TTP::m] < 0.01);
  REQUIRE(model->has_calcium());
  CHECK(model->calcium_uM(s.data()) == Approx(0.126));
}

TEST_CASE("The ten Tusscher-Panfilov variants differ in G_to, the s gate and "
          "G_Ks",
          "[ep][ionic][ttp]")
{
  const TTP endo = variant(TTP::CellType::endocardial);
  const TTP mid  = variant(TTP::CellType::mid_myocardial);
  const TTP epi  = variant(TTP::CellType::epicardial);
  CHECK(endo.transient_outward_conductance() == 0.073);
  CHECK(mid.transient_outward_conductance() == 0.294);
  CHECK(epi.transient_outward_conductance() == 0.294);
  CHECK(endo.slow_delayed_rectifier_conductance() == 0.392);
  CHECK(mid.slow_delayed_rectifier_conductance() == 0.098);
  CHECK(epi.slow_delayed_rectifier_conductance() == 0.392);
  std::vector<double> s(18), a(12), b(12), tau_a(12), tau_b(12);
  epi.resting_state(s.data());
  // s_inf = 1/(1 + exp((V + 28)/5)) endocardially, (V + 20)/5 otherwise.
  endo.gate_rates(-28, s.data(), a.data(), tau_a.data());
  epi.gate_rates(-20, s.data(), b.data(), tau_b.data());
  CHECK(a[TTP::s] == Approx(0.5));
  CHECK(b[TTP::s] == Approx(0.5));
  endo.gate_rates(-67, s.data(), a.data(), tau_a.data());
  CHECK(tau_a[TTP::s] == Approx(1008.0));
  mid.gate_rates(-67, s.data(), b.data(), tau_b.data());
  epi.gate_rates(-67, s.data(), a.data(), tau_a.data());
  CHECK(tau_a[TTP::s] == tau_b[TTP::s]);
  CHECK(TTP::cell_type_name(TTP::CellType::mid_myocardial) == "mid-myocardial");
}

TEST_CASE("ten Tusscher-Panfilov's L-type calcium current is continuous at "
          "its removable singularity V = 15 mV",
          "[ep][ionic][ttp]")
{
  const TTP           model{TTP::Parameters()};
  std::vector<double> s(18);
  model.resting_state(s.data());
  s[TTP::d]       = 0.5; // open the L-type channel
  const double at = model.ionic_current(15.0, s.data());
  REQUIRE(std::isfinite(at));
  for (const double dv : {1e-9, 1e-6, 1e-3})
    {
      CHECK(model.ionic_current(15.0 + dv, s.data()) ==
            Approx(at).epsilon(0.1 * dv + 1e-12));
      CHECK(model.ionic_current(15.0 - dv, s.data()) ==
            Approx(at).epsilon(0.1 * dv + 1e-12));
    }
}

TEST_CASE("A paced ten Tusscher-Panfilov cell fires with the model's action "
          "potential and calcium transient; a weak stimulus does not",
          "[ep][ionic][ttp]")
{
  for (const auto type : {TTP::CellType::endocardial,
                          TTP::CellType::mid_myocardial,
                          TTP::CellType::epicardial})
    {
      const TTP model = variant(type);
      INFO(TTP::cell_type_name(type));
      const auto beats = paced_beats(model, 1);
      // SciPy on the model file (docs/verification.md): rest -85.24 mV,
      // peak 37.4-38.3 mV, APD90 292-381 ms, calcium 0.96 µM.
      CHECK(beats[0].resting_potential_mV == Approx(-85.24).margin(0.01));
      CHECK(beats[0].peak_potential_mV > 35);
      CHECK(beats[0].peak_potential_mV < 40);
      CHECK(beats[0].APD90_ms > 280);
      CHECK(beats[0].APD90_ms < 400);
      CHECK(beats[0].peak_calcium_uM > 0.9);
      CHECK(beats[0].peak_calcium_uM < 1.0);
    }
  // The mid-myocardial cell (G_Ks a quarter) has the longest action
  // potential, as in the paper.
  const auto mid = paced_beats(variant(TTP::CellType::mid_myocardial), 1);
  const auto epi = paced_beats(variant(TTP::CellType::epicardial), 1);
  CHECK(mid[0].APD90_ms > epi[0].APD90_ms + 50);
  // 10 pA/pF for 1 ms moves V by about 10 mV: below threshold, no upstroke.
  const auto weak = paced_beats(variant(TTP::CellType::epicardial), 1, 10);
  CHECK(weak[0].peak_potential_mV < -70);
}
