#pragma once

/// @file
/// The Rush-Larsen update of gating variables (Rush and Larsen 1978, IEEE
/// Trans. Biomed. Eng. 25:389): over a step dt with the potential and the
/// other states frozen, ds/dt = (s_inf - s)/tau is linear with constant
/// coefficients, so its exact solution
/// @f[ s(t + dt) = s_\infty + (s(t) - s_\infty)\, e^{-dt/\tau} @f]
/// is the update. It is unconditionally stable and keeps s between s(t) and
/// s_inf, however small tau is (the m gate of ten Tusscher-Panfilov has
/// tau < 0.01 ms at rest, far below any explicit step). The models apply it
/// to their gates in IonicModel::advance_gates_batch().

namespace systole::Electrophysiology
{
  /// The exact solution of ds/dt = (@p steady - s)/@p tau after @p dt [ms]
  /// from @p s, for constant @p steady [-] and @p tau [ms] > 0.
  double
  rush_larsen(const double s,
              const double steady,
              const double tau,
              const double dt);
} // namespace systole::Electrophysiology
