#pragma once

#include "postprocess/postprocessor.h"

#include <array>
#include <functional>
#include <string>

namespace systole::Postprocess
{
  /// Regional values of the 17 AHA segments ("AHA segments"): in /summary
  /// per beat, for every segment NN = 01 ... 17,
  /// - aha_NN_peak_strain_{circumferential,longitudinal,radial}: the peak
  ///   over the beat's steps (the value of largest magnitude, with its sign)
  ///   of the segment's volume-weighted mean Green-Lagrange strain in the
  ///   cardiac frame;
  /// - aha_NN_activation_time: the volume-weighted mean activation time in
  ///   the beat [ms] of the segment's activated points (NaN if none or
  ///   without activation).
  /// The segment of a quadrature point is that of its reference position;
  /// only the points of the LV wall count (StepData::in_wall()).
  class AhaRegional : public Postprocessor
  {
  public:
    /// Three values (circumferential, longitudinal, radial) per segment:
    /// [segment - 1][component].
    using SegmentValues = std::array<std::array<double, 3>, 17>;

    AhaRegional();

    Needs
    needs() const override;

    void
    step(const StepData &data, std::vector<IO::Column> &row) override;

    void
    end_beat(const StepData                         &data,
             const std::vector<std::vector<double>> *activation_times,
             std::vector<IO::Column>                &row) override;

    /// Volume-weighted means of the three strains per segment at the
    /// points of @p data (collective): [segment - 1][component].
    static SegmentValues
    segment_means(const StepData &data);

    /// Three values per point: value(cell, q) at quadrature point q of the
    /// locally owned cell with active index cell.
    using PointValues =
      std::function<std::array<double, 3>(unsigned int, unsigned int)>;

    /// Means of @p value over every segment's points of the LV wall,
    /// weighted by the points' reference volume (JxW), NaN for a segment
    /// without points (collective): [segment - 1][component].
    static SegmentValues
    segment_means(const StepData &data, const PointValues &value);

    /// The column name prefix "aha_NN_" of @p segment (1 ... 17).
    static std::string
    column_prefix(const unsigned int segment);

    std::vector<double>
    state() const override;

    void
    set_state(const std::vector<double> &values) override;

  private:
    /// No peaks yet (NaN).
    void
    reset();

    SegmentValues peaks{};
  };

  /// Keep in @p peak the value of largest magnitude, with its sign, of
  /// @p peak and @p value (a NaN @p peak takes @p value).
  void
  update_peak(double &peak, const double value);

  /// update_peak() of every value of @p peaks with that of @p values.
  void
  update_peaks(AhaRegional::SegmentValues       &peaks,
               const AhaRegional::SegmentValues &values);
} // namespace systole::Postprocess
