#include "postprocess/ventricle_function.h"

#include <deal.II/base/mpi.h>

#include <cmath>
#include <limits>

namespace systole::Postprocess
{
  Needs
  VentricleFunction::needs() const
  {
    Needs n;
    n.segments = n.vertices = n.areas = true;
    return n;
  }

  VentricleShape
  ventricle_shape(const StepData &data)
  {
    const AhaSegments &aha  = *data.segments;
    const auto        &axis = aha.axis();
    const auto        &e    = axis.direction;
    // The centroids (reference, deformed) of the vertices of the apical and
    // basal rings: the rotations are about the axis through them, so a
    // translation does not rotate.
    std::vector<double> centroid_sums(14, 0.0);
    for (const auto &v : *data.vertices)
      {
        const unsigned int ring = aha.ring(aha.level(v.reference));
        if (ring != 1 && ring != 3)
          continue;
        const unsigned int o = ring == 1 ? 0 : 7;
        for (unsigned int d = 0; d < 3; ++d)
          {
            centroid_sums[o + d] += v.reference[d];
            centroid_sums[o + 3 + d] += v.deformed[d];
          }
        centroid_sums[o + 6] += 1;
      }
    dealii::Utilities::MPI::sum(centroid_sums, data.comm, centroid_sums);
    const auto centroid = [&](const unsigned int ring, const bool deformed) {
      const unsigned int   o = (ring == 1 ? 0 : 7) + (deformed ? 3 : 0);
      const double         n = centroid_sums[ring == 1 ? 6 : 13];
      dealii::Tensor<1, 3> c;
      for (unsigned int d = 0; d < 3; ++d)
        c[d] = centroid_sums[o + d] / std::max(n, 1.0);
      return c;
    };
    // Sums over this rank's vertices: the apex (deformed position, count),
    // the base (deformed position, count), the rotations of the apical and
    // basal rings (sum, count).
    std::vector<double> sums(12, 0.0);
    const double        tolerance = 1e-8 * axis.length;
    for (const auto &v : *data.vertices)
      {
        const double l = aha.level(v.reference);
        if ((v.reference - axis.apex).norm() < tolerance)
          {
            for (unsigned int d = 0; d < 3; ++d)
              sums[d] += v.deformed[d];
            sums[3] += 1;
          }
        if (std::abs(l - 1.0) < 1e-8)
          {
            for (unsigned int d = 0; d < 3; ++d)
              sums[4 + d] += v.deformed[d];
            sums[7] += 1;
          }
        const unsigned int ring = aha.ring(l);
        if (ring != 1 && ring != 3)
          continue;
        // Rotation about the long axis through the ring's centroid, positive
        // right-handed about -e (counter-clockwise seen from the apex).
        dealii::Tensor<1, 3> r0 = v.reference - centroid(ring, false);
        dealii::Tensor<1, 3> r  = v.deformed - centroid(ring, true);
        r0 -= (r0 * e) * e;
        r -= (r * e) * e;
        if (r0.norm() < tolerance)
          continue;
        const double angle =
          std::atan2(-e * dealii::cross_product_3d(r0, r), r0 * r);
        sums[ring == 1 ? 8 : 10] += angle;
        sums[ring == 1 ? 9 : 11] += 1;
      }
    double volume = 0;
    for (unsigned int c = 0; c < data.points->size(); ++c)
      if (data.in_wall(c))
        for (const auto &p : (*data.points)[c])
          volume += dealii::determinant(p.F) * p.JxW;
    std::vector<double> totals(12);
    dealii::Utilities::MPI::sum(sums, data.comm, totals);
    volume = dealii::Utilities::MPI::sum(volume, data.comm);
    AssertThrow(totals[3] > 0 && totals[7] > 0 && totals[9] > 0 &&
                  totals[11] > 0,
                dealii::ExcMessage(
                  "Postprocess: the mesh has no apex vertex, base vertices or "
                  "vertices in the apical and basal rings."));
    VentricleShape shape;
    for (unsigned int d = 0; d < 3; ++d)
      {
        shape.apex[d] = totals[d] / totals[3];
        shape.base[d] = totals[4 + d] / totals[7];
      }
    shape.apical_rotation = totals[8] / totals[9];
    shape.basal_rotation  = totals[10] / totals[11];
    shape.thickness =
      2 * volume / (data.endocardial_area + data.epicardial_area);
    return shape;
  }

  void
  VentricleFunction::step(const StepData &data, std::vector<IO::Column> &row)
  {
    const VentricleShape shape = ventricle_shape(data);
    const double         length =
      (shape.base - shape.apex) * data.segments->axis().direction;
    if (!initialized)
      {
        reference_length    = length;
        reference_thickness = shape.thickness;
        initialized         = true;
      }
    const double torsion =
      (shape.apical_rotation - shape.basal_rotation) * 180 / M_PI;
    if (data.beat != beat || !(max_volume > 0))
      max_volume = data.cavity_volume;
    beat       = data.beat;
    max_volume = std::max(max_volume, data.cavity_volume);
    const double ejection_fraction =
      std::isfinite(data.cavity_volume)
        ? (max_volume - data.cavity_volume) / max_volume
        : std::numeric_limits<double>::quiet_NaN();
    row.push_back(
      {"long_axis_shortening", "-", 1.0 - length / reference_length});
    row.push_back(
      {"wall_thickening", "-", shape.thickness / reference_thickness - 1.0});
    row.push_back({"torsion", "deg", torsion});
    row.push_back({"ejection_fraction", "-", ejection_fraction});
  }

  std::vector<double>
  VentricleFunction::state() const
  {
    return {initialized ? 1.0 : 0.0,
            reference_length,
            reference_thickness,
            static_cast<double>(beat),
            max_volume};
  }


  void
  VentricleFunction::set_state(const std::vector<double> &values)
  {
    AssertThrow(values.size() == 5,
                dealii::ExcMessage("VentricleFunction: a state of 5 numbers "
                                   "expected."));
    initialized         = values[0] != 0.0;
    reference_length    = values[1];
    reference_thickness = values[2];
    beat                = static_cast<unsigned int>(values[3]);
    max_volume          = values[4];
  }
} // namespace systole::Postprocess
