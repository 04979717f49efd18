#include "postprocess/clinical_kinematics.h"

#include <deal.II/base/mpi.h>

#include <cmath>
#include <limits>
#include <map>

namespace systole::Postprocess
{
  namespace
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();

    /// The /timeseries columns, in the order of the peaks.
    const std::array<std::pair<const char *, const char *>, 11> columns = {
      {{"global_longitudinal_strain", "-"},
       {"global_circumferential_strain", "-"},
       {"global_radial_strain", "-"},
       {"endocardial_longitudinal_strain", "-"},
       {"endocardial_circumferential_strain", "-"},
       {"endocardial_radial_strain", "-"},
       {"twist", "deg"},
       {"torsion_per_length", "deg/mm"},
       {"av_plane_displacement", "mm"},
       {"apex_displacement", "mm"},
       {"wall_thickening_ed", "-"}}};

    /// The strain components in the order of the directions: c, l, r.
    const char *const components[3] = {"circumferential",
                                       "longitudinal",
                                       "radial"};

    /// The numbers of state() before the points: has_reference, beat,
    /// ed_volume, ed_time, ed_stage (0, 0.5, 1), the ED shape (9), the peaks,
    /// the segment peaks; then the number of points.
    constexpr unsigned int n_scalars = 5 + 9 + 11 + 17 * 3;

