#include "electrophysiology/ecg.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/vector.h>

#include "base/linear_algebra.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace systole::Electrophysiology
{
  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();

    const std::string section = "Electrophysiology";

    /// The default electrodes: the standard 12-lead positions on an adult
    /// torso around the LV of parameters/lv_heartbeat.prm (long axis along
    /// z, base at z = 5 mm, apex at z = -92 mm), its centre (0, 0, -40) at
    /// the origin of the body frame and its long axis pointing to the apex
    /// leftwards, anteriorly and inferiorly (docs/architecture.md, "ECG");
    /// scripts/ecg_electrodes.py's defaults. The model's +y lies to the
    /// patient's left and up (until 2026-12-06 the mirror image: every y
    /// had the other sign).
    const char *default_electrodes =
      "V1: 100 -25 -37; V2: 87 11 -70; V3: 69 14 -96; V4: 46 18 -120; "
      "V5: -2 53 -133; V6: -58 71 -121; RA: 145 -35 211; LA: 4 247 -34; "
      "LL: -134 -226 -273";
  } // namespace


  const std::vector<std::string> &
  electrode_names()
  {
    static const std::vector<std::string> names =
      {"RA", "LA", "LL", "V1", "V2", "V3", "V4", "V5", "V6"};
    return names;
  }


  const std::array<std::string, 12> &
  lead_names()
  {
    static const std::array<std::string, 12> names = {{"I",
                                                       "II",
                                                       "III",
                                                       "aVR",
                                                       "aVL",
                                                       "aVF",
                                                       "V1",
                                                       "V2",
                                                       "V3",
                                                       "V4",
                                                       "V5",
                                                       "V6"}};
    return names;
  }


  std::vector<Electrode>
  parse_electrodes(const std::string &text)
  {
    const std::string      entry = "Electrophysiology / ECG electrodes: ";
    const auto            &names = electrode_names();
    std::vector<Electrode> electrodes(names.size());
    std::vector<bool>      seen(names.size(), false);
    for (const auto &item : dealii::Utilities::split_string_list(text, ';'))
      {
        const auto colon = item.find(':');
        AssertThrow(colon != std::string::npos,
                    dealii::ExcMessage(entry + "'" + item +
                                       "' is not of the form 'name: x y z'."));
        const std::string name = dealii::Utilities::trim(item.substr(0, colon));
        std::string       xyz  = item.substr(colon + 1);
        std::replace(xyz.begin(), xyz.end(), ',', ' ');
        const auto words = dealii::Utilities::split_string_list(xyz, ' ');
        std::vector<std::string> coordinates;
        for (const auto &w : words)
          if (!w.empty())
            coordinates.push_back(w);
        AssertThrow(coordinates.size() == 3,
                    dealii::ExcMessage(entry + "'" + item +
                                       "' needs three coordinates."));
        const auto it = std::find(names.begin(), names.end(), name);
        AssertThrow(it != names.end(),
                    dealii::ExcMessage(
                      entry + "unknown electrode '" + name +
                      "'; the electrodes are RA, LA, LL, V1, V2, V3, V4, V5, "
                      "V6."));
        const unsigned int i = it - names.begin();
        AssertThrow(!seen[i],
                    dealii::ExcMessage(entry + "'" + name +
                                       "' is given twice."));
        seen[i]            = true;
        electrodes[i].name = name;
        for (unsigned int d = 0; d < 3; ++d)
          electrodes[i].position[d] =
            dealii::Utilities::string_to_double(coordinates[d]);
      }
    for (unsigned int i = 0; i < names.size(); ++i)
      AssertThrow(seen[i],
                  dealii::ExcMessage(entry + "electrode '" + names[i] +
                                     "' is missing (the 12 leads need RA, "
                                     "LA, LL and V1 ... V6)."));
    return electrodes;
  }


  void
  EcgParameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    const EcgParameters d;
    prm.enter_subsection(section);
    prm.declare_entry(
      "ECG",
      d.enabled ? "true" : "false",
      Bool(),
      "Compute the pseudo-ECG (the infinite homogeneous volume conductor: "
      "phi_e = 1/(4 pi sigma_b) int sigma grad V_m . grad_e(1/r) dV over the "
      "EP mesh) at ECG electrodes and write the 12 leads as "
      "/timeseries/ecg_<lead> [mV] (I, II, III, aVR, aVL, aVF, V1 ... V6, "
      "the precordial ones against Wilson's central terminal) and the "
      "biomarkers per beat to /summary (docs/architecture.md, ECG). Units: "
      "-.");
    prm.declare_entry(
      "ECG electrodes",
      default_electrodes,
      Anything(),
      "The nine electrodes 'name: x y z; ...' with names RA, LA, LL (limb "
      "electrodes) and V1 ... V6 (precordial), in the mesh's reference "
      "coordinates; all outside the heart. Default: the standard positions "
      "on an adult torso around the LV of parameters/lv_heartbeat.prm (base "
      "at z = 5, apex at z = -92), the heart's long axis pointing leftwards, "
      "anteriorly and inferiorly (docs/architecture.md, ECG). Units: mm.");
    prm.declare_entry(
      "ECG bath conductivity",
      dealii::Utilities::to_string(d.bath_conductivity),
      Double(0.0),
      "Conductivity sigma_b of the infinite homogeneous medium around the "
      "heart (the torso; about 0.2 S/m, Keller et al. 2010). Units: mS/mm "
      "(= S/m).");
    prm.declare_entry(
      "ECG biomarker threshold",
      dealii::Utilities::to_string(d.threshold),
      Double(0.0, 1.0),
      "The ECG biomarkers per beat, on the RMS over the 12 leads a(t): the "
      "QRS's core lasts from the first time a exceeds this fraction of its "
      "peak in the beat to the next time it falls below it; the QRS is the "
      "core widened to the last sample at rest before it (a at its minimum) "
      "and to the J point after it (a at its minimum before the T wave); "
      "the T wave ends the last time a exceeds this fraction of its peak "
      "after the QRS (docs/architecture.md, ECG). Units: -.");
    prm.leave_subsection();
  }


  EcgParameters
  EcgParameters::parse(const dealii::ParameterHandler &prm)
  {
    const std::vector<std::string> s = {section};
    EcgParameters                  p;
    p.enabled           = prm.get_bool(s, "ECG");
    p.electrodes        = parse_electrodes(prm.get(s, "ECG electrodes"));
    p.bath_conductivity = prm.get_double(s, "ECG bath conductivity");
    p.threshold         = prm.get_double(s, "ECG biomarker threshold");
    AssertThrow(p.bath_conductivity > 0,
                dealii::ExcMessage("Electrophysiology / ECG bath conductivity "
                                   "must be > 0."));
    AssertThrow(p.threshold > 0 && p.threshold < 1,
                dealii::ExcMessage("Electrophysiology / ECG biomarker "
                                   "threshold must lie in (0, 1)."));
    return p;
  }


  std::array<double, 12>
  leads_from_electrodes(const std::vector<double> &phi)
  {
    AssertThrow(phi.size() == electrode_names().size(),
                dealii::ExcInternalError());
    const double RA = phi[0], LA = phi[1], LL = phi[2];
    const double wilson = (RA + LA + LL) / 3.0;
    return {{LA - RA,
             LL - RA,
             LL - LA,
             RA - 0.5 * (LA + LL),
             LA - 0.5 * (RA + LL),
             LL - 0.5 * (RA + LA),
             phi[3] - wilson,
             phi[4] - wilson,
             phi[5] - wilson,
             phi[6] - wilson,
             phi[7] - wilson,
             phi[8] - wilson}};
  }


  LeadField::LeadField(const dealii::DoFHandler<3>         &dof_handler,
                       const dealii::Mapping<3, 3>         &mapping,
                       const dealii::Quadrature<3>         &quadrature,
                       const Fibres::FibreField            &fibres,
                       const double                         sigma_l,
                       const double                         sigma_t,
                       const std::vector<dealii::Point<3>> &electrodes,
                       const double                         sigma_b)
    : comm(dof_handler.get_communicator())
  {
    const auto                  &fe  = dof_handler.get_fe();
    const unsigned int           n   = fe.n_dofs_per_cell();
    const unsigned int           n_e = electrodes.size();
    dealii::FEValues<3>          fe_values(mapping,
                                  fe,
                                  quadrature,
                                  dealii::update_gradients |
                                    dealii::update_quadrature_points |
                                    dealii::update_JxW_values);
    const dealii::IndexSet       owned = dof_handler.locally_owned_dofs();
    std::vector<LA::MPI::Vector> w(n_e);
    for (auto &v : w)
      v.reinit(owned, comm);
    std::vector<dealii::Vector<double>> local(n_e, dealii::Vector<double>(n));
    std::vector<dealii::types::global_dof_index> indices(n);
    std::vector<Fibres::FibreBasis>              bases;
    const double scale = 1.0 / (4.0 * M_PI * sigma_b);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          const auto &points = fe_values.get_quadrature_points();
          fibres(cell, points, bases);
          AssertThrow(bases.size() == quadrature.size(),
                      dealii::ExcInternalError());
          for (auto &l : local)
            l = 0;
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              const dealii::Tensor<1, 3> &f = bases[q].f;
              for (unsigned int e = 0; e < n_e; ++e)
                {
                  // σ g with g = (x − x_e)/r³: σ is symmetric, so
                  // σ∇φ_i · g = ∇φ_i · σ g.
                  const dealii::Tensor<1, 3> d = points[q] - electrodes[e];
                  const double               r = d.norm();
                  AssertThrow(r > 0,
                              dealii::ExcMessage(
                                "ECG: an electrode lies on a quadrature "
                                "point of the mesh; the electrodes must lie "
                                "outside the heart."));
                  const dealii::Tensor<1, 3> g = d / (r * r * r);
                  const dealii::Tensor<1, 3> sigma_g =
                    sigma_t * g + (sigma_l - sigma_t) * (f * g) * f;
                  const double JxW = fe_values.JxW(q) * scale;
                  for (unsigned int i = 0; i < n; ++i)
                    local[e][i] += (fe_values.shape_grad(i, q) * sigma_g) * JxW;
                }
            }
          cell->get_dof_indices(indices);
          for (unsigned int e = 0; e < n_e; ++e)
            w[e].add(indices, local[e]);
        }
    weights.resize(n_e);
    for (unsigned int e = 0; e < n_e; ++e)
      {
        w[e].compress(dealii::VectorOperation::add);
        weights[e].resize(owned.n_elements());
        const Vec      vec    = static_cast<const Vec &>(w[e]);
        const double  *values = nullptr;
        PetscErrorCode ierr   = VecGetArrayRead(vec, &values);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
        std::copy(values, values + weights[e].size(), weights[e].begin());
        ierr = VecRestoreArrayRead(vec, &values);
        AssertThrow(ierr == 0, dealii::ExcPETScError(ierr));
      }
  }


  std::vector<double>
  LeadField::potentials(
    const dealii::ArrayView<const double> &owned_values) const
  {
    std::vector<double> phi(weights.size(), 0.0);
    for (unsigned int e = 0; e < weights.size(); ++e)
      {
        AssertThrow(owned_values.size() == weights[e].size(),
                    dealii::ExcInternalError());
        double sum = 0;
        for (unsigned int i = 0; i < weights[e].size(); ++i)
          sum += weights[e][i] * owned_values[i];
        phi[e] = sum;
      }
    std::vector<double> total(phi.size());
    const int           ierr = MPI_Allreduce(phi.data(),
                                   total.data(),
                                   static_cast<int>(phi.size()),
                                   MPI_DOUBLE,
                                   MPI_SUM,
                                   comm);
    AssertThrowMPI(ierr);
    return total;
  }


  namespace
  {
    /// Time at which the linear interpolant of (t0, y0), (t1, y1) crosses
    /// @p level.
    double
    crossing(const double t0,
             const double y0,
             const double t1,
             const double y1,
             const double level)
    {
      if (y1 == y0)
        return t1;
      return t0 + (level - y0) / (y1 - y0) * (t1 - t0);
    }
  } // namespace


  EcgBiomarkers
  ecg_biomarkers(const std::vector<double>                 &times,
                 const std::vector<std::array<double, 12>> &leads,
                 const double                               threshold)
  {
    AssertThrow(times.size() == leads.size() && times.size() >= 3,
                dealii::ExcMessage("ECG biomarkers: need at least three "
                                   "samples of the 12 leads."));
    const unsigned int n = times.size();
    EcgBiomarkers      b;
    b.qrs_onset = b.qrs_end = b.qrs_duration = b.t_end = b.qt_interval = nan;
    b.r_amplitude.fill(nan);

    // The RMS amplitude over the leads.
    std::vector<double> amplitude(n);
    for (unsigned int k = 0; k < n; ++k)
      {
        AssertThrow(k == 0 || times[k] > times[k - 1],
                    dealii::ExcMessage("ECG biomarkers: the sample times "
                                       "must increase."));
        double sum = 0;
        for (const double v : leads[k])
          sum += v * v;
        amplitude[k] = std::sqrt(sum / 12.0);
      }
    const double peak = *std::max_element(amplitude.begin(), amplitude.end());
    if (!(peak > 0))
      return b;
    const double level = threshold * peak;

    // QRS: its core from the first upward crossing of the level to the next
    // downward one (robust: the peak is in the QRS), then widened to its
    // whole extent, since a level relative to the peak cuts the small first
    // and last deflections (the first junctions, the last basal cells): the
    // onset is the last sample before the core where a is at its minimum
    // over the samples before the core (at rest a = 0: the last sample
    // before the first deflection), the J point the first sample after the
    // core where a is at its minimum up to the T wave's peak (the ST segment
    // rises into the T wave; a notch before a terminal deflection smaller
    // than the T wave is not taken for it). Values within 0.1 % of the peak
    // of the minimum count as at it: the last cells' upstrokes fade into a
    // slowly drifting ST segment (a knee, not a sharp minimum), and the
    // first deflections below that are invisible in any ECG.
    unsigned int first = 0;
    while (amplitude[first] < level)
      ++first;
    unsigned int below = first + 1;
    while (below < n && amplitude[below] >= level)
      ++below;
    if (below == n)
      return b; // the QRS has not ended
    const double tolerance = 1e-3 * peak;
    const double rest =
      *std::min_element(amplitude.begin(), amplitude.begin() + first + 1);
    unsigned int onset = first;
    while (amplitude[onset] > rest + tolerance)
      --onset;
    // The T wave's peak: the largest a after the first local minimum past
    // the core (none: a still falls at the last sample, the QRS not over).
    unsigned int dip = below;
    while (dip + 1 < n && amplitude[dip + 1] < amplitude[dip])
      ++dip;
    if (dip + 1 == n)
      return b;
    const unsigned int t_peak =
      std::max_element(amplitude.begin() + dip, amplitude.end()) -
      amplitude.begin();
    const double st      = *std::min_element(amplitude.begin() + below,
                                        amplitude.begin() + t_peak + 1);
    unsigned int j_point = below;
    while (amplitude[j_point] > st + tolerance)
      ++j_point;
    b.qrs_onset    = times[onset];
    b.qrs_end      = times[j_point];
    b.qrs_duration = b.qrs_end - b.qrs_onset;

    // R waves: the largest positive value of each lead within the QRS.
    for (unsigned int l = 0; l < 12; ++l)
      {
        double r = 0;
        for (unsigned int k = 0; k < n; ++k)
          if (times[k] >= b.qrs_onset && times[k] <= b.qrs_end)
            r = std::max(r, leads[k][l]);
        b.r_amplitude[l] = r;
      }

    // T-wave end: the last time the amplitude exceeds the level of its peak
    // after the QRS.
    double       peak_after = 0;
    unsigned int start      = n;
    for (unsigned int k = 0; k < n; ++k)
      if (times[k] > b.qrs_end)
        {
          start      = std::min(start, k);
          peak_after = std::max(peak_after, amplitude[k]);
        }
    if (start < n && peak_after > 0)
      {
        const double t_level = threshold * peak_after;
        unsigned int above   = start;
        for (unsigned int k = start; k < n; ++k)
          if (amplitude[k] >= t_level)
            above = k;
        if (above + 1 < n)
          {
            b.t_end       = crossing(times[above],
                               amplitude[above],
                               times[above + 1],
                               amplitude[above + 1],
                               t_level);
            b.qt_interval = b.t_end - b.qrs_onset;
          }
      }
    return b;
  }
} // namespace systole::Electrophysiology
