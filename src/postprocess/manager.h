#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>

#include "io/results_file.h"
#include "mechanics/problem.h"

#include "postprocess/aha_segments.h"
#include "postprocess/point_quantities.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
}

namespace systole::Postprocess
{
  /// Subsection "Postprocess": the postprocessors chosen by name.
  struct Parameters
  {
    /// Names from postprocessor_names(), in the order given.
    std::vector<std::string> postprocessors;
    /// The anterior direction of the AHA segments (theta = 0).
    dealii::Tensor<1, 3> reference_direction;

    static void
    declare(dealii::ParameterHandler &prm);
    /// Throws naming the valid postprocessors on an unknown name.
    static Parameters
    parse(const dealii::ParameterHandler &prm);
  };

  /// Runs the chosen postprocessors on the mechanics of a run: evaluates the
  /// state of every quadrature point once per step (and the wall frame, the
  /// AHA segments, vertices and areas when a postprocessor needs them),
  /// hands it to each postprocessor, and writes their fields (the point
  /// values projected onto continuous Q1 nodal fields: the lumped L2
  /// projection sum_q phi_i v_q w_q / sum_q phi_i w_q, exact for a constant
  /// field). All calls are collective.
  class Manager
  {
  public:
    /// @p problem and @p names must outlive this object. If a postprocessor
    /// needs the ventricle, finds the wall of the left ventricle (LvWall:
    /// the whole mesh of a left ventricle, the LV free wall and the septum
    /// of two ventricles) and solves for its frame if one needs the cardiac
    /// frame; throws a clear error if the mesh has neither kind of
    /// ventricle, or (two ventricles) if the RV lies outside the septal
    /// segments of the AHA reference direction.
    Manager(const Parameters              &params,
            const Mechanics::Problem      &problem,
            const Geometry::BoundaryNames &names,
            Logger                        *logger = nullptr);
    ~Manager();

    /// Whether no postprocessor was chosen (then every call does nothing).
    bool
    empty() const;

    /// An accepted step at @p time [ms] of beat @p beat (starting at
    /// @p beat_start [ms]) with cavity volume @p cavity_volume [mm^3] (NaN:
    /// none), in which the ventricle fills or not (@p filling, where a
    /// circulation says so: StepData::filling): appends the /timeseries
    /// columns to @p row. The first call fixes the reference state.
    void
    step(const double               time,
         const unsigned int         beat,
         const double               beat_start,
         const double               cavity_volume,
         const std::optional<bool> &filling,
         std::vector<IO::Column>   &row);

    /// The end of a beat (or of a run), after its last step(): appends the
    /// /summary columns. @p activation_times: per point (the layout of
    /// Mechanics::Problem::quadrature_points()), the activation time in the
    /// beat [ms], NaN where not activated; null without activation.
    void
    end_beat(const std::vector<std::vector<double>> *activation_times,
             std::vector<IO::Column>                &row);

    /// The postprocessors' state (Postprocessor::state()), for checkpoints:
    /// per postprocessor its count, then its numbers.
    std::vector<double>
    state() const;

    /// Restore what state() returned (the same list of postprocessors).
    void
    set_state(const std::vector<double> &values);

    /// Add the fields of the last step() to @p data_out (the vectors stay
    /// valid until the next call). Call before build_patches.
    void
    attach_output(dealii::DataOut<3, 3> &data_out);

    /// Names of the fields attach_output() adds.
    std::vector<std::string>
    field_names() const;

    /// Verification: the quantities of the last step() per point.
    const std::vector<std::vector<PointQuantities>> &
    quantities() const;

    /// Verification: the cardiac frame per point (empty if not needed).
    const std::vector<std::vector<CardiacFrame>> &
    frames() const;

    /// Verification: the nodal values of field @p name of the last
    /// attach_output(), this rank's owned nodes.
    std::vector<double>
    nodal_values(const std::string &name) const;

    /// Verification: the wall of the left ventricle (throws unless a
    /// postprocessor needs the ventricle).
    const LvWall &
    wall() const;

    /// The AHA segments (throws unless a postprocessor needs them).
    const AhaSegments &
    segments() const;

    /// Reference volume [mm^3] of every segment and the number of cells
    /// with points in it
    /// (collective; throws unless a postprocessor needs the segments).
    std::array<double, 17>
    segment_volumes() const;
    std::array<unsigned int, 17>
    segment_cells() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Postprocess
