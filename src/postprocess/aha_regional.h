#pragma once

#include "postprocess/postprocessor.h"

#include <array>

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
  /// The segment of a quadrature point is that of its reference position.
  class AhaRegional : public Postprocessor
  {
  public:
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
    static std::array<std::array<double, 3>, 17>
    segment_means(const StepData &data);

    std::vector<double>
    state() const override;

    void
    set_state(const std::vector<double> &values) override;

  private:
    /// No peaks yet (NaN).
    void
    reset();

    std::array<std::array<double, 3>, 17> peaks{};
  };
} // namespace systole::Postprocess