    /// F^-1 e_k for the ED frame (e_c, e_l, e_r) that the reference cardiac
    /// frame @p frame has under @p F: e_c along F E_c, e_r along F^-T E_r
    /// (the normal of the deformed wall layer; F E_c . F^-T E_r = E_c . E_r
    /// = 0), e_l = e_r x e_c (as e_l = e_r x e_c in the reference frame).
    std::array<dealii::Tensor<1, 3>, 3>
    pulled_back_ed_frame(const dealii::Tensor<2, 3> &F,
                         const CardiacFrame         &frame)
    {
      const dealii::Tensor<2, 3> F_inv = dealii::invert(F);
      dealii::Tensor<1, 3>       c     = F * frame.circumferential;
      c /= c.norm();
      dealii::Tensor<1, 3> r = dealii::transpose(F_inv) * frame.radial;
      r /= r.norm();
      const dealii::Tensor<1, 3> l = dealii::cross_product_3d(r, c);
      return {{F_inv * c, F_inv * l, F_inv * r}};
    }
  } // namespace

  ClinicalKinematics::ClinicalKinematics()
  {
    reset_peaks();
  }

  Needs
  ClinicalKinematics::needs() const
  {
    Needs n;
    n.cardiac_frame = n.segments = n.vertices = n.areas = true;
    return n;
  }

  void
  ClinicalKinematics::reset_peaks()
  {
    peaks.fill(nan);
    for (auto &p : segment_peaks)
      p.fill(nan);
  }

  void
  ClinicalKinematics::take_reference(const StepData       &data,
                                     const VentricleShape &shape)
  {
    has_reference = true;
    ed_volume     = data.cavity_volume;
    ed_time       = data.time - data.beat_start;
    ed_shape      = shape;
    directions.assign(data.points->size(), {});
    positions.assign(data.points->size(), {});
    for (unsigned int c = 0; c < data.points->size(); ++c)
      for (unsigned int q = 0; q < (*data.points)[c].size(); ++q)
        {
          const auto &p = (*data.points)[c][q];
          directions[c].push_back(
            pulled_back_ed_frame(p.F, (*data.frames)[c][q]));
          positions[c].push_back(p.position);
        }
    reset_peaks();
  }

  bool
  ClinicalKinematics::restore_points(const StepData &data)
  {
    std::map<std::array<double, 3>, std::size_t> index;
    for (std::size_t i = 0; i < saved_points.size() / 12; ++i)
      index.emplace(std::array<double, 3>{{saved_points[12 * i],
                                           saved_points[12 * i + 1],
                                           saved_points[12 * i + 2]}},
                    i);
    bool found = true;
    directions.assign(data.points->size(), {});
    positions.assign(data.points->size(), {});
    for (unsigned int c = 0; c < data.points->size() && found; ++c)
      for (const auto &p : (*data.points)[c])
        {
          const auto it =
            index.find({{p.position[0], p.position[1], p.position[2]}});
          if (it == index.end())
            {
              found = false;
              break;
            }
          std::array<dealii::Tensor<1, 3>, 3> d;
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int j = 0; j < 3; ++j)
              d[k][j] = saved_points[12 * it->second + 3 + 3 * k + j];
          directions[c].push_back(d);
          positions[c].push_back(p.position);
        }
    return dealii::Utilities::MPI::min(found ? 1 : 0, data.comm) == 1;
  }

  void
  ClinicalKinematics::step(const StepData &data, std::vector<IO::Column> &row)
  {
    comm                               = data.comm;
    const VentricleShape shape         = ventricle_shape(data);
    const bool           new_beat      = !has_reference || data.beat != beat;
    bool                 new_reference = new_beat;
    if (restoring)
      {
        new_reference = !restore_points(data) || new_reference;
        restoring     = false;
        saved_points.clear();
        saved_points.shrink_to_fit();
      }
    if (new_beat)
      {
        beat     = data.beat;
        ed_stage = EdStage::moving;
      }
    const double volume  = data.cavity_volume;
    const bool   ejected = std::isfinite(volume) && has_reference &&
                         volume < (1 - fall_tolerance) * ed_volume;
    if (data.filling.has_value())
      {
        // Every filling step, and the step that closes the mitral valve (the
        // heartbeat ends that step at the closure); a refilling before the
        // ejection moves ED on.
        if (ed_stage == EdStage::held)
          ed_stage = ejected         ? EdStage::fixed
                     : *data.filling ? EdStage::moving
                                     : EdStage::held;
        new_reference = new_reference || ed_stage == EdStage::moving;
        if (ed_stage == EdStage::moving && !*data.filling)
          ed_stage = EdStage::held;
      }
    else if (!new_reference && std::isfinite(volume))
      {
        if (ejected)
          ed_stage = EdStage::fixed;
        new_reference = ed_stage != EdStage::fixed &&
                        volume > (1 + rise_tolerance) * ed_volume;
      }
    if (new_reference)
      take_reference(data, shape);

    // The strains referred to ED at every point (c, l, r), their means over
    // the wall and over its endocardial layer (weighted sums and weights).
    std::vector<std::vector<std::array<double, 3>>> strains(
      data.points->size());
    std::vector<double> sums(8, 0.0);
    for (unsigned int c = 0; c < data.points->size(); ++c)
      for (unsigned int q = 0; q < (*data.points)[c].size(); ++q)
        {
          const auto           &p = (*data.points)[c][q];
          std::array<double, 3> e;
          for (unsigned int k = 0; k < 3; ++k)
            e[k] = (p.F * directions[c][q][k]).norm() - 1.0;
          strains[c].push_back(e);
          if (!data.in_wall(c))
            continue;
          const bool endocardial =
            (*data.frames)[c][q].transmural < endocardial_layer;
          for (unsigned int k = 0; k < 3; ++k)
            {
              sums[k] += e[k] * p.JxW;
              sums[4 + k] += endocardial ? e[k] * p.JxW : 0.0;
            }
          sums[3] += p.JxW;
          sums[7] += endocardial ? p.JxW : 0.0;
        }
    dealii::Utilities::MPI::sum(sums, data.comm, sums);
    const auto mean = [&](const unsigned int layer, const unsigned int k) {
      const double weight = sums[4 * layer + 3];
      return weight > 0 ? sums[4 * layer + k] / weight : nan;
    };
    const auto segments = AhaRegional::segment_means(data,
                                                     [&](const unsigned int c,
                                                         const unsigned int q) {
                                                       return strains[c][q];
                                                     });

    const dealii::Tensor<1, 3> axis   = ed_shape.base - ed_shape.apex;
    const double               length = axis.norm();
    const double               twist =
      ((shape.apical_rotation - shape.basal_rotation) -
       (ed_shape.apical_rotation - ed_shape.basal_rotation)) *
      180 / M_PI;
    // Longitudinal first, as the clinical GLS, GCS, GRS.
    const std::array<double, n_columns> values = {
      {mean(0, 1),
       mean(0, 0),
       mean(0, 2),
       mean(1, 1),
       mean(1, 0),
       mean(1, 2),
       twist,
       twist / length,
       (ed_shape.base - shape.base) * axis / length,
       (shape.apex - ed_shape.apex).norm(),
       shape.thickness / ed_shape.thickness - 1.0}};
    for (unsigned int i = 0; i < n_columns; ++i)
      {
        update_peak(peaks[i], values[i]);
        row.push_back({columns[i].first, columns[i].second, values[i]});
      }
    update_peaks(segment_peaks, segments);
  }

  void
  ClinicalKinematics::end_beat(
    const StepData                         &data,
    const std::vector<std::vector<double>> *activation_times,
    std::vector<IO::Column>                &row)
  {
    (void)data;
    (void)activation_times;
    for (unsigned int i = 0; i < n_columns; ++i)
      row.push_back(
        {std::string("peak_") + columns[i].first, columns[i].second, peaks[i]});
    row.push_back({"end_diastolic_time", "ms", ed_time});
    for (unsigned int s = 0; s < 17; ++s)
      for (unsigned int k = 0; k < 3; ++k)
        row.push_back({AhaRegional::column_prefix(s + 1) + "peak_ed_strain_" +
                         components[k],
                       "-",
                       segment_peaks[s][k]});
    reset_peaks();
  }

  std::vector<double>
  ClinicalKinematics::state() const
  {
    std::vector<double> values = {has_reference ? 1.0 : 0.0,
                                  static_cast<double>(beat),
                                  ed_volume,
                                  ed_time,
                                  ed_stage == EdStage::fixed  ? 1.0
                                  : ed_stage == EdStage::held ? 0.5
                                                              : 0.0};
    for (unsigned int d = 0; d < 3; ++d)
      values.push_back(ed_shape.apex[d]);
    for (unsigned int d = 0; d < 3; ++d)
      values.push_back(ed_shape.base[d]);
    values.insert(values.end(),
                  {ed_shape.apical_rotation,
                   ed_shape.basal_rotation,
                   ed_shape.thickness});
    values.insert(values.end(), peaks.begin(), peaks.end());
    for (const auto &segment : segment_peaks)
      values.insert(values.end(), segment.begin(), segment.end());
    // The points: restored ones not placed yet are on every rank; otherwise
    // gathered on rank 0 (only its state is saved).
    std::vector<double> points = saved_points;
    if (!restoring && has_reference)
      {
        std::vector<double> local;
        for (unsigned int c = 0; c < directions.size(); ++c)
          for (unsigned int q = 0; q < directions[c].size(); ++q)
            {
              for (unsigned int d = 0; d < 3; ++d)
                local.push_back(positions[c][q][d]);
              for (const auto &v : directions[c][q])
                for (unsigned int d = 0; d < 3; ++d)
                  local.push_back(v[d]);
            }
        for (const auto &part : dealii::Utilities::MPI::gather(comm, local, 0))
          points.insert(points.end(), part.begin(), part.end());
      }
    values.push_back(static_cast<double>(points.size() / 12));
    values.insert(values.end(), points.begin(), points.end());
    return values;
  }

  void
  ClinicalKinematics::set_state(const std::vector<double> &values)
  {
    AssertThrow(values.size() > n_scalars &&
                  values.size() ==
                    n_scalars + 1 +
                      12 * static_cast<std::size_t>(values[n_scalars]),
                dealii::ExcMessage("ClinicalKinematics: the saved state has "
                                   "the wrong size."));
    auto v             = values.begin();
    has_reference      = *v++ != 0.0;
    beat               = static_cast<unsigned int>(*v++);
    ed_volume          = *v++;
    ed_time            = *v++;
    const double stage = *v++;
    ed_stage           = stage == 1.0   ? EdStage::fixed
                         : stage == 0.5 ? EdStage::held
                                        : EdStage::moving;
    for (unsigned int d = 0; d < 3; ++d)
      ed_shape.apex[d] = *v++;
    for (unsigned int d = 0; d < 3; ++d)
      ed_shape.base[d] = *v++;
    ed_shape.apical_rotation = *v++;
    ed_shape.basal_rotation  = *v++;
    ed_shape.thickness       = *v++;
    for (auto &p : peaks)
      p = *v++;
    for (auto &segment : segment_peaks)
      for (auto &p : segment)
        p = *v++;
    ++v; // the number of points
    saved_points.assign(v, values.end());
    restoring = has_reference;
    directions.clear();
    positions.clear();
  }
} // namespace systole::Postprocess
