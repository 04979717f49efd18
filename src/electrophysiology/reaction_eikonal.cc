// The eikonal and reaction-eikonal models of Monodomain (Electrophysiology /
// Model): the eikonal activation times from the stimuli, the nodal stimulus
// of the reaction-eikonal model, and the activation of the eikonal model
// alone; the Purkinje network, the sources of the eikonal models or the
// stimuli of the monodomain.

#include "electrophysiology/monodomain_impl.h"
#include "electrophysiology/single_cell.h"
#include "geometry/mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace systole::Electrophysiology
{
  namespace
  {
    /// The time from the onset of @p stimulus to the upward crossing of
    /// @p threshold [model units] of one resting cell of @p model,
    /// integrated as the tissue is (ARK, Rush-Larsen gates), with steps of
    /// at most 0.01 ms [ms].
    double
    stimulus_latency(const IonicModel &model,
                     const Stimulus   &stimulus,
                     const double      chi_C_m,
                     const double      threshold,
                     const double      time_step)
    {
      SingleCell::Settings settings;
      settings.time_step = std::min(time_step, 0.01);
      SingleCell::Pacing pacing;
      pacing.start    = 0;
      pacing.duration = stimulus.duration;
      // µA/mm³ over µF/mm³: µA/µF, the cell's amplitude.
      pacing.amplitude = stimulus.amplitude / chi_C_m;
      pacing.period    = 0;
      SingleCell cell(model, settings, pacing, 0.0);
      double     crossing = std::numeric_limits<double>::quiet_NaN();
      double     t_before = 0, v_before = cell.potential();
      cell.advance(stimulus.duration + 50,
                   [&](const double t, const double v, const double *) {
                     if (std::isnan(crossing) && v_before < threshold &&
                         v >= threshold)
                       crossing = t_before + (threshold - v_before) /
                                               (v - v_before) * (t - t_before);
                     t_before = t;
                     v_before = v;
                   });
      AssertThrow(std::isfinite(crossing),
                  dealii::ExcMessage(
                    "Electrophysiology: the stimulus '" + stimulus.name +
                    "' does not excite a resting cell of the ionic model "
                    "within 50 ms of its end: the eikonal models need a "
                    "stimulus that does."));
      return crossing;
    }
  } // namespace


  void
  Monodomain::Impl::setup_eikonal(const Fibres::FibreField      &fibres,
                                  const Geometry::BoundaryNames &names)
  {
    EikonalSolver solver(space.dof_handler, fibres, names, params.eikonal);
    // A stimulated node activates when the stimulus has brought a cell to
    // the threshold (all of a stimulated region depolarises together:
    // there the diffusion nearly vanishes); the front leaves from there.
    constexpr double    infinity = std::numeric_limits<double>::infinity();
    std::vector<double> initial(space.n_owned, infinity);
    std::vector<double> latency(params.stimuli.size());
    for (unsigned int s = 0; s < params.stimuli.size(); ++s)
      {
        latency[s] = stimulus_latency(model,
                                      params.stimuli[s],
                                      params.chi * params.C_m,
                                      threshold,
                                      params.time_step);
        if (!params.purkinje.enabled)
          for (const unsigned int i : stimulation.nodes[s])
            initial[i] =
              std::min(initial[i], params.stimuli[s].start + latency[s]);
      }
    if (params.purkinje.enabled)
      {
        grow_purkinje(names, params.stimuli.front().start + latency[0]);
        add_junction_sources(purkinje, space.node_positions, initial, comm);
      }
    solver.solve(initial);
    eikonal.times      = solver.owned_times();
    eikonal.statistics = solver.statistics();

    // The reaction-eikonal stimulus: the first stimulus's current, from
    // its latency before each node's eikonal time, in place of the stimuli
    // (whose nodes it stimulates at their own start).
    if (params.model == Parameters::Model::reaction_eikonal)
      {
        const Stimulus &first = params.stimuli.front();
        eikonal.duration      = first.duration;
        eikonal.rate          = first.amplitude * stimulation.scale;
        std::vector<std::pair<double, unsigned int>> onsets;
        for (unsigned int i = 0; i < space.n_owned; ++i)
          if (eikonal.times[i] < infinity)
            onsets.emplace_back(eikonal.times[i] - latency[0], i);
        std::sort(onsets.begin(), onsets.end());
        for (const auto &[onset, i] : onsets)
          {
            eikonal.onsets.push_back(onset);
            eikonal.onset_nodes.push_back(i);
          }
        eikonal.first_onset =
          dealii::Utilities::MPI::min(onsets.empty() ? infinity
                                                     : onsets.front().first,
                                      comm);
        eikonal.last_onset =
          dealii::Utilities::MPI::max(onsets.empty() ? -infinity
                                                     : onsets.back().first,
                                      comm);
        for (auto &nodes : stimulation.nodes)
          nodes.clear();
      }
  }


  void
  Monodomain::Impl::grow_purkinje(const Geometry::BoundaryNames &names,
                                  const double                   his_time)
  {
    const auto start = std::chrono::steady_clock::now();
    const auto grow  = [&](const PurkinjeParameters &tree) {
      Geometry::require_boundary(tria, names, tree.surface);
      const auto surface =
        TriangleSurface::gather(tria, names.id(tree.surface), comm);
      return std::make_pair(build_purkinje_network(surface, tree, his_time),
                            surface.n_triangles());
    };
    auto [network, n_triangles] = grow(params.purkinje);
    std::string part            = params.purkinje.surface;
    if (!params.purkinje.right.surface.empty())
      {
        const auto right = grow(params.purkinje.right_bundle());
        network          = merge(network, right.first);
        n_triangles += right.second;
        part += "' and '" + params.purkinje.right.surface;
      }
    purkinje     = std::move(network);
    double first = std::numeric_limits<double>::infinity(), last = -first;
    for (const unsigned int j : purkinje.junctions)
      {
        first = std::min(first, purkinje.times[j]);
        last  = std::max(last, purkinje.times[j]);
      }
    std::ostringstream o;
    o << "Electrophysiology: Purkinje tree on '" << part << "' (" << n_triangles
      << " triangles): " << purkinje.nodes.size() << " nodes, "
      << purkinje.junctions.size() << " junctions, His activation " << his_time
      << " ms, junctions activated " << first << " ... " << last
      << " ms, muscle after " << purkinje.junction_delay << " ms more ("
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
           .count()
      << " s)";
    logger.line(o.str());
  }


  void
  Monodomain::Impl::setup_purkinje_stimuli(const Geometry::BoundaryNames &names)
  {
    // The His bundle activates at the first stimulus's start (the
    // monodomain has no eikonal latency); the junctions' stimuli replace
    // the given ones.
    Stimulus pulse = params.stimuli.front();
    grow_purkinje(names, pulse.start);
    pulse.region.radius = params.purkinje.junction_radius;
    params.stimuli =
      junction_stimuli(purkinje, space.node_positions, pulse, comm);
  }


  void
  Monodomain::Impl::eikonal_step_stimulus(const double t0, const double t1)
  {
    eikonal.stimulus.clear();
    const double period = params.stimulus_period;
    const double h      = t1 - t0;
    if (!(h > 0) || eikonal.onsets.empty())
      return;
    // Beats k >= 0 whose windows [onset + k P, onset + k P + duration) can
    // meet [t0, t1].
    int k_first = 0, k_last = 0;
    if (period > 0)
      {
        k_first =
          std::max(0.0,
                   std::floor((t0 - eikonal.duration - eikonal.onsets.back()) /
                              period));
        k_last =
          std::max(0.0, std::floor((t1 - eikonal.onsets.front()) / period));
      }
    for (int k = k_first; k <= k_last; ++k)
      {
        const double shift = k * period;
        // Onsets in (t0 - duration - shift, t1 - shift).
        const auto begin = std::upper_bound(eikonal.onsets.begin(),
                                            eikonal.onsets.end(),
                                            t0 - eikonal.duration - shift);
        const auto end =
          std::lower_bound(begin, eikonal.onsets.end(), t1 - shift);
        for (auto it = begin; it != end; ++it)
          {
            const double on = *it + shift;
            const double overlap =
              std::min(t1, on + eikonal.duration) - std::max(t0, on);
            if (overlap > 0)
              eikonal.stimulus.emplace_back(
                eikonal.onset_nodes[it - eikonal.onsets.begin()],
                eikonal.rate * overlap / h);
          }
      }
  }


  std::vector<double>
  Monodomain::Impl::eikonal_breakpoints(const double t0, const double t1) const
  {
    std::vector<double> times;
    if (params.model != Parameters::Model::reaction_eikonal ||
        !(eikonal.last_onset >= eikonal.first_onset))
      return times;
    const double period = params.stimulus_period;
    const double step   = 0.25 * eikonal.duration;
    const double span   = eikonal.last_onset + eikonal.duration;
    for (int k = 0;; ++k)
      {
        const double shift = k * period;
        if (eikonal.first_onset + shift >= t1)
          break;
        for (double t = eikonal.first_onset + shift; t < span + shift + step;
             t += step)
          if (t > t0 && t < t1)
            times.push_back(t);
        if (!(period > 0))
          break;
      }
    return times;
  }


  void
  Monodomain::Impl::advance_eikonal_only(const double t_end)
  {
    // The first and the most recent activation of each node by t_end, and a
    // square action potential (peak from the activation for half a period,
    // or 300 ms without one; for display: no ionic model runs).
    const double        period   = params.stimulus_period;
    const double        duration = period > 0 ? 0.5 * period : 300;
    const double        nan      = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> first(space.n_owned, nan), latest(space.n_owned, nan);
    const LocalWrite    y(state);
    const double        rest = model.resting_potential();
    const double        peak = model.from_mV(20);
    for (unsigned int i = 0; i < space.n_owned; ++i)
      {
        const double T = eikonal.times[i];
        double      &v = y.data()[i * space.n_components];
        v              = rest;
        if (!(T <= t_end))
          continue;
        first[i]       = T;
        const double k = period > 0 ? std::floor((t_end - T) / period) : 0.0;
        latest[i]      = T + k * period;
        if (t_end - latest[i] < duration)
          v = peak;
      }
    tracker.set(first, latest);
    t = t_end;
  }
} // namespace systole::Electrophysiology
